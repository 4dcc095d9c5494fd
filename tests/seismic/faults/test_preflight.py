"""Judging a cube from a sample of blocks before tracing its faults, and the smallest memory limit of a block-by-block
run (seismo3d.seismic.faults.preflight.judge_sample, seismo3d.seismic.faults.pipeline.minimum_memory_limit)."""

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError, UnsupportedDataError
from seismo3d.seismic.faults.likelihood import learned_blocks, scan_blocks as likelihood_blocks
from seismo3d.seismic.faults.surfaces import blocks as surface_steps
from seismo3d.seismic.faults.likelihood.scan import FaultScanOptions
from seismo3d.seismic.blocks.options import ChunkOptions
from seismo3d.seismic.faults.options import FaultTracingOptions
from seismo3d.seismic.blocks.preflight import SampleOptions
from seismo3d.seismic.faults import preflight as fault_preflight
from seismo3d.seismic.faults.result import FaultLikelihood
from seismo3d.seismic.faults.preflight import CubeSample, judge_sample, lateral_coherence
from seismo3d.seismic.faults.steps import run_likelihood
from seismo3d.seismic.faults.surfaces.ridges import ridges
from seismo3d.seismic.faults.pipeline import minimum_memory_limit


class Recording:
    """An array that records the samples read from it."""

    def __init__(self, data):
        self.data, self.shape, self.read = data, data.shape, 0

    def __getitem__(self, region):
        block = self.data[region]
        self.read += block.size
        return block


SMALL = SampleOptions(n_blocks=2, traces=32, samples=96)  # a quick sample for tests


def test_noise_is_refused_from_a_sample_reading_only_the_sample():
    noise = Recording(np.random.default_rng(0).standard_normal((160, 160, 400)).astype(np.float32))
    message = (r"^in a sample of 2 blocks of 32 x 32 traces, neighbouring traces correlate at 0.1\d \(the median of "
               r"their best correlation within 4 samples; below 0.3\): the data has no lateral coherence")
    with pytest.raises(UnsupportedDataError, match=message):
        judge_sample(noise, sample=SMALL, options=FaultTracingOptions())
    assert noise.read == 2 * 32 * 32 * 96


def test_lateral_coherence_of_noise_dipping_reflections_and_shuffled_traces():
    """White noise measures about 1.3 / sqrt(n_samples) (the median of the largest of 9 correlations of n samples);
    reflections dipping by 3 samples a trace are found within the lags; the same traces out of order are not."""
    rng = np.random.default_rng(0)
    n = 256
    noise = rng.standard_normal((40, 40, n)).astype(np.float32)
    assert lateral_coherence([noise]) == pytest.approx(1.3 / np.sqrt(n), abs=0.02)
    trace = np.convolve(rng.standard_normal(n + 300), np.hanning(9), mode="same")
    dipping = np.stack([np.stack([trace[3 * i + j: 3 * i + j + n] for j in range(20)]) for i in range(20)])
    assert lateral_coherence([dipping.astype(np.float32)]) > 0.99
    shuffled = dipping.reshape(400, n)[rng.permutation(400)].reshape(20, 20, n)
    assert lateral_coherence([shuffled.astype(np.float32)]) < 0.3


@pytest.mark.parametrize("likelihood", ["learned", pytest.param("scan", marks=pytest.mark.slow)])  # scan: 13 s
def test_the_sample_counts_the_candidates_of_the_likelihood_the_run_makes(likelihood):
    """One block: its seed candidates are the ridges above the seed threshold of the run's own likelihood
    (run_likelihood: the network's or the scan), and its saturation that likelihood's."""
    cube = synthetic_cube((64, 64, 160), seed=2).cube
    opt = FaultTracingOptions(likelihood=likelihood)
    one = SampleOptions(n_blocks=1, traces=32, samples=96)
    sample = judge_sample(cube, sample=one, options=opt)
    block = np.ascontiguousarray(cube[16:48, 16:48, 32:128], dtype=np.float32)  # the centre block
    fl = run_likelihood(block, opt)
    expected = ridges(fl.likelihood, fl.strike_deg, fl.dip_deg, opt.voting.seed_threshold)
    n = int(np.count_nonzero(expected > opt.voting.seed_threshold))
    assert sample.candidate_density * block.size == pytest.approx(n, abs=1e-6)
    assert sample.saturated_fraction == pytest.approx(float(np.mean(fl.likelihood > opt.saturation_level)), abs=1e-9)


def test_a_saturated_likelihood_is_refused_from_the_sample(monkeypatch):
    """Coherent amplitudes whose likelihood (here replaced) is above the saturation level everywhere."""
    cube = synthetic_cube((64, 64, 160), seed=2).cube

    def saturated(data, opt, progress=False):
        return FaultLikelihood(np.full(data.shape, 0.95, np.float32), np.zeros(data.shape, np.float32),
                               np.full(data.shape, 90.0, np.float32))

    monkeypatch.setattr(fault_preflight, "run_likelihood", saturated)
    with pytest.raises(UnsupportedDataError, match=r"^in a sample of 2 blocks of 32 x 32 traces, the fault likelihood "
                                                   r"is above 0.9 at 100% of the samples"):
        judge_sample(cube, sample=SMALL, options=FaultTracingOptions())


def test_a_velocity_model_is_refused_from_a_sample():
    t = np.linspace(0.0, 1.0, 200)
    model = 1500.0 + 2500.0 * t[None, None, :] + np.linspace(0, 50, 64)[:, None, None] + np.zeros((64, 64, 1))
    with pytest.raises(UnsupportedDataError, match="not seismic amplitude data"):
        judge_sample(model.astype(np.float32), options=FaultTracingOptions())


def test_a_cube_too_small_is_refused_before_reading():
    tiny = Recording(np.zeros((20, 6, 100), np.float32))
    with pytest.raises(UnsupportedDataError, match="fault tracing needs at least 32 traces"):
        judge_sample(tiny, options=FaultTracingOptions())
    assert tiny.read == 0


@pytest.mark.slow
def test_seismic_passes_with_its_seed_candidates():
    cube = synthetic_cube((64, 64, 160), seed=2).cube
    sample = judge_sample(cube, sample=SMALL, options=FaultTracingOptions())
    assert sample.n_blocks == 2 and sample.n_samples == 2 * 32 * 32 * 96
    assert sample.saturated_fraction < 0.5  # far from the refusal
    assert 0.0 < sample.candidate_density < 0.2
    assert sample.candidates((100, 100, 100)) == int(np.ceil(sample.candidate_density * 1e6))


@pytest.mark.parametrize("likelihood", ["scan", "learned"])
@pytest.mark.parametrize("shape", [(128, 128, 128), (400, 400, 500), (96, 300, 64)])
def test_minimum_memory_limit_is_what_both_stages_plan_with(shape, likelihood):
    """At the minimum both block-by-block stages plan their blocks (the second from a process grown by the stage
    growth); 1 MiB less and one of them refuses."""
    baseline, growth = 300 << 20, 50 << 20
    opt = FaultTracingOptions(likelihood=likelihood)
    limit = minimum_memory_limit(shape, baseline=baseline, growth=growth, options=opt)

    def plans(memory_limit):
        chunking = ChunkOptions(memory_limit=memory_limit)
        if likelihood == "scan":
            likelihood_blocks._plan(shape, FaultScanOptions(), chunking, baseline)
        else:
            learned_blocks._plan(shape, opt.learned, chunking, baseline)
        surface_steps.plan_blocks(shape, opt, chunking, baseline + growth)

    plans(limit)
    with pytest.raises(InputError, match="raise (--)?memory_limit"):
        plans(limit - (1 << 20))


def test_minimum_memory_limit_holds_the_predicted_seed_candidates_and_cells():
    """The seed candidates a sample predicts, and as many fault cells per candidate
    (``CELLS_PER_CANDIDATE``) in the stages after the blocks (``held_stages``) and those given (the job's writers)."""
    from seismo3d.seismic.blocks.plan import HeldStage, held_need

    shape = (400, 400, 500)
    plain = minimum_memory_limit(shape, baseline=0, growth=0)
    dense = CubeSample(n_blocks=3, n_samples=1, saturated_fraction=0.1, candidate_density=0.2)
    with_candidates = minimum_memory_limit(shape, baseline=0, sample=dense, growth=0)
    candidates = dense.candidates(shape)
    cells = int(np.ceil(candidates * surface_steps.CELLS_PER_CANDIDATE))
    assert with_candidates == max(candidates * surface_steps.CANDIDATE_BYTES,
                                  held_need(surface_steps.held_stages(shape), cells)[0]) > plain
    writer = HeldStage("a writer", lambda n: 3 * with_candidates + n)
    assert minimum_memory_limit(shape, baseline=0, sample=dense, growth=0,
                                after=(writer,)) == 3 * with_candidates + cells
    sparse = CubeSample(n_blocks=3, n_samples=1, saturated_fraction=0.1, candidate_density=1e-6)  # 80 candidates
    fixed = held_need(surface_steps.held_stages(shape), 60)[0]  # the throws' windows, whatever the cells
    assert minimum_memory_limit(shape, baseline=0, sample=sparse, growth=0) == max(plain, fixed)
