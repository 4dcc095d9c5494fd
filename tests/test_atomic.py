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


def test_a_ctrl_c_within_deferred_interrupt_is_raised_when_the_block_ends():
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
