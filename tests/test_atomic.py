"""Atomic outputs (seismo3d._atomic): a staged output folder's files and folders moved in together."""

import pytest

from seismo3d._atomic import StagedFolder


def test_staged_folder_replaces_an_earlier_folder_whole(tmp_path):
    """A folder of files among the staged outputs (the faults job's TSurf file per fault) replaces the earlier run's
    folder of that name whole: none of the earlier files is left beside the new ones; on an error, the earlier
    folder is kept as it was."""
    out = tmp_path / "out"
    for faults in (["fault_1.ts", "fault_2.ts", "fault_3.ts"], ["fault_1.ts"]):
        with StagedFolder(out) as stage:
            (stage.path / "surfaces").mkdir()
            for name in faults:
                (stage.path / "surfaces" / name).write_text(f"{len(faults)}\n")
            (stage.path / "run.json").write_text("{}\n")
    assert sorted(p.name for p in out.iterdir()) == ["run.json", "surfaces"]
    assert [(p.name, p.read_text()) for p in (out / "surfaces").iterdir()] == [("fault_1.ts", "1\n")]
    with pytest.raises(RuntimeError), StagedFolder(out) as stage:
        (stage.path / "surfaces").mkdir()
        raise RuntimeError("a writer failed")
    assert sorted(p.name for p in out.iterdir()) == ["run.json", "surfaces"]
    assert [p.name for p in (out / "surfaces").iterdir()] == ["fault_1.ts"]


def test_a_ctrl_c_within_deferred_interrupt_is_raised_when_the_block_ends(default_sigint_handler):
    import os
    import signal

    from seismo3d._atomic import deferred_interrupt

    done = []
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt():
            os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C in the middle of the block
            done.append("the rest of the block")
    assert done == ["the rest of the block"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # Ctrl-C raises again at once
    with deferred_interrupt():  # no Ctrl-C: nothing raised
        done.append("again")
    assert done[-1] == "again"


def test_a_run_killed_outright_leaves_a_staging_folder_the_next_run_of_its_owner_removes(tmp_path):
    """``kill -9`` gives a run no clean-up: its ``.staged-*.tmp`` stays in the output folder. The next run of the same
    owner into that folder removes it, and only it: a folder of that name without the run's record (the user's),
    one of another owner, and one whose process still runs are left alone. The record is not among the outputs."""
    import json
    import os
    import signal
    import subprocess
    import sys

    from seismo3d._atomic import STAGING_RECORD

    out = tmp_path / "out"
    child = subprocess.Popen([sys.executable, "-c", (
        "import sys, time\nfrom seismo3d._atomic import StagedFolder\n"
        f"with StagedFolder({str(out)!r}, owner='seismo3d faults') as stage:\n"
        "    (stage.path / 'fault_points.csv').write_text('half')\n    print('staged', flush=True)\n"
        "    time.sleep(60)\n")], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "staged"
    os.kill(child.pid, signal.SIGKILL)
    child.wait()
    stale = list(out.glob(".staged-*.tmp"))
    assert len(stale) == 1 and (stale[0] / "fault_points.csv").exists()
    user = out / ".staged-mine.tmp"  # the user's: no record
    user.mkdir()
    other = out / ".staged-other.tmp"  # another owner's
    other.mkdir()
    (other / STAGING_RECORD).write_text(json.dumps(dict(json.loads((stale[0] / STAGING_RECORD).read_text()),
                                                        owner="seismo3d map")))
    with StagedFolder(out, owner="seismo3d faults") as running:  # a run still going: its folder is kept
        with StagedFolder(out, owner="seismo3d faults") as stage:
            assert not stale[0].exists()
            assert running.path.exists() and user.exists() and other.exists()
            (stage.path / "fault_points.csv").write_text("whole")
    assert sorted(p.name for p in out.iterdir()) == sorted([".staged-mine.tmp", ".staged-other.tmp",
                                                            "fault_points.csv"])
    assert (out / "fault_points.csv").read_text() == "whole"
