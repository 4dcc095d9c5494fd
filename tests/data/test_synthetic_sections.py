"""The generated training sections of the learned fault likelihood (seismo3d.data.synthetic_sections): the options
of fault systems, steep folds, small throws and short faults (used by ``python -m seismo3d.training.fault_unet --generator NAME=VALUE``)."""

import numpy as np
import pytest

from seismo3d.data.synthetic_sections import (FaultSectionOptions, _buried_layering, _draw_fault,
                                              synthetic_fault_section)
from seismo3d.errors import InputError


def test_the_new_options_off_by_default_leave_the_sections_unchanged():
    # the shipped network was trained on these sections: the defaults draw nothing more from the generator
    for seed in range(6):
        a = synthetic_fault_section((64, 48), seed=seed)
        b = synthetic_fault_section((64, 48), seed=seed, options=FaultSectionOptions(
            p_fault_system=0.0, p_steep_fold=0.0, p_small_throw=0.0, fault_length_range=(0.3, 1.2),
            p_buried_faults=0.0, p_basal_fault=0.0))
        assert np.array_equal(a.section, b.section) and np.array_equal(a.faults, b.faults)


def test_a_fault_system_shares_one_dip_direction_and_a_dip():
    opt = FaultSectionOptions(p_antithetic=0.0, system_dip_spread=3.0)
    rng = np.random.default_rng(0)
    faults = [_draw_fault(rng, 128, 128, opt, (70.0, -1.0)) for _ in range(200)]
    assert all(f.direction == -1.0 for f in faults)
    dips = np.degrees(np.arctan(1.0 / np.abs([f.cot for f in faults])))
    assert abs(np.median(dips) - 70.0) < 1.0 and np.std(dips) < 4.0
    anti = FaultSectionOptions(p_antithetic=0.25)
    share = np.mean([_draw_fault(rng, 128, 128, anti, (70.0, 1.0)).direction < 0 for _ in range(2000)])
    assert 0.2 < share < 0.3


def test_steep_folds_dip_more_than_the_default_folds():
    def steepest(options):
        out = []
        for seed in range(12):
            clean = synthetic_fault_section((96, 96), seed=seed, options=options).clean
            gx, gz = np.gradient(clean.astype(np.float64))
            # reflector dip from the gradient: 90 deg minus its angle from the trace axis, at strong gradients
            strong = np.hypot(gx, gz) > np.quantile(np.hypot(gx, gz), 0.9)
            out.append(np.degrees(np.arctan2(np.abs(gx[strong]), np.abs(gz[strong]))).mean())
        return np.mean(out)

    flat = FaultSectionOptions(max_faults=1, p_unfaulted=1.0, max_fold_dip=5.0)
    steep = FaultSectionOptions(max_faults=1, p_unfaulted=1.0, max_fold_dip=5.0, p_steep_fold=1.0,
                                steep_fold_dip=60.0)
    assert steepest(steep) > steepest(flat) + 5.0


@pytest.mark.slow
def test_small_throws_are_drawn_in_their_range_with_the_fault_sense_kept():
    opt = FaultSectionOptions(p_small_throw=1.0, small_throw_range=(1.5, 5.0), reverse_fraction=0.3)
    rng = np.random.default_rng(1)
    throws = np.array([_draw_fault(rng, 128, 128, opt).throw for _ in range(2000)])
    assert np.all((np.abs(throws) >= 1.5) & (np.abs(throws) <= 5.0))
    assert 0.25 < np.mean(throws < 0) < 0.35  # reverse faults keep their share
    half = FaultSectionOptions(p_small_throw=0.5)
    small = np.mean([abs(_draw_fault(rng, 128, 128, half).throw) <= 5.0 for _ in range(4000)])
    assert 0.5 + 0.5 * 0.25 - 0.03 < small < 0.5 + 0.5 * 0.25 + 0.03  # half small, a quarter of the rest <= 5 of 20


def test_fault_length_range_sets_the_length_of_the_faults_that_die_out():
    rng = np.random.default_rng(2)
    short = FaultSectionOptions(fault_length_range=(0.1, 0.2))
    lengths = np.array([f.bottom - f.top for f in (_draw_fault(rng, 128, 100, short) for _ in range(500))
                        if f.tapered])
    assert len(lengths) > 200 and lengths.min() >= 10.0 - 1e-9 and lengths.max() <= 20.0 + 1e-9


@pytest.mark.slow
def test_buried_faults_end_at_the_erosion_surface_and_run_to_the_bottom_edge():
    opt = FaultSectionOptions(p_buried_faults=1.0, p_unfaulted=0.0, buried_surface_range=(0.6, 0.6))
    top_labels = bottom_labels = 0
    for seed in range(24):
        buried = synthetic_fault_section((96, 128), seed=seed, options=opt)
        assert not buried.throw[~buried.faults].any()
        top_labels += buried.faults[:, :32].sum()  # the surface waves +-33 samples (3 sd) about sample 77
        bottom_labels += buried.faults[:, -4:].any(axis=1).sum()
    assert top_labels == 0
    assert bottom_labels > 24 * 2  # faults cut the last samples, the data's edge, on more than 2 traces a section
    default = [synthetic_fault_section((96, 128), seed=seed).faults[:, :32].sum() for seed in range(24)]
    assert sum(default) > 1000  # the default sections' faults do reach the top


def test_the_package_above_the_erosion_surface_ignores_the_faults():
    nx, nz, margin = 40, 50, 8
    xs, zs = np.meshgrid(np.arange(nx - 2 * margin, dtype=float), np.arange(nz - 2 * margin, dtype=float),
                         indexing="ij")
    slipped = zs - 3.0 * (xs > 12)  # a vertical fault's hanging wall moved down 3 samples
    a = _buried_layering(np.random.default_rng(4), nx, nz, margin, 20.0, (0.5, 0.5), xs, zs)
    b = _buried_layering(np.random.default_rng(4), nx, nz, margin, 20.0, (0.5, 0.5), xs, slipped)
    rgt_a, above, surface = a
    assert above.any() and (~above).any() and np.array_equal(above, b[1]) and np.array_equal(surface, b[2])
    assert np.array_equal(rgt_a[above], b[0][above])  # unbroken above
    assert not np.array_equal(rgt_a[~above], b[0][~above])  # offset below
    assert np.array_equal(surface, above.sum(axis=1))  # the strong reflector: the first sample below


def test_basal_faults_slip_from_their_upper_tip_past_the_last_sample():
    opt = FaultSectionOptions(p_basal_fault=1.0, basal_top_range=(0.6, 0.8))
    rng = np.random.default_rng(3)
    faults = [_draw_fault(rng, 128, 100, opt) for _ in range(300)]
    assert all(f.tapered and 60.0 - 1e-9 <= f.top <= 80.0 + 1e-9 and f.bottom >= 100.0 for f in faults)
    assert all(abs(float(f.local_throw(99.0))) > 0 for f in faults if f.throw)  # still slipping at the last sample
    labels = [synthetic_fault_section((96, 100), seed=seed, options=FaultSectionOptions(
        p_basal_fault=1.0, basal_top_range=(0.6, 0.8), p_unfaulted=0.0)).faults for seed in range(12)]
    assert all(not f[:, :36].any() for f in labels)  # upper tips at 60-80 samples, moved up <= 20 by reverse faults
    assert sum(f[:, -3:].any(axis=1).sum() for f in labels) > 12 * 3


@pytest.mark.parametrize("kwargs", [dict(p_small_throw=1.5), dict(p_buried_faults=1.5), dict(p_basal_fault=-0.5),
                                    dict(basal_top_range=(0.5, 1.5)),
                                    dict(buried_surface_range=(0.9, 0.2)), dict(small_throw_range=(5.0, 1.0)),
                                    dict(fault_length_range=(0.0, 1.0)), dict(p_fault_system=1.5), dict(p_steep_fold=-0.1), dict(p_antithetic=2.0),
                                    dict(system_dip_spread=50.0), dict(steep_fold_dip=90.0), dict(p_unfaulted=1.2)])
def test_bad_options_are_refused(kwargs):
    with pytest.raises(InputError, match=next(iter(kwargs))):
        FaultSectionOptions(**kwargs)
