"""Progress reporting (seismo3d._progress): one log line per step when standard error is not a terminal."""

import logging

from seismo3d._progress import progress_steps


def test_named_steps_and_item_loops_are_log_lines(caplog):
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        with progress_steps(3, "job") as bar:  # pytest's stderr is not a terminal
            for name in ("read", "trace", "write"):
                bar.start(name)
                bar.advance()
        with progress_steps(100, "loop", unit="inline") as bar:
            for _ in range(100):
                bar.advance()
    lines = [r.getMessage() for r in caplog.records]
    assert lines[:3] == ["job: read (1/3)", "job: trace (2/3)", "job: write (3/3)"]
    loop = [line for line in lines if line.startswith("loop: ")]
    assert 10 <= len(loop) <= 21 and loop[-1] == "loop: 100/100 inline"  # about every 5 %, and the end


def test_disabled_progress_says_nothing(caplog):
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        with progress_steps(3, "quiet", enabled=False) as bar:
            bar.start("step")
            bar.advance()
    assert not caplog.records


def test_status_is_shown_beside_the_count(caplog):
    with caplog.at_level(logging.INFO, logger="seismo3d"):
        with progress_steps(4, "map", unit="frame") as bar:
            for i in range(4):
                bar.advance(status=f"{i + 1}.0 frames/s")
    lines = [r.getMessage() for r in caplog.records]
    assert lines == [f"map: {i}/4 frame, {i}.0 frames/s" for i in range(1, 5)]


def test_each_named_step_is_timed_until_the_next_or_the_end():
    import time

    for enabled in (True, False):  # timed whether reported or not
        with progress_steps(2, "faults", enabled=enabled) as bar:
            bar.start("voting")
            time.sleep(0.02)
            bar.advance()
            bar.start("thinning")  # ends "voting"
            time.sleep(0.01)
        assert list(bar.seconds) == ["voting", "thinning"]  # the last one ends with the block
        assert 0.02 <= bar.seconds["voting"] < 0.5 and 0.01 <= bar.seconds["thinning"] < 0.5
