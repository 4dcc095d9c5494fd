"""The saturation level (a likelihood above it counts as saturated) is a field of each options class that counts
saturated samples, 0.9 by default, and a value outside (0, 1) is refused with the field's name."""

from __future__ import annotations

import pytest

from seismo3d.errors import InputError
from seismo3d.seismic.faults import FaultScanOptions, FaultTracingOptions, LearnedOptions
from seismo3d.seismic.faults.steps import check_saturation


@pytest.mark.parametrize("cls", [FaultTracingOptions, FaultScanOptions, LearnedOptions])
def test_the_saturation_level_is_an_option_in_0_1(cls):
    assert cls().saturation_level == 0.9
    for bad in (0.0, 1.0, -0.5):
        with pytest.raises(InputError, match=r"saturation_level must be a (likelihood|probability) in \(0, 1\)"):
            cls(saturation_level=bad)


def test_the_refusal_names_the_level_it_counted_with():
    with pytest.raises(Exception, match="the fault likelihood is above 0.8 at 97% of the samples"):
        check_saturation(97, 100, FaultTracingOptions(saturation_level=0.8))
    assert check_saturation(95, 100, FaultTracingOptions()) == 0.95  # at max_saturated: kept
