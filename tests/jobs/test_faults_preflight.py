"""The faults job decides its refusals before the full computation (issue 32): data without lateral coherence from a
sample of blocks, a memory limit too small with the smallest one that works, and no negative sizes in any message."""

import logging
import re
import time

import numpy as np
import pytest
import segyio
from typer.testing import CliRunner

import seismo3d.seismic.blocks.options as block_options
import seismo3d.jobs.faults as job
import seismo3d.seismic.faults.pipeline as pipeline
from seismo3d.cli import app
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import UnsupportedDataError
from seismo3d.seismic.faults.preflight import CubeSample

runner = CliRunner()


def _never(*args, **kwargs):  # pragma: no cover - must not be called
    raise AssertionError("the full computation started")


_SIZE = r"(\d+(?:\.\d+)?(?:MB|GB))"


def _bytes(text: str) -> int:
    """A size as the job writes it ('460MB', '1.3GB'; the process running the whole suite can hold over 1 GB)."""
    value, unit = float(text[:-2]), text[-2:]
    return int(round(value * (10 ** 6 if unit == "MB" else 10 ** 9)))


def _error_line(result) -> str:
    """The refusal: exit 2, one 'error:' line, the last on stderr (after progress lines), no traceback."""
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert result.exit_code == 2 and isinstance(result.exception, SystemExit), result.output
    assert [line for line in lines if line.startswith("error: ")] == lines[-1:], result.stderr
    return lines[-1]


@pytest.fixture(scope="module")
def cube_file(tmp_path_factory):
    """A 128^3 SEG-Y cube: in memory it needs ~200 MB beyond the process, more than the limits below leave."""
    path = tmp_path_factory.mktemp("cube") / "cube.sgy"
    segyio.tools.from_array3D(str(path), synthetic_cube((128, 128, 128), seed=2).cube.astype(np.float32), format=5,
                              dt=4000)
    return path


class _Started(Exception):
    """The run went past its checks: its first block started."""


def _started(*args, **kwargs):
    raise _Started


def _stop_at_the_blocks(monkeypatch) -> dict:
    """Runs by blocks at any limit that stop at their first block (_Started), and the process (``'bytes'`` of the
    dict returned) as measured by the first call for every call: a process of 2 GB (the whole suite) can give back
    more than the advice's 5 % margin between two calls (release_memory trims the heap); a user's fresh process
    differs by ~10 MB between runs."""
    monkeypatch.setattr(pipeline, "chunked_fault_likelihood", _started)
    monkeypatch.setattr(pipeline, "chunked_learned_likelihood", _started)
    monkeypatch.setattr(block_options, "fits_in_memory", lambda *a, **k: False)  # blocks at either limit
    baseline = {}
    measure = pipeline.worker_baseline
    monkeypatch.setattr(pipeline, "worker_baseline", lambda *a, **k: baseline.setdefault("bytes", measure(*a, **k)))
    return baseline


@pytest.mark.slow
@pytest.mark.parametrize("sample", [CubeSample(n_blocks=3, n_samples=1, saturated_fraction=0.1, candidate_density=0.0),
                                    CubeSample(n_blocks=3, n_samples=1, saturated_fraction=0.1,
                                               candidate_density=1.0)],  # 2 M seed candidates: 168 MB
                         ids=["few-candidates", "dense-candidates"])
@pytest.mark.parametrize("likelihood", ["scan", "learned"])
def test_the_limit_named_is_one_the_run_goes_through_with(cube_file, tmp_path, monkeypatch, sample, likelihood):
    """A limit too small is refused once, after the sample and before any block, naming a limit; with that limit the
    run passes its checks and starts its blocks (issue 77: the advice moved, 830MB, then at 830MB "1000MB or more",
    when the smallest blocks were checked before the sample's seed candidates)."""
    monkeypatch.setattr(pipeline, "judge_sample", lambda *a, **k: sample)
    _stop_at_the_blocks(monkeypatch)
    line = _error_line(runner.invoke(app, ["faults", str(cube_file), "-o", str(tmp_path / "out"),
                                           "--likelihood", likelihood, "--memory-limit", "100MB"]))
    assert line.startswith("error: cube: a block-by-block run of its 128 x 128 x 128 samples needs a memory limit of "
                           "at least ")
    assert f"(its smallest blocks, and the ~{sample.candidates((128, 128, 128))} seed candidates" in line
    assert "more than the 100MB given" in line and not re.search(r"-\d", line)
    need = re.search(rf"pass --memory-limit {_SIZE} or more$", line).group(1)
    assert _bytes(need) >= sample.candidates((128, 128, 128)) * 80
    assert not (tmp_path / "out").exists()
    with pytest.raises(_Started):
        job.run_faults_job(cube_file, tmp_path / "out", memory_limit=need, likelihood=likelihood, progress=False)


@pytest.mark.slow
def test_a_limit_too_small_for_the_stages_after_the_blocks_is_refused_before_the_work(cube_file, tmp_path,
                                                                                      monkeypatch):
    """The fault cells, skins, throws and the writers hold their data whole after the blocks (issue 75): a limit that
    the smallest blocks fit but the cells a sample predicts do not is refused before any block, naming a limit that
    holds the largest of those stages; with it the run passes its checks and starts its blocks."""
    from seismo3d.seismic.blocks.plan import held_need
    from seismo3d.seismic.faults.surfaces.blocks import CELLS_PER_CANDIDATE, held_stages

    shape = (128, 128, 128)
    few = CubeSample(n_blocks=3, n_samples=1, saturated_fraction=0.1, candidate_density=0.0)
    # every sample a candidate (2,097,152): the cells' stages need more than the rounding of the first limit leaves
    # beside the process, up to a process of several GB (a worker late in the suite holds 2 GB)
    many = CubeSample(n_blocks=3, n_samples=1, saturated_fraction=0.1, candidate_density=1.0)
    baseline = _stop_at_the_blocks(monkeypatch)

    def refusal(sample, limit):
        monkeypatch.setattr(pipeline, "judge_sample", lambda *a, **k: sample)
        line = _error_line(runner.invoke(app, ["faults", str(cube_file), "-o", str(tmp_path / "out"),
                                               "--memory-limit", limit]))
        assert not (tmp_path / "out").exists()
        return re.search(rf"pass --memory-limit {_SIZE} or more$", line).group(1)

    blocks_only = refusal(few, "100MB")  # the smallest blocks' limit, or the fixed parts of the later stages
    with pytest.raises(_Started):
        job.run_faults_job(cube_file, tmp_path / "out", memory_limit=blocks_only, progress=False)
    need = refusal(many, blocks_only)  # refused at a limit the blocks fit, before any block
    cells = int(np.ceil(many.candidates(shape) * CELLS_PER_CANDIDATE))
    stages = held_stages(shape) + job._writer_stages(shape)
    assert _bytes(need) >= baseline["bytes"] + held_need(stages, cells)[0] > _bytes(blocks_only)
    with pytest.raises(_Started):
        job.run_faults_job(cube_file, tmp_path / "out", memory_limit=need, progress=False)


@pytest.mark.slow
def test_progress_lines_have_no_negative_sizes(cube_file, tmp_path, monkeypatch, caplog):
    """A limit below the process's own size: the lines say what the process holds, never a negative size left."""
    monkeypatch.setattr(pipeline, "judge_sample", lambda *a, **k: CubeSample(3, 1, 0.1, 0.0))
    monkeypatch.setattr(pipeline, "minimum_memory_limit", lambda *a, **k: 0)  # let the run reach its first step

    class Started(Exception):
        pass

    def started(*args, **kwargs):
        raise Started

    monkeypatch.setattr(pipeline, "chunked_fault_likelihood", started)
    monkeypatch.setattr(pipeline, "chunked_learned_likelihood", started)
    with caplog.at_level(logging.INFO, logger="seismo3d"), pytest.raises(Started):
        job.run_faults_job(cube_file, tmp_path / "out", memory_limit="100MB", progress=False)
    # no negative size (a range of numbers, such as the input's inlines "(1-128)", is not one)
    assert "block by block" in caplog.text and not re.search(r"(?<!\w)-\d", caplog.text)


@pytest.fixture(scope="module")
def noise_file(tmp_path_factory):
    """The issue's cube: 400 x 400 x 500 float32 white noise as SEG-Y (358 MB)."""
    path = tmp_path_factory.mktemp("noise") / "noise.sgy"
    noise = np.random.default_rng(0).standard_normal((400, 400, 500), dtype=np.float32)
    segyio.tools.from_array3D(str(path), noise, format=5, dt=4000)
    return path


@pytest.mark.slow
def test_white_noise_under_1GB_is_refused_within_30_s(noise_file, tmp_path):
    """As a user runs it: a fresh process (this one is larger than 1 GB after a test session), imports included.
    Its CPU seconds (user + system, the child's and its threads'), which stay near their value under load where the
    wall time does not: alone 10-18 s wall, 12.5-19.9 CPU s (2026-11-27, the slow machine, the sample's scan); 45 s
    wall in a CI run beside three other heavy processes on 2 cores (the wall-clock limit failed there); 13.1 s wall,
    4.5 CPU s refused by the traces' coherence before any likelihood (2026-11-28, load 9-13)."""
    import os
    import resource
    import subprocess
    import sys

    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "seismo3d.cli", "faults", str(noise_file), "-o", str(tmp_path / "out"),
                           "--memory-limit", "1GB"], capture_output=True, text=True, env=env, timeout=300)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    seconds = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print(f"refused in {wall:.1f} s, {seconds:.1f} CPU s")
    assert done.returncode == 2 and "Traceback" not in done.stderr, done.stderr
    assert done.stderr.splitlines()[-1] == (
        "error: in a sample of 3 blocks of 48 x 48 traces, neighbouring traces correlate at 0.09 (the median of their "
        "best correlation within 4 samples; below 0.3): the data has no lateral coherence to trace faults in (noise, "
        "chaotic reflections, or traces out of order); check the inline/crossline geometry or the file")
    assert seconds <= 30.0
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_white_noise_under_100MB_is_refused_for_its_data_before_any_block(noise_file, tmp_path, monkeypatch):
    """Data the sample refuses is refused for what it is at any limit, not first sent to a larger limit."""
    monkeypatch.setattr(pipeline, "chunked_fault_likelihood", _never)
    monkeypatch.setattr(pipeline, "chunked_learned_likelihood", _never)
    line = _error_line(runner.invoke(app, ["faults", str(noise_file), "-o", str(tmp_path / "out"),
                                           "--memory-limit", "100MB"]))
    assert "the data has no lateral coherence to trace faults in" in line and "memory" not in line
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_noise_in_memory_is_refused_from_a_sample(tmp_path, monkeypatch):
    """A cube traced in memory but large enough to sample: refused before its whole likelihood."""
    path = tmp_path / "noise.npy"
    np.save(path, np.random.default_rng(1).standard_normal((300, 300, 320), dtype=np.float32))
    monkeypatch.setattr(pipeline, "run_likelihood", _never)  # the whole cube's likelihood
    with pytest.raises(UnsupportedDataError, match="in a sample of 3 blocks"):
        job.run_faults_job(path, tmp_path / "out", progress=False)
