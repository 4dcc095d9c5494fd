"""The fault interpretation of arrays (seismo3d.seismic.faults): trace_faults' result and units, dead samples and
clipped amplitudes (clean_traces), bad arrays, sensitivity, and the targets on real sections (the F3 inlines with
faults drawn by a person, Costa Rica against the published OSV faults, the large Penobscot fault, what an interpreter
sees on Teapot and Volve)."""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from seismo3d.data.interpretations import (TEAPOT_TPD_FAULTS, VOLVE_CONTINUOUS_MS, XL1155_LINE, load_real_sections,
                                           opposite_dip_faults, xl1155_coverage)
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError, Seismo3dWarning
from seismo3d.seismic import (FaultInterpretation, evaluate_faults, fault_labels, fault_line_coverage, open_segy,
                              trace_faults)
from seismo3d.seismic.evaluation import plain_semblance, semblance_skeleton
from seismo3d.seismic.faults import FaultTracingOptions
from seismo3d.seismic.faults.evidence import EvidenceOptions
from seismo3d.seismic.faults.surfaces.skins import SkinOptions
from seismo3d.seismic.amplitudes import clean_traces


@pytest.fixture(scope="module")
def section():
    return synthetic_cube((160, 96), n_faults=2, seed=3)


def test_trace_faults_units_and_result(section):
    res = trace_faults(section.cube, sample_interval=2.0, sample_unit="m", progress=False)
    assert isinstance(res, FaultInterpretation)
    assert res.sample_unit == "m" and res.sample_interval == 2.0
    assert res.likelihood.shape == res.strike_deg.shape == res.dip_deg.shape == res.thin.shape == (160, 96)
    assert len(res.throws) == len(res.faults) >= 2
    assert [t.fault_id for t in res.throws] == [f.id for f in res.faults]
    assert np.all(res.thin[res.thin > 0] == res.votes[res.thin > 0])
    assert 0 < res.thresholds[0] <= res.thresholds[1] < 1


def test_a_labelled_cube_gives_the_results_of_its_values_on_its_coordinates(section):
    """A DataArray of one crossline (segysak's dims; a grid of one line is traced as its section) gives the numpy
    run's results, its volumes DataArrays on its own coordinates, its sample interval and unit from its twt."""
    xr = pytest.importorskip("xarray")
    dt = 4.0
    ref = trace_faults(section.cube, sample_interval=dt, sample_unit="ms", progress=False)
    inlines = np.arange(2001, 2001 + 2 * section.cube.shape[0], 2)
    cube = xr.DataArray(section.cube[:, None, :], dims=("iline", "xline", "twt"),
                        coords={"iline": inlines, "xline": [7],
                                "twt": ("twt", 500 + dt * np.arange(section.cube.shape[1]), {"units": "ms"}),
                                "cdp_x": (("iline", "xline"), 1000.0 + 12.5 * inlines[:, None]),
                                "cdp_y": (("iline", "xline"), 5000.0 + 0.0 * inlines[:, None])})
    got = trace_faults(cube, progress=False)
    assert type(got) is FaultInterpretation and got.sample_unit == "ms" and got.sample_interval == dt
    assert len(got.faults) == len(ref.faults) >= 2
    for a, b in zip(got.faults, ref.faults):
        np.testing.assert_array_equal(a.points, b.points)
    for name in ("likelihood", "strike_deg", "dip_deg", "votes", "thin"):
        volume = getattr(got, name)
        assert isinstance(volume, xr.DataArray) and volume.dims == cube.dims and isinstance(volume.data, np.ndarray)
        np.testing.assert_array_equal(volume.values[:, 0, :], getattr(ref, name))
        np.testing.assert_array_equal(volume["cdp_x"].values, cube["cdp_x"].values)
        np.testing.assert_array_equal(volume["twt"].values, cube["twt"].values)
    with pytest.raises(InputError, match="carries its sample interval"):
        trace_faults(cube, sample_interval=dt, progress=False)


@pytest.mark.parametrize("kwargs", [dict(sample_unit="ms"), dict(sample_unit="s", sample_interval=1.0),
                                    dict(sample_interval=4.0), dict(sample_unit="ms", sample_interval=-4.0)])
def test_trace_faults_rejects_bad_units(section, kwargs):
    with pytest.raises(InputError):
        trace_faults(section.cube, progress=False, **kwargs)


@pytest.mark.parametrize("data", [np.zeros((40, 40)), np.full((20, 20, 20), np.nan), np.zeros((4, 5, 6, 7)),
                                  np.array([["a"] * 20] * 20)])
def test_trace_faults_rejects_bad_arrays(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        with pytest.raises(InputError):
            trace_faults(data, progress=False)


def test_clipped_amplitudes_are_reported():
    # an 8-bit export clips the strong peaks and troughs (most Penobscot section samples sit at 0 or 255); the fault
    # job says so, and says nothing for unclipped data
    cube = synthetic_cube((16, 16, 48), seed=0).cube
    hi = float(np.percentile(np.abs(cube), 80))
    with pytest.warns(Seismo3dWarning, match="clipped amplitudes"):
        clean_traces(np.clip(cube, -hi, hi))
    with warnings.catch_warnings():
        warnings.simplefilter("error", Seismo3dWarning)
        clean_traces(cube)


def _runs_by_hand(equal: np.ndarray, length: int) -> np.ndarray:
    """The Trues of each row that lie in a run of at least ``length - 1`` Trues (all of a shorter row's Trues when
    every one is True), one row and one run at a time."""
    out = np.zeros_like(equal)
    rows, m = equal.reshape(-1, equal.shape[-1]), equal.shape[-1]
    need = min(length - 1, m)
    for r, row in enumerate(rows):
        k = 0
        while k < m:
            if not row[k]:
                k += 1
                continue
            start = k
            while k < m and row[k]:
                k += 1
            if k - start >= need:
                out.reshape(-1, m)[r, start:k] = True
    return out


def test_runs_of_equal_samples_are_counted_as_by_hand():
    """The runs of at least n equal samples along each trace (scipy's binary opening by a line of n - 1 differences)
    are the runs counted one by one, on random masks of every density and length (traces shorter than the line
    included)."""
    from seismo3d.seismic.amplitudes import _runs

    rng = np.random.default_rng(0)
    for _ in range(50):
        m = int(rng.integers(1, 40))
        equal = rng.random((int(rng.integers(1, 5)), int(rng.integers(1, 4)), m)) < rng.uniform(0.2, 0.95)
        for length in (2, 5, 16, 60):
            assert np.array_equal(_runs(equal, length), _runs_by_hand(equal, length))
            assert np.array_equal(_runs(equal[:, 0], length), _runs_by_hand(equal[:, 0], length))


def test_quantised_runs_are_not_dead_but_fill_values_are():
    # In an 8-bit export, slowly varying amplitudes repeat the same value for a few samples; a run of five 107s on the
    # Penobscot fault at crossline 56 (inlines 1-2) counted as a dead zone and blanked the fault's likelihood on
    # inlines 0-5. Dead samples are runs at a fill value: 0, or a value that fills a whole trace or a long run (the
    # image's grey 127 in a muted top).
    section = np.round(127.5 + 100 * synthetic_cube((40, 96), n_faults=0, seed=2).cube / 3).clip(0, 255)
    section[:, :20] = 127  # a muted top in the image's grey: a fill value
    section[5, 60:65] = 107  # a short run of a live value (quantisation)
    section[8, 50:55] = 127  # a short run of the fill value: a gap
    section[30] = 99  # a dead trace
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        dead = clean_traces(section).dead
    assert dead[:, :20].all() and dead[8, 50:55].all() and dead[30].all()
    assert not dead[5, 55:70].any()
    live = np.ones_like(dead)
    live[:, :20] = live[8, 50:55] = live[30] = False
    assert not dead[live].any()


@pytest.mark.slow
def test_penobscot_fault_at_crossline_56_is_not_blanked(penobscot):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        dead = clean_traces(penobscot.cube).dead
    assert not dead[:, 50:62, 600:720].any()
    assert dead[:, 10:500, :40].mean() > 0.5  # the muted top (grey 127) is still dead


# --------------------------------------------------------------------------------------------------------------------
# real data: the targets (the same defaults on every input)


def _read_f32be(data_dir, name, shape):
    return np.fromfile(Path(data_dir) / "seismic" / name, ">f4").reshape(shape).astype(np.float32)


@pytest.mark.slow
def test_costarica_crf_against_the_published_osv_faults(data_dir):
    """Our faults on the Costa Rica section against X. Wu's optimal-surface-voting result (a reference from another
    algorithm, thresholded at 0.3 as published), tolerance 3 samples: recall >= 0.70 at precision >= 0.80.
    Before the voting and skins: precision 0.79, recall 0.34. With the scan likelihood: the default learned one
    finds fewer of OSV's dense faults (precision 0.93, recall 0.27: README, "The learned fault likelihood")."""
    section = _read_f32be(data_dir, "sections/costarica_crf.f32be", (500, 180))
    reference = _read_f32be(data_dir, "references/costarica_crf_osv_fvt.f32be", (500, 180)) > 0.3
    res = trace_faults(section, progress=False, options=FaultTracingOptions(likelihood="scan"))
    scores = evaluate_faults(fault_labels(res.faults, section.shape) > 0, reference, tolerance=3)
    print(f"crf: precision {scores.precision:.3f} recall {scores.recall:.3f}, {len(res.faults)} faults")
    assert scores.precision >= 0.80 and scores.recall >= 0.70, scores


@pytest.fixture(scope="module")
def xl1155_traced(data_dir):
    """Penobscot crossline 1155 (601 traces x 1501 samples at 4 ms), its sample times and its faults traced by the
    defaults, once for the two tests that read them."""
    with open_segy(Path(data_dir) / "seismic" / "penobscot_xl1155.sgy") as cube:
        section = cube.read()[:, 0, :]
        samples = np.asarray(cube.samples)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # its muted top-left corner is reported
        res = trace_faults(section, sample_interval=4.0, sample_unit="ms", progress=False)
    return section, samples, res


@pytest.mark.slow
def test_penobscot_xl1155_large_normal_fault_is_one_fault(xl1155_traced):
    """The large normal fault of crossline 1155 (any interpreter sees it; before this work: not found, 0 faults) is
    traced by the defaults as one fault along >= 70 % of its length between 1000 and 2400 ms, within 10 traces of
    the line through its two ends."""
    section, samples, res = xl1155_traced
    assert samples[1] - samples[0] == 4.0 and section.shape == (601, 1501)
    labels = fault_labels(res.faults, section.shape)
    main = xl1155_coverage(labels)
    coverage, fid, whole = main.one_fault, main.fault_id, xl1155_coverage(labels, (900.0, 2550.0)).one_fault
    print(f"xl1155: fault {fid} covers {coverage:.0%} of 1000-2400 ms, {whole:.0%} of 900-2550 ms, "
          f"{len(res.faults)} faults")
    assert coverage >= 0.70, (coverage, fid)
    assert whole >= 0.70, whole  # issue 35 asks 80 %: measured 74 %, the fault's top (900-1250 ms) a fault of its own
    # no fault of the opposite dip along its upper part (900-1700 ms; before issue 35 one was drawn there)
    assert opposite_dip_faults(res.faults, XL1155_LINE) == []
    # its throw profile (issue 54) against the offsets read by hand (traces of the section, t0 = 0 ms, 4 ms samples):
    # at 2000 ms the strong trough lies at 2011-2012 ms in the hanging wall next to the fault (traces 262-266) and at
    # 1950-1955 ms in the footwall beyond its two strands (traces 280-284, bending up into it): 57-62 ms, normal; at
    # 2500 ms, the crest of an anticline, the trough at 2449-2454 ms (traces 222-226) and 2463-2469 ms (236-240): under
    # 15 ms. Near 1500-1600 ms the strongest peak of each side where it meets the fault: 1628 ms in the hanging
    # wall (traces 308-314, flat there, bending down from 1608 ms at trace 296) and 1520 ms in the footwall (1524 ms
    # at trace 330, rising into the fault from 1536 ms at trace 338): 104-108 ms, normal; the profile carries each
    # side to the fault's centre along the dip read 9 traces out (7-11 ms more): within 3 samples. Before issue 54
    # the whole fault had one throw, 1.2 ms, read between its strands; until 2026-11-27, 51 ms near 1500 ms (its
    # search bound, 80 ms, short of the offset: a cycle skip).
    assert samples[0] == 0.0
    fault = next(f for f in res.faults if f.id == fid)
    throw = next(t for t in res.throws if t.fault_id == fid)
    ms = fault.points[:, 1] * 4.0
    at = {level: np.median(throw.throw[np.abs(ms - level) <= 40.0]) * 4.0 for level in (1500.0, 2000.0, 2500.0)}
    gain = np.median((throw.correlation - throw.correlation_unshifted)[np.abs(ms - 2000.0) <= 40.0])
    print(f"xl1155 fault {fid} throw: {at[1500.0]:.1f} ms at 1500 ms, {at[2000.0]:.1f} ms at 2000 ms (correlation "
          f"gain {gain:.2f}), {at[2500.0]:.1f} ms at 2500 ms")
    assert 92.0 <= at[1500.0] <= 120.0  # within 3 samples of the hand reading; measured 116.2
    assert 49.0 <= at[2000.0] <= 70.0 and gain > 0.2  # within 2 samples of the hand reading; measured 57.5, 0.45
    assert abs(at[2500.0]) <= 15.0  # measured 1.4


@pytest.mark.slow
def test_faults_along_crossing_events_are_not_clear_displacements(xl1155_traced):
    """Faults an interpreter rejects (issue 54), traced where dipping events cross (migration swings, a crosshatch)
    and kept as clear and likely though their sides look alike at no shift: Penobscot crossline 1155's two at
    4300-5400 ms (traces 102-230; throws 4.84 and -3.71 samples, side correlations 0.37 and 0.20, the reflectors'
    half period about 6 samples there). Their throws are under the half period (``clear_half_periods``); the large
    fault of crossline 1155 (13.9 samples, correlation 0.41, half period about 5) stays (test above). The same claim
    on the 18 Penobscot inlines' crosshatch (crosslines 312-383, samples 838-1033: throw 5.07, correlation 0.20, half
    period 5.31; about 2 min to trace) is asserted by ``python benchmarks/horizons.py --only traced_faults --check``,
    which traces those inlines' faults with the same defaults (issue 58: a claim over 20 s leaves the suite)."""
    res = xl1155_traced[2]
    deep = [f.id for f in res.faults if 100 <= np.median(f.points[:, 0]) <= 235
            and 1075 <= np.median(f.points[:, 1]) <= 1355]
    print("xl1155:", len(res.faults), "faults; along the swings at 4300-5400 ms:", deep)
    assert deep == []


def _prf(scores) -> tuple:
    """(precision, recall, F1) of a FaultScores."""
    return scores.precision, scores.recall, scores.f1


@pytest.mark.slow
def test_f3_inlines_against_the_faults_a_person_drew(data_dir):
    """The five F3 inlines with faults drawn by a person (tolerance 3 samples), the defaults: mean precision >= 0.60
    (issue 54's target) and mean F1 >= 0.49 (measured 0.638 / 0.418 / 0.500, as ``tools/dev_fault_scores.py`` scores
    the command; issue 54's F1 target 0.55 is not reached), and on every inline an F1 above both peers':
    the plain 1-semblance skeleton at its single best threshold over the five inlines (computed here, F1 0.08-0.24)
    and FaultNet (Dou et al. 2022): its released weights' F1 per inline as ``python benchmarks/faults.py --only f3``
    measures them (0.323, 0.289, 0.141, 0.158, 0.176; 80 CPU s, too long for the suite; the published figures
    0.33, 0.28, 0.15, 0.14, 0.19)."""
    from seismo3d.data import load_f3_fault_sections

    data = load_f3_fault_sections()
    ours = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)  # the 8-bit rendering's clipped amplitudes
        for section, drawn in zip(data.sections, data.faults):
            res = trace_faults(section, sample_interval=4.0, sample_unit="ms", progress=False)
            ours.append(_prf(evaluate_faults(fault_labels(res.faults, section.shape) > 0, drawn, tolerance=3.0)))
    skeleton = None  # the quantile of 1 - semblance with the best mean F1 over the five inlines
    discontinuity = [1.0 - plain_semblance(section) for section in data.sections]
    for q in (0.95, 0.97, 0.98, 0.985, 0.99, 0.993):
        scores = [_prf(evaluate_faults(semblance_skeleton(section, float(np.quantile(d, q))), drawn, tolerance=3.0))
                  for section, d, drawn in zip(data.sections, discontinuity, data.faults)]
        if skeleton is None or np.mean([s[2] for s in scores]) > np.mean([s[2] for s in skeleton]):
            skeleton = scores
    faultnet = (0.323, 0.289, 0.141, 0.158, 0.176)  # measured by benchmarks/faults.py --only f3 (docstring)
    precision, recall, f1 = (float(np.mean([s[i] for s in ours])) for i in range(3))
    print(f"F3: precision {precision:.3f} recall {recall:.3f} F1 {f1:.3f}; per inline "
          + ", ".join(f"{s[2]:.3f} (skeleton {k[2]:.3f})" for s, k in zip(ours, skeleton)))
    assert precision >= 0.60 and f1 >= 0.49, (precision, recall, f1)
    for inline, s, k, fn in zip(data.inlines, ours, skeleton, faultnet):
        assert s[2] > max(k[2], fn), (inline, s, k, fn)


@pytest.mark.slow
def test_volve_line_has_no_fault_through_its_continuous_reflectors(data_dir):
    """No fault of the defaults crosses the continuous reflectors of the Volve arbitrary line at 2300-2500 ms (before
    issue 35: several did)."""
    section, dt = load_real_sections()["volve_fullstack_twt_arbline"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", Seismo3dWarning)
        res = trace_faults(section, sample_interval=dt, sample_unit="ms", progress=False)
    k0, k1 = (int(round(t / dt)) - 1 for t in VOLVE_CONTINUOUS_MS)  # samples at 4, 8, ... ms
    crossing = [f.id for f in res.faults if np.any((f.points[:, 1] >= k0) & (f.points[:, 1] <= k1))]
    assert res.faults and not crossing, crossing


@pytest.mark.slow
def test_teapot_tpd_what_an_interpreter_sees(data_dir):
    """Teapot tpd, where an interpreter sees three faults: at most 8 faults (issue 35; the scan: 28); the one dipping
    from trace 115 at sample 20 to 145 at 280 is traced (88 % of it within 8 traces), the near-vertical one at traces
    210-220 is one fault along 57 % of it. Not reached: the fault near trace 20 below sample 240 (43 %, the issue
    asks it traced)."""
    section, _ = load_real_sections()["teapot_tpd"]
    res = trace_faults(section, progress=False)
    labels = fault_labels(res.faults, section.shape)
    coverage = {name: fault_line_coverage(labels, line, tolerance=8) for name, line in TEAPOT_TPD_FAULTS.items()}
    print("teapot_tpd:", len(res.faults), {name: round(c.covered, 2) for name, c in coverage.items()})
    assert len(res.faults) <= 8, len(res.faults)
    assert coverage["trace 115 at sample 20 to 145 at 280"].covered >= 0.8
    assert coverage["near-vertical at traces 210-220"].one_fault >= 0.5
    assert coverage["near trace 20 below sample 240"].covered >= 0.4


@pytest.mark.slow
def test_sensitivity_gives_more_or_fewer_faults(section):
    low = trace_faults(section.cube, sensitivity=0.1, progress=False)
    mid = trace_faults(section.cube, progress=False)
    high = trace_faults(section.cube, sensitivity=0.9, progress=False)
    assert low.thresholds[1] > mid.thresholds[1] > high.thresholds[1]
    n = [int(np.count_nonzero(fault_labels(r.faults, section.cube.shape))) for r in (low, mid, high)]
    assert n[0] <= n[1] <= n[2] and n[0] < n[2], n
    with pytest.raises(InputError, match="sensitivity"):
        trace_faults(section.cube, sensitivity=1.5, progress=False)


# --- faults an interpreter rejects: one id over branches of opposite dip, a flexure (issue 54) -----------------------

def _layers(shift, *, n_traces=192, n_samples=160, seed=0, noise=0.05):
    """Flat layers (random reflectivity, Ricker 0.15 cycles/sample) lying ``shift(x, z)`` samples deeper at trace x,
    sample z; (n_traces, n_samples) float32."""
    from seismo3d.data.synthetic import ricker

    rng = np.random.default_rng(seed)
    pad = 40
    reflectivity = rng.standard_normal(n_samples + 2 * pad) * (rng.random(n_samples + 2 * pad) < 0.35)
    trace = np.convolve(reflectivity, ricker(0.15), mode="same")
    z = np.arange(n_samples, dtype=np.float64)
    out = np.stack([np.interp(z - shift(x, z) + pad, np.arange(trace.size), trace) for x in range(n_traces)])
    out += noise * out.std() * rng.standard_normal(out.shape)
    return out.astype(np.float32)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_an_inverted_v_of_opposite_dips_is_two_faults_each_with_its_throw(seed):
    """A horst under an inverted V: two normal faults dipping 80 degrees away from an apex at trace 96, sample 30,
    throwing 4 samples. As one fault (``split_angle=None``) its zone spans the horst, and the two hanging walls it
    compares lie at the same depth: they match with no shift, so the evidence drops it as reflectors continuing
    across (``EvidenceOptions.unbroken_correlation``; a throw of -0.01 before that rule). Split by their dips, each
    fault reads its own throw (measured 3.92-4.03)."""
    run = 1.0 / np.tan(np.radians(80.0))
    section = _layers(lambda x, z: np.where((z >= 30) & (np.abs(x - 96) <= run * (z - 30)), 0.0, 4.0), seed=seed)
    one = trace_faults(section, progress=False, options=FaultTracingOptions(skins=SkinOptions(split_angle=None)))
    assert one.faults == []
    kept = trace_faults(section, progress=False, options=FaultTracingOptions(
        skins=SkinOptions(split_angle=None), evidence=EvidenceOptions(unbroken_correlation=None)))
    assert len(kept.faults) == 1 and abs(kept.evidence[0].median_throw) < 1.0
    res = trace_faults(section, progress=False)
    assert len(res.faults) == 2
    for f, e in zip(res.faults, res.evidence):
        below = f.points[f.points[:, 1] >= 50]
        assert np.all(below[:, 0] <= 97) or np.all(below[:, 0] >= 95), f.id  # on one branch only
        assert abs(abs(e.median_throw) - 4.0) <= 0.3, e


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1])
def test_a_flexure_is_no_fault_and_a_small_fault_is_kept(seed):
    """Layers dipping 0.1 sample per trace, bent down by 4-6 samples over 6-8 traces (a monocline, no fault): the
    network calls the bend a fault (mean probability 0.89-0.97) and its throw, read farther out, is 3.1-3.9 samples,
    but the step at it is under a tenth of that: no fault. The same layers offset by 2 or 3 samples: one fault,
    its throw and step within 0.1 sample. Not reached: a broader bend (8 samples over 12 traces) whose sides match
    less closely at the throw (correlation 0.79-0.83) is still traced."""
    for relief, half_width in ((6.0, 4.0), (4.0, 3.0)):
        section = _layers(lambda x, z: 0.1 * x + relief * 0.5 * (1.0 + np.tanh((x - 96) / half_width)), seed=seed)
        res = trace_faults(section, progress=False)
        assert res.faults == [], [(e.median_throw, e.step, e.correlation) for e in res.evidence]
    for throw in (2.0, 3.0):
        res = trace_faults(_layers(lambda x, z: 0.1 * x + throw * (x >= 96), seed=seed), progress=False)
        assert len(res.faults) == 1, len(res.faults)
        e = res.evidence[0]
        assert abs(abs(e.median_throw) - throw) <= 0.1 and abs(abs(e.step) - throw) <= 0.15, e


def test_the_stores_of_another_run_are_told_from_what_they_record(tmp_path):
    """A finished likelihood is this run's when it records the same input, shape and likelihood options (another
    sensitivity reuses it, another network does not); the surfaces go with that likelihood and the run's options."""
    import dataclasses

    import zarr

    from seismo3d.seismic.blocks.options import ChunkOptions
    from seismo3d.seismic.blocks.stores import StoreRun
    from seismo3d.seismic.faults.pipeline import LIKELIHOOD_STORE, SURFACES_STORE, stores_of_another_run

    opt, shape = FaultTracingOptions(), (4, 4, 4)
    as_json = lambda o: json.loads(json.dumps(dataclasses.asdict(o), default=str))  # noqa: E731
    for name, manifest, attrs in ((LIKELIHOOD_STORE, {"options": as_json(opt.learned)}, {"id": "L1"}),
                                  (SURFACES_STORE, {"options": as_json(opt), "likelihood_id": "L1"}, {})):
        run = StoreRun(tmp_path / name, ChunkOptions(), progress=False)
        run.start_output(dict(manifest, shape=list(shape), plan={}), shape, 32, ())
        run.finish(attrs)
        zarr.open_group(str(tmp_path / name), mode="r+").attrs["source"] = "a"

    def another(source="a", shape=shape, options=opt):
        return [p.name for p in stores_of_another_run(tmp_path, source, shape, options)]

    assert another() == []
    assert another(options=dataclasses.replace(opt, sensitivity=0.7)) == [SURFACES_STORE]
    network = dataclasses.replace(opt, learned=dataclasses.replace(opt.learned, adapted="model/network.onnx"))
    assert another(options=network) == [LIKELIHOOD_STORE, SURFACES_STORE]
    assert another(source="b") == another(shape=(4, 4, 5)) == [LIKELIHOOD_STORE, SURFACES_STORE]
    zarr.open_group(str(tmp_path / LIKELIHOOD_STORE), mode="r+").attrs["id"] = "L2"  # a likelihood written since
    assert another() == [SURFACES_STORE]
