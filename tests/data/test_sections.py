"""Loaders of real seismic data with people's interpretation (seismo3d.data.sections): the Parihaka cube."""

import pathlib

import numpy as np
import pytest

from seismo3d.data import load_parihaka_timeslices
from seismo3d.errors import DataNotFoundError

PARIHAKA = "seismic/parihaka_timeslices/parihaka_timeslices_cols174_302.npz"


@pytest.mark.slow  # two reads of the 11 MB file: 15 s at a load of 15 on 2 cores
def test_parihaka_cube_as_the_fault_command_reads_it(data_dir):
    """The cube is the file's slices turned to (inline = row, crossline = column, sample = slice) and centred as
    tools/parihaka_dev_scores.py centres them (value - 127.5); the faults are label 1 on the same grid; the fault
    window is the 128 slices with the most fault labels, found here as that tool finds it."""
    with np.load(pathlib.Path(data_dir) / PARIHAKA) as z:
        seismic, labels = z["seismic"], z["labels"]
    parihaka = load_parihaka_timeslices()
    assert parihaka.cube.shape == (256, 128, 591) and parihaka.cube.dtype == np.float32
    np.testing.assert_array_equal(parihaka.cube, seismic.transpose(1, 2, 0).astype(np.float32) - 127.5)
    np.testing.assert_array_equal(parihaka.faults, (labels == 1).transpose(1, 2, 0))
    np.testing.assert_array_equal(parihaka.labelled, ~(labels == 255).all(axis=(1, 2)))
    assert parihaka.labelled.sum() == 391 and not parihaka.faults[:, :, ~parihaka.labelled].any()
    np.testing.assert_array_equal(parihaka.slices, np.arange(70, 661))
    k0 = int(np.argmax(np.convolve((labels == 1).sum(axis=(1, 2)), np.ones(128), "valid")))  # the tool's window
    assert parihaka.fault_window == slice(k0, k0 + 128) == slice(45, 173)
    for array in (parihaka.cube, parihaka.faults, parihaka.labelled, parihaka.slices):
        assert not array.flags.writeable


def test_parihaka_without_the_data_folder_says_where_to_point(tmp_path, monkeypatch):
    """A derived file, not downloaded: without the data folder the loader says so in one line naming the
    variable."""
    monkeypatch.setenv("SEISMO3D_DATA_DIR", str(tmp_path))
    monkeypatch.setenv("SEISMO3D_CACHE_DIR", str(tmp_path / "cache"))
    with pytest.raises(DataNotFoundError, match="SEISMO3D_DATA_DIR") as caught:
        load_parihaka_timeslices()
    assert "\n" not in str(caught.value)
