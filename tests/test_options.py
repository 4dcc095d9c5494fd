"""Options objects (seismo3d._options): keyword overrides of a frozen dataclass, checked."""

import dataclasses

import pytest

from seismo3d._options import resolve_options
from seismo3d.errors import InputError
from seismo3d.registration import ICPOptions


def test_overrides_replace_fields_and_leave_the_options_alone():
    base = ICPOptions(max_iterations=20)
    out = resolve_options(ICPOptions, base, {"tolerance": 1e-6}, "icp")
    assert out.max_iterations == 20 and out.tolerance == 1e-6
    assert base.tolerance == ICPOptions().tolerance  # frozen: a new object
    assert resolve_options(ICPOptions, None, {}, "icp") == ICPOptions()
    with pytest.raises(dataclasses.FrozenInstanceError):
        base.tolerance = 1.0


def test_unknown_names_and_wrong_types_are_clear_errors():
    with pytest.raises(InputError, match="icp\\(\\) got unknown keyword argument\\(s\\) max_iter; the options of "
                                         "ICPOptions are max_distance, voxel_size, max_iterations"):
        resolve_options(ICPOptions, None, {"max_iter": 5}, "icp")
    with pytest.raises(InputError, match="must be an instance of ICPOptions"):
        resolve_options(ICPOptions, {"max_iterations": 5}, {}, "icp")
    with pytest.raises(InputError, match="max_iterations must be an int >= 1"):
        resolve_options(ICPOptions, None, {"max_iterations": 0}, "icp")
