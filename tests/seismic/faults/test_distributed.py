"""trace_faults by blocks on a local dask.distributed cluster gives what it gives on dask's threads (issue 75): the
same fault likelihood within 1e-5, the same votes and the same faults, with every step in more than one block."""

from __future__ import annotations

import numpy as np
import pytest

import seismo3d.seismic.faults.pipeline as pipeline
from seismo3d.data.synthetic import synthetic_cube
from seismo3d.seismic.blocks.options import BlockRunOptions, ChunkOptions
from seismo3d.seismic.faults import trace_faults


@pytest.mark.slow  # two fault runs by blocks of a 64 x 72 x 48 cube and a cluster: 57 s on 2 shared cores
def test_blocks_on_a_local_cluster_equal_blocks_on_threads(tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    # blocks of 32 traces in every step (the cube's 64 x 72 traces: 2 x 3 blocks, halos across every boundary)
    monkeypatch.setattr(pipeline, "ChunkOptions", lambda **kw: ChunkOptions(block=32, **kw))
    cube = synthetic_cube((64, 72, 48), seed=2).cube.astype(np.float32)
    (tmp_path / "threads").mkdir()
    (tmp_path / "cluster").mkdir()
    threads = trace_faults(cube, blocks=BlockRunOptions(in_memory=False, work_dir=tmp_path / "threads"),
                           progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        cluster_run = trace_faults(cube, blocks=BlockRunOptions(in_memory=False, work_dir=tmp_path / "cluster",
                                                                scheduler=cluster.scheduler_address),
                                   progress=False)
    assert cluster_run.stores and threads.stores
    np.testing.assert_allclose(cluster_run.likelihood[:], threads.likelihood[:], atol=1e-5, rtol=0)
    np.testing.assert_allclose(cluster_run.votes[:], threads.votes[:], atol=1e-6, rtol=0)
    assert len(cluster_run.faults) == len(threads.faults) > 0
    for f, g in zip(threads.faults, cluster_run.faults):
        np.testing.assert_array_equal(f.points, g.points)
