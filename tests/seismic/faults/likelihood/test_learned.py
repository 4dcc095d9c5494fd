"""The learned fault likelihood: the shipped network, its ONNX inference, its orientation, and its faults on
generated sections and cubes the training never saw."""

import hashlib
import io
import json
import warnings
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.data.degradations import add_noise, chaotic_interval, clip_and_quantise
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.data.synthetic_sections import synthetic_fault_section
from seismo3d.errors import InputError, Seismo3dError
from seismo3d.seismic import evaluate_faults, fault_labels, trace_faults
from seismo3d.seismic.faults import FaultTracingOptions
from seismo3d.seismic.faults.likelihood import learned
from seismo3d.seismic.faults.likelihood.learned import (
    INT8_SHA256, LearnedOptions, NETWORKS, WEIGHTS_SHA256, fault_probability, learned_fault_likelihood,
    load_fault_network,
)
from seismo3d.seismic.faults.likelihood.network import RECEPTIVE_HALF, FaultNetwork, normalise_section, unet_forward
from seismo3d.training.export_onnx import onnx_model

CHECK = Path(__file__).parents[2] / "data" / "fault_unet_check.npz"  # tests/seismic/data
LEARNED = FaultTracingOptions(likelihood="learned")
TEST_SEED = 31_000_000  # generator seeds the training never draws (it draws seed 0 * 1_000_003 + i, i < 20_000)


def test_shipped_network_has_the_recorded_sha256_and_is_the_export_of_the_trained_weights():
    files = resources.files("seismo3d.seismic.faults.likelihood")
    raw = files.joinpath("fault_unet.onnx").read_bytes()
    assert hashlib.sha256(raw).hexdigest() == WEIGHTS_SHA256
    assert len(raw) <= 10 * 2 ** 20  # ships in <= 10 MB
    record = json.loads(files.joinpath("fault_unet.json").read_text())
    npz = files.joinpath("fault_unet.npz").read_bytes()
    assert hashlib.sha256(npz).hexdigest() == record["weights_sha256"]
    pytest.importorskip("onnx")  # the test extra has it
    with np.load(io.BytesIO(npz)) as weights:
        assert onnx_model({k: weights[k] for k in weights.files}) == raw  # a deterministic export, byte for byte


@pytest.mark.parametrize("network", ["int8", "float"])
def test_damaged_weights_are_refused(monkeypatch, network):
    load_fault_network.cache_clear()
    monkeypatch.setitem(learned.NETWORKS, network, (NETWORKS[network][0], "1" * 64))
    try:
        with pytest.raises(Seismo3dError, match="reinstall seismo3d"):
            load_fault_network(network)
    finally:
        load_fault_network.cache_clear()


def test_auto_runs_the_int8_network_on_cubes_and_the_float_one_on_sections():
    auto = LearnedOptions()
    assert auto.network == "auto" and auto.model(3) == "int8" and auto.model(2) == "float"
    assert LearnedOptions(network="float").model(3) == "float" and LearnedOptions(network="int8").model(2) == "int8"
    section = synthetic_fault_section((64, 128), seed=TEST_SEED).section
    float_run = fault_probability(section, options=LearnedOptions(network="float"))
    assert np.array_equal(fault_probability(section), float_run)


def test_an_unknown_network_is_refused():
    with pytest.raises(InputError, match="network"):
        LearnedOptions(network="int4")
    with pytest.raises(InputError, match="network"):
        load_fault_network("fp16")
    with pytest.raises(InputError, match="FaultNetwork"):  # trained weights: FaultNetwork(onnx_model(weights))
        unet_forward(np.zeros((1, 8, 8), np.float32), {"head.weight": np.zeros((1, 12, 1, 1), np.float32)})


def test_onnx_inference_equals_the_stored_pytorch_output():
    check = np.load(CHECK)
    got = unet_forward(check["section"][None], load_fault_network("float"))[0]
    assert got.shape == check["probability"].shape
    assert np.abs(got - check["probability"]).max() <= 1e-5


def test_shipped_int8_network_has_the_recorded_sha256_and_is_the_quantisation_of_the_float_one():
    files = resources.files("seismo3d.seismic.faults.likelihood")
    raw = files.joinpath("fault_unet_int8.onnx").read_bytes()
    assert hashlib.sha256(raw).hexdigest() == INT8_SHA256 == NETWORKS["int8"][1]
    record = json.loads(files.joinpath("fault_unet_int8.json").read_text())
    assert record["sha256"] == INT8_SHA256 and record["float_sha256"] == WEIGHTS_SHA256
    assert len(raw) <= 2 ** 20


@pytest.mark.slow  # 5 s: generates 80 sections and quantises
def test_the_quantisation_script_reproduces_the_shipped_int8_network():
    pytest.importorskip("onnx")
    from seismo3d.training.quantize_onnx import QuantiseOptions, calibration_sections, quantise_fault_network

    files = resources.files("seismo3d.seismic.faults.likelihood")
    npz = files.joinpath("fault_unet.npz").read_bytes()
    assert hashlib.sha256(npz).hexdigest() == json.loads(files.joinpath("fault_unet_int8.json").read_text())[
        "weights_sha256"]
    with np.load(io.BytesIO(npz)) as weights:
        made = quantise_fault_network(onnx_model({k: weights[k] for k in weights.files}, channels_last=True))
    if hashlib.sha256(made).hexdigest() != INT8_SHA256:  # byte for byte on the machine that made it (ORT 1.32);
        # elsewhere the float network's last bits move the calibration ranges a little: the same probabilities
        opt = QuantiseOptions()
        x = calibration_sections(opt.n_check, opt.shape, seed=opt.seed + opt.n_sections)[:, 0]
        ours = unet_forward(x, learned.FaultNetwork(made))
        shipped = unet_forward(x, load_fault_network("int8"))
        assert np.abs(ours - shipped).mean() <= 1e-3


# the int8 network's probability against the float one's on generated cubes (48 x 48 x 96, seeds 3-5, every grid and
# both directions): mean absolute difference 0.00056-0.00063, 99th percentile 0.011-0.013, max 0.08-0.09, 99.95 % of
# the samples on the same side of 0.5; the tolerances are twice the largest
TOLERANCE_MEAN, TOLERANCE_P99 = 0.0013, 0.026


@pytest.mark.slow  # 6 s: the network on every grid and both directions, twice
def test_the_int8_probability_is_within_its_measured_tolerance_of_the_float_one():
    # a generated faulted cube the calibration never saw (synthetic_cube, not the calibration's sections)
    cube = synthetic_cube((48, 48, 96), n_faults=2, seed=3, noise=0.1).cube
    a = fault_probability(cube, options=LearnedOptions(network="float"))
    b = fault_probability(cube, options=LearnedOptions(network="int8"))
    d = np.abs(a - b)
    assert d.mean() <= TOLERANCE_MEAN and np.quantile(d, 0.99) <= TOLERANCE_P99
    assert ((a > 0.5) == (b > 0.5)).mean() >= 0.999
    assert a.max() > 0.9 and b.max() > 0.9  # the faults are there in both


@pytest.mark.parametrize("network", ["int8", "float"])
def test_receptive_field_is_within_its_stated_half_width(network):
    weights = load_fault_network(network)
    x = np.zeros((1, 256, 256), np.float32)
    base = unet_forward(x, weights)
    x[0, 128, 128] = 5.0
    changed = np.abs(unet_forward(x, weights) - base)[0] > 0
    rows, cols = np.nonzero(changed)
    assert max(128 - rows.min(), rows.max() - 128, 128 - cols.min(), cols.max() - 128) <= RECEPTIVE_HALF


@pytest.mark.parametrize("network", ["int8", "float"])
def test_a_batch_run_in_parts_on_threads_gives_the_same_bits(network):
    # FaultNetwork(calls=2), as cubes run it: a session of one thread, each call's sections in two parts at once
    sections = np.stack([normalise_section(synthetic_fault_section(shape=(96, 104), seed=TEST_SEED + k).section)
                         for k in range(5)]).astype(np.float32)
    one = unet_forward(sections, load_fault_network(network))
    parts = load_fault_network(network, 2)
    assert parts is not load_fault_network(network) and parts._calls == 2
    assert np.array_equal(unet_forward(sections, parts), one)
    assert np.array_equal(unet_forward(sections[:1], parts), one[:1])  # one section: one call


def test_input_scaling_of_a_stack_is_per_section():
    rng = np.random.default_rng(0)
    a = rng.normal(3.0, 2.0, (2, 40, 30)).astype(np.float32)
    out = normalise_section(a)
    assert np.allclose(out.std(axis=(1, 2)), 1.0, atol=0.05)
    assert np.allclose(np.median(out, axis=(1, 2)), 0.0, atol=1e-6)


def test_direction_probability_refuses_a_section():
    with pytest.raises(InputError, match="n_inlines, n_xlines, n_samples"):
        learned.direction_probability(np.zeros((40, 32), np.float32), 0, scale=(0.0, 1.0))


def test_bad_input_is_refused():
    with pytest.raises(InputError, match="NaN"):
        learned_fault_likelihood(np.full((40, 40), np.nan))
    with pytest.raises(InputError, match="section"):
        learned_fault_likelihood(np.zeros(10))
    with pytest.raises(InputError, match="directions"):
        LearnedOptions(directions="diagonal")
    with pytest.raises(InputError, match="likelihood"):
        FaultTracingOptions(likelihood="magic")


def _section_scores(seed):
    sec = synthetic_fault_section((256, 256), seed=TEST_SEED + seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = trace_faults(sec.section, options=LEARNED, progress=False)
    ours = fault_labels(res.faults, sec.section.shape) > 0
    return sec, res, ours


@pytest.mark.slow
def test_generated_unfaulted_sections_with_real_degradations_get_no_fault():
    rng = np.random.default_rng(5)
    found = []
    for seed in range(4):
        clean = synthetic_cube((256, 256), n_faults=0, seed=100 + seed, noise=0.0, max_dip=25.0).cube
        noisy = chaotic_interval(clean, rng, strength=1.0, blob=True)
        noisy = add_noise(noisy, rng, white=0.2, coherent=0.4)
        noisy = clip_and_quantise(noisy, rng, clip_percentile=98.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            found.append(len(trace_faults(noisy, options=LEARNED, progress=False).faults))
    # the target is 0 on each; reached on three. The first keeps one fault along the edge of its chaotic
    # blob (throw 0.4 sample, unshifted correlation 0.22): the evidence's discontinuity exception keeps it, though its
    # chaotic side is not continuous in itself (side coherence 0.01; asking for continuous sides drops it, and faults
    # of the Costa Rica crf section with them: see EvidenceOptions). The scan likelihood finds 12, 6, 8 and 17 faults
    # on these four (benchmarks/faults.py --only generated).
    assert sum(found) <= 1, found


@pytest.mark.slow
def test_generated_faulted_cubes_precision_and_recall():
    for seed in (0, 1):
        syn = synthetic_cube((96, 96, 96), seed=seed, noise=0.1)
        res = trace_faults(syn.cube, options=LEARNED, progress=False)
        s = evaluate_faults(fault_labels(res.faults, syn.cube.shape) > 0, syn.fault_labels > 0, tolerance=2)
        assert s.precision >= 0.90 and s.recall >= 0.90, (seed, s)


def test_section_step_is_a_positive_integer():
    assert LearnedOptions().section_step == 2  # every second section of a cube (the tracing default)
    for bad in (0, -1, 1.5, True):
        with pytest.raises(InputError, match="section_step"):
            LearnedOptions(section_step=bad)


def test_section_span_reads_the_computed_sections_around_a_block():
    span, computed, positions = learned.section_span(3, 7, 2, 10)
    assert span == (2, 7) and computed.tolist() == [2, 4, 6]
    assert_allclose(positions, [0.5, 1.0, 1.5, 2.0])  # sections 3-6 between 2, 4 and 6
    span, computed, positions = learned.section_span(7, 10, 2, 10)  # the cube's last section, 9, is computed
    assert span == (6, 10) and computed.tolist() == [6, 8, 9]
    assert_allclose(positions, [0.5, 1.0, 2.0])
    assert learned.section_span(3, 7, 1, 10)[2] is None


@pytest.mark.slow  # 2 s: the network on 32 + 40 sections twice
def test_every_second_section_equals_every_section_where_computed():
    syn = synthetic_cube((32, 40, 48), seed=3, noise=0.1)
    scale = learned.amplitude_scale(syn.cube)
    for axis in (0, 1):
        every = learned.direction_probability(syn.cube, axis, scale=scale)
        second = learned.direction_probability(syn.cube, axis, scale=scale, step=2)
        computed = [slice(None)] * 3
        computed[axis] = slice(0, None, 2)
        assert_allclose(second[tuple(computed)], every[tuple(computed)], atol=1e-6)
        between = np.take(second, [1], axis=axis)  # the mean of its neighbours
        assert_allclose(between, 0.5 * (np.take(every, [0], axis=axis) + np.take(every, [2], axis=axis)), atol=1e-6)


@pytest.mark.slow  # 1.2 s in the fast lane, whose budget is 60 s
def test_cube_directions_keep_the_larger_probability():
    # on the data's own grid (resample 1): with resampling the maximum is taken on the network's grid, before the
    # probability is interpolated back
    syn = synthetic_cube((32, 40, 48), seed=3, noise=0.1)
    both = fault_probability(syn.cube, options=LearnedOptions(cube_resample=1.0))
    inl = fault_probability(syn.cube, options=LearnedOptions(directions="inline", cube_resample=1.0))
    xl = fault_probability(syn.cube, options=LearnedOptions(directions="crossline", cube_resample=1.0))
    assert np.array_equal(both, np.maximum(inl, xl))


# the training script's three runs below, one after the other in one process: each as ``python -m
# seismo3d.training.fault_unet ARGS`` runs it (runpy, its ``__main__``, its sys.argv), PyTorch imported once
_TRAINING_RUNS = """
import runpy, sys
for argv in {runs!r}:
    sys.argv = ["fault_unet.py", *argv]
    runpy.run_module("seismo3d.training.fault_unet", run_name="__main__", alter_sys=True)
"""


@pytest.mark.slow  # 12-13 s, 15.5 CPU s (2026-11-29): imports torch, trains 3 times (the fast lane's budget: 60 s)
def test_training_smoke(tmp_path):
    """A few training steps on tiny sections with the training script's command line, in its own process (PyTorch's
    and numba's thread pools do not share one process safely): a new network, a fine-tuning of it and a distillation
    of it, the three runs in one process, as three ``python -m seismo3d.training.fault_unet`` commands would run them
    (each of those paid 10-15 CPU s of imports, PyTorch's and its optimiser's torch._dynamo among them, for 2 steps:
    30 s of the test, 2026-11-29)."""
    import json
    import subprocess
    import sys

    pytest.importorskip("torch")
    out, tuned, student = tmp_path / "run", tmp_path / "tuned", tmp_path / "student"
    runs = [
        ["--out", str(out), "--steps", "2", "--batch-size", "2", "--patch", "32", "--channels", "4,8,8,8", "--threads",
         "1", "--n-validation", "2", "--log-every", "1"],
        ["--out", str(tuned), "--steps", "2", "--batch-size", "2", "--patch", "32", "--threads", "1",
         "--n-validation", "2", "--log-every", "1", "--learning-rate", "1e-12", "--init-weights",
         str(out / "fault_unet.npz")],
        ["--out", str(student), "--steps", "1", "--batch-size", "2", "--patch", "32", "--channels", "2,4,4,4",
         "--threads", "1", "--n-validation", "2", "--log-every", "1", "--teacher", str(out / "fault_unet.npz"),
         "--distill-weight", "0.7"],
    ]
    done = subprocess.run([sys.executable, "-c", _TRAINING_RUNS.format(runs=runs)], capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.count("weights sha256") == 3, done.stdout  # each run's last line
    record = json.loads((out / "fault_unet.json").read_text())
    weights = dict(np.load(out / "fault_unet.npz"))
    assert record["weights_sha256"] == hashlib.sha256((out / "fault_unet.npz").read_bytes()).hexdigest()
    check = np.load(out / "fault_unet_check.npz")
    got = unet_forward(check["section"][None], FaultNetwork(onnx_model(weights)))[0]
    assert np.abs(got - check["probability"]).max() <= 1e-5
    assert [h["step"] for h in record["history"]] == [1, 2]
    # fine-tuning starts from those weights: their folded batch normalisations stay the identity, so at a vanishing
    # learning rate the run returns them (batch statistics in training mode would change every layer's output)
    again = dict(np.load(tuned / "fault_unet.npz"))
    assert again.keys() == weights.keys()
    assert max(float(np.abs(again[k] - weights[k]).max()) for k in weights) <= 1e-6
    # distilling: a narrower network learns the teacher's probability beside the labels; the record names the teacher
    student_record = json.loads((student / "fault_unet.json").read_text())
    assert student_record["training"]["teacher"] == str(out / "fault_unet.npz")
    assert student_record["training"]["distill_weight"] == 0.7
    assert student_record["training"]["channels"] == [2, 4, 4, 4]
    assert student_record["teacher_sha256"] == record["weights_sha256"]
    assert set(student_record["teacher_validation"]) == {"precision", "recall", "f1", "unfaulted_clean"}
    assert dict(np.load(student / "fault_unet.npz"))["enc0.0.weight"].shape == (2, 1, 3, 3)
    tuned_record = json.loads((tuned / "fault_unet.json").read_text())
    assert tuned_record["training"]["init_weights"] == str(out / "fault_unet.npz")
    assert tuned_record["init_weights_sha256"] == hashlib.sha256((out / "fault_unet.npz").read_bytes()).hexdigest()


# slow: forced blocks, each network block reading most of the cube along its sections (4-11 s). The grid of
# 0.7 (232 x 236 x 32) and three grids (0.5, 0.7, 1) (120 x 128 x 32), 70 s and 39 s, are asserted by
# `python benchmarks/fault_blocks.py --only learned_blocks --check` (issue 58: a claim over 20 s leaves the suite)
@pytest.mark.slow
@pytest.mark.parametrize("resample, shape, block, step", [
    (1.0, (72, 80, 48), 64, 1),  # the data's own grid: network blocks of 64 traces, halo 56 traces
    (1.0, (72, 80, 48), 64, 2),  # every 2nd section: blocks read the computed sections around theirs (the last,
])                               # 71 and 79, computed too)
def test_blocks_equal_the_in_memory_likelihood(tmp_path, resample, shape, block, step):
    from seismo3d.seismic.faults.likelihood.learned_blocks import chunked_learned_likelihood
    from seismo3d.seismic.blocks.options import ChunkOptions

    cube = synthetic_cube(shape, seed=2, noise=0.1).cube
    opt = LearnedOptions(cube_resample=resample, min_grid_samples=0,  # every grid, on traces of 32 and 48 samples too
                         section_step=step)
    mem = learned_fault_likelihood(cube, options=opt)
    run = chunked_learned_likelihood(cube, tmp_path / "l.zarr", options=opt,
                                     chunking=ChunkOptions(block=block, scheduler="synchronous"))
    steps = [f"network_{d}_{k}" for k in range(len(opt.cube_resample)) for d in ("inline", "crossline")]
    assert set(run.blocks_computed) == set(steps) | {"orientation"}
    assert min(run.blocks_computed[step] for step in steps + ["orientation"]) > 1, run.blocks_computed
    out = run.open()
    # equal up to float rounding, except where the dip sits on min_dip and rounding flips the dip mask (1 sample of
    # 1.75 M at resample 0.7, its dip 40.0015 deg)
    diff = np.abs(out["likelihood"][:] - mem.likelihood)
    on_the_mask_edge = np.abs(mem.dip_deg - opt.min_dip) <= 0.01
    assert diff[~on_the_mask_edge].max() <= 1e-5 and np.count_nonzero(diff > 1e-5) <= 3
    live = mem.likelihood > 0.5  # where there is a fault, its orientation is the same
    strike = np.abs(out["strike_deg"][:] - mem.strike_deg)[live]
    assert np.minimum(strike, 360 - strike).max() <= 0.5
    assert np.abs(out["dip_deg"][:] - mem.dip_deg)[live].max() <= 0.5


def test_blocks_refuse_nan_amplitudes(tmp_path):
    """NaN given to the learned likelihood by blocks directly (trace_faults reads them as 0 before its blocks): refused
    from the amplitude scale's subsample of traces before any block, and by a network block, naming its inlines."""
    from seismo3d.seismic.blocks.apply import BlockPlace
    from seismo3d.seismic.faults.likelihood.learned import network_block
    from seismo3d.seismic.faults.likelihood.learned_blocks import chunked_learned_likelihood

    cube = synthetic_cube((40, 40, 32), seed=2).cube.astype(np.float32)
    cube[0, 0, 5] = np.nan  # a trace of the subsample
    with pytest.raises(InputError, match=r"the cube holds NaN or infinite amplitudes; replace them"):
        chunked_learned_likelihood(cube, tmp_path / "l.zarr")
    assert not (tmp_path / "l.zarr").exists()
    with pytest.raises(InputError, match=r"NaN or infinite amplitudes in inlines 8-39 \(indices\)"):
        network_block(BlockPlace((8, 24, 0, 40), (8, 40, 0, 40)), cube[8:40] * np.inf, 0, LearnedOptions(), 1.0,
                      (0.0, 1.0), 40)


# A block on the whole cube's network grid of 0.7 (its origin off the pooling grid) equal to the whole cube: 42 s,
# asserted by `python benchmarks/fault_blocks.py --only network_grid --check`; the blocks above (grid 1) put their
# origins off 0 too.


@pytest.mark.parametrize("shape, limit", [((400, 400, 500), 10**9), ((1448, 1448, 512), 10**9)])
def test_network_blocks_are_as_long_as_the_limit_allows(shape, limit):
    # the network is 2D: a block of sections needs the receptive half of halo along them only, so the plan makes
    # them as long as the limit allows (the whole width: no halo) and only then stacks sections
    from seismo3d.seismic.faults.likelihood import learned_blocks
    from seismo3d.seismic.blocks.options import ChunkOptions

    opt = LearnedOptions(cube_resample=None)  # the three grids of resample: the default's two and the data's own
    baseline = 300 << 20
    plan = learned_blocks._plan(shape, opt, ChunkOptions(memory_limit=limit), baseline)
    budget = int((limit - baseline) * 0.8)
    assert [g["factor"] for g in plan["grids"]] == list(opt.grids(shape[2], 3)) == [0.5, 0.7, 1.0]
    step = int(opt.section_step)  # the blocks read the computed sections their others are interpolated from
    for g in plan["grids"]:
        grid, factor = g["network_shape"], g["factor"]
        for axis, name in enumerate(("inline", "crossline")):
            across, along = g["network_blocks"][name]
            assert learned_blocks._largest_network_bytes(grid, across, along, axis, shape, factor, 4, step) <= budget
            if along < grid[1 - axis]:  # longer sections would not fit, even one chunk of them
                assert along % 16 == 0 and across == 16
                assert learned_blocks._largest_network_bytes(grid, 16, along + 16, axis, shape, factor, 4,
                                                             step) > budget
            else:  # whole sections: as many as fit
                assert learned_blocks._largest_network_bytes(grid, across + 16, along, axis, shape, factor,
                                                             4, step) > budget or across >= grid[axis]


def test_the_likelihood_of_several_grids_is_the_mean_of_each_grids():
    # sections and cubes: the mean of the grids' probabilities, in the order given, each as one grid gives it
    sec = synthetic_cube((96, 80), seed=1, noise=0.1).cube
    cube = synthetic_cube((24, 40, 48), seed=1, noise=0.1).cube
    # every grid, none stretched: traces of 80 and 48 samples are shorter than the default's three grids need
    for data in (sec, cube):
        grids = fault_probability(data, options=LearnedOptions(resample=(0.5, 0.7, 1.0), cube_resample=None,
                                                               min_grid_samples=0, patch_samples=0))
        each = [fault_probability(data, options=LearnedOptions(resample=f, cube_resample=None, patch_samples=0))
                for f in (0.5, 0.7, 1.0)]
        expected = (each[0] + each[1] + each[2]) * np.float32(1.0 / 3.0)
        assert grids.dtype == np.float32 and np.array_equal(grids, expected)
    assert LearnedOptions(resample=0.7).resample == (0.7,)
    for bad in ((), (0.7, 0.7), (0.2, 0.7), 1.5, "fine"):
        with pytest.raises(InputError, match="resample"):
            LearnedOptions(resample=bad)


def test_grids_that_leave_the_traces_fewer_samples_than_the_receptive_half_are_not_run():
    # a 76-sample line (Great South Basin) on grids of 38, 53 and 76 samples: only its own grid; 80 samples (40, 56,
    # 80): 0.7 and 1; the 462 samples of an F3 inline: the three; the finest grid always, whatever the traces
    from seismo3d.seismic.faults.likelihood import learned_blocks
    from seismo3d.seismic.blocks.options import ChunkOptions

    opt = LearnedOptions()
    assert opt.min_grid_samples == RECEPTIVE_HALF
    assert opt.grids(76) == (1.0,) and opt.grids(80) == (0.7, 1.0) and opt.grids(111) == opt.grids(462) == opt.resample
    assert LearnedOptions(resample=(0.5, 0.7)).grids(20) == (0.7,)
    assert LearnedOptions(min_grid_samples=0).grids(8) == opt.resample
    for bad in (-1, 2.5, True):
        with pytest.raises(InputError, match="min_grid_samples"):
            LearnedOptions(min_grid_samples=bad)
    sec = synthetic_cube((96, 76), seed=1, noise=0.1).cube
    own = fault_probability(sec, options=LearnedOptions(resample=1.0))
    assert np.array_equal(fault_probability(sec, options=opt), own)
    # the run by blocks plans the same grids
    plan = learned_blocks._plan((400, 400, 76), opt, ChunkOptions(memory_limit=10**9), 300 << 20)
    assert [g["factor"] for g in plan["grids"]] == [1.0]


@pytest.mark.slow
def test_a_cube_runs_the_grids_of_cube_resample_and_a_section_those_of_resample():
    # issue 76: on cubes the default grids are (0.5, 0.7), the data's own grid left out (0.32 of the network's samples
    # of a 256^3 cube); (0.5, 1) was rejected (issue 58 and again at issue 76: a horizon tracked across a generated
    # cube's faults went 5.4 samples off); sections keep resample; cube_resample=None runs resample on cubes too
    opt = LearnedOptions(cube_resample=(0.5, 1.0))
    assert LearnedOptions().cube_resample == (0.5, 0.7) and LearnedOptions().grids(462, 3) == (0.5, 0.7)
    assert LearnedOptions().grids(462) == (0.5, 0.7, 1.0) and LearnedOptions(cube_resample=None).grids(462, 3) \
        == (0.5, 0.7, 1.0)
    assert LearnedOptions().grids(96, 3) == (0.7,) and LearnedOptions().grids(76, 3) == (1.0,)  # 0.5 / 0.7: < 56
    assert opt.grids(462) == (0.5, 0.7, 1.0) and opt.grids(462, 3) == (0.5, 1.0) and opt.grids(76, 3) == (1.0,)
    assert LearnedOptions(cube_resample=0.7).cube_resample == (0.7,)
    for bad in ((), (0.7, 0.7), (0.2, 0.7), 1.5, "fine"):
        with pytest.raises(InputError, match="cube_resample"):
            LearnedOptions(cube_resample=bad)
    sec = synthetic_cube((96, 128), seed=1, noise=0.1).cube
    assert np.array_equal(fault_probability(sec, options=opt),
                          fault_probability(sec, options=LearnedOptions(cube_resample=(0.7,))))
    cube = synthetic_cube((24, 40, 128), seed=1, noise=0.1).cube
    mine = fault_probability(cube, options=opt)
    two = LearnedOptions(resample=(0.5, 1.0), cube_resample=None)
    assert np.array_equal(mine, fault_probability(cube, options=two))
    assert not np.array_equal(mine, fault_probability(cube, options=LearnedOptions()))


def test_the_finest_grid_of_traces_shorter_than_the_training_patches_is_stretched_to_them():
    # 76 samples (Great South Basin): its one grid runs on 128; 96 samples: the grid 1 (not 0.7) on 128; traces of
    # 128 samples or more, and coarser grids, as they are; patch_samples=0: never
    opt = LearnedOptions()
    assert opt.patch_samples == 128
    assert opt.stretch(76, 1.0) == 128 and opt.stretch(96, 1.0) == 128 and opt.stretch(96, 0.7) == 0
    assert opt.stretch(128, 1.0) == opt.stretch(128, 0.5) == opt.stretch(462, 1.0) == 0
    assert LearnedOptions(patch_samples=0).stretch(76, 1.0) == 0
    for bad in (-1, 2.5, True):
        with pytest.raises(InputError, match="patch_samples"):
            LearnedOptions(patch_samples=bad)
    sec = synthetic_cube((96, 76), seed=1, noise=0.1).cube
    prob = fault_probability(sec, options=opt)
    assert prob.shape == sec.shape and prob.dtype == np.float32 and 0.0 <= prob.min() and prob.max() <= 1.0
    assert not np.array_equal(prob, fault_probability(sec, options=LearnedOptions(patch_samples=0)))


def test_orientation_sample_step_is_a_positive_integer():
    assert LearnedOptions().orientation_sample_step == 2  # strike and dip on every second sample of a cube
    for bad in (0, -1, 1.5, True):
        with pytest.raises(InputError, match="orientation_sample_step"):
            LearnedOptions(orientation_sample_step=bad)


@pytest.mark.slow
def test_below_the_orientation_floor_strike_and_dip_are_nan_and_the_likelihood_the_probability():
    """``orientation_floor``: in a cube, where the network's probability is below it, strike and dip are NaN and the
    likelihood is the probability (no dip to test against ``min_dip``); elsewhere all three are the bits of the
    orientation of every sample (``orientation_floor=0``). A section's are every sample's."""
    data = synthetic_cube((40, 40, 64), seed=3, noise=0.1).cube
    section = data[:, 20]
    every, floored = (learned_fault_likelihood(section, options=LearnedOptions(orientation_floor=f)) for f in (0, 0.5))
    for name in ("likelihood", "strike_deg", "dip_deg"):
        assert np.array_equal(getattr(floored, name), getattr(every, name))
    floor = LearnedOptions().orientation_floor
    assert floor == 0.01
    every = learned_fault_likelihood(data, options=LearnedOptions(orientation_floor=0.0))
    floored = learned_fault_likelihood(data)
    prob = fault_probability(data)
    below = prob < np.float32(floor)
    assert 0.05 < below.mean() < 0.999 and np.isfinite(every.strike_deg).all() and np.isfinite(every.dip_deg).all()
    for name in ("strike_deg", "dip_deg"):
        a, b = getattr(floored, name), getattr(every, name)
        assert np.isnan(a[below]).all() and np.array_equal(a[~below], b[~below])
    assert np.array_equal(floored.likelihood[below], prob[below]) and (every.likelihood[below] == 0).any()
    assert np.array_equal(floored.likelihood[~below], every.likelihood[~below])


def test_the_orientation_floor_is_a_probability_below_the_seed_threshold():
    for bad in (-0.01, 1.0):
        with pytest.raises(InputError, match="orientation_floor"):
            LearnedOptions(orientation_floor=bad)
    with pytest.raises(InputError, match="orientation_floor 0.3 leaves the voting's seeds"):
        FaultTracingOptions(learned=LearnedOptions(orientation_floor=0.3))
    assert FaultTracingOptions(learned=LearnedOptions(orientation_floor=0.29)).learned.orientation_floor == 0.29
