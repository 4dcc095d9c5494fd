"""The map job: an RGB-D sequence in, a trajectory, a keyframe graph, a mesh and a picture of the map out.

:func:`run_map_job` streams the frames of a TUM or 7-Scenes sequence (:func:`seismo3d.mapping.open_sequence`) through
:class:`seismo3d.mapping.RGBDMapper` and writes into the output folder:

* ``trajectory.txt``: ``timestamp tx ty tz qx qy qz qw`` (TUM format, camera-to-world, metres), one line per input
  frame that has a pose (frames the loop could not use get the motion prediction; see ``keyframes.json``);
* ``keyframes.json``: the keyframe graph (vertices with frame index, timestamp and pose; odometry and loop edges), the
  frames skipped or lost and why, a summary (frames, keyframes, loops, frames per second) and, when the sequence has a
  reference trajectory, the ATE and RPE against it;
* ``mesh.ply``: the TSDF map by marching cubes (binary PLY with vertex normals);
* ``map.png``: the mesh with the trajectory, the keyframes, the reference trajectory (when the sequence has one,
  aligned as the ATE aligns it, with the ATE in the title) and a scale bar, rendered off screen.

The output folder follows the output policy of every command (:mod:`seismo3d.jobs.outputs`); the files are written
into a staging folder and moved in together. A frame that cannot be read or used (missing file, depth of the wrong dtype or size,
no valid depth, a timestamp out of order) is skipped with a :class:`~seismo3d.errors.FrameSkippedWarning`; an
interrupt (Ctrl-C) stops the loop and the outputs of the frames done so far are still written before it propagates.
"""

from __future__ import annotations

import json
import pathlib
import time
import warnings
from dataclasses import dataclass

import numpy as np
from threadpoolctl import threadpool_limits

from .._atomic import StagedFolder, atomic_path
from .._progress import progress_steps
from ..errors import DataIntegrityError, DataNotFoundError, FrameSkippedWarning, InputError, RegistrationError
from ..mapping import RGBDMapper, open_sequence
from ..mapping.metrics import (absolute_trajectory_error, reference_in_map_frame, relative_pose_error,
                               write_tum_trajectory)
from .outputs import check_outputs, output_folder
from .runinfo import RUN_JSON, RunRecord

__all__ = ["MapJobResult", "RESULTS", "run_map_job", "write_ply"]

RESULTS = ("trajectory.txt", "keyframes.json", "mesh.ply", "map.png", RUN_JSON)  # what a run writes into its folder


@dataclass(frozen=True)
class MapJobResult:
    """What :func:`run_map_job` wrote and measured.

    Attributes
    ----------
    written : dict of str to pathlib.Path
        ``trajectory``, ``keyframes``, ``mesh``, ``map`` (when rendered) and ``run_json``.
    summary : dict
        The summary of ``keyframes.json``: ``frames_in_sequence``, ``frames_processed``, ``frames_tracked``,
        ``frames_skipped``, ``keyframes``, ``loop_closures``, ``seconds``, ``frames_per_second``, ``map_blocks``,
        ``map_mib``, ``interrupted``, ...
    evaluation : dict or None
        ATE and RPE against the sequence's reference trajectory (``ate_rmse_m``, ``ate_max_m``,
        ``rpe_translation_rmse_m``, ``rpe_rotation_rmse_deg``, ``n_associated``); None without one.
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``map``: the frames; ``write``: the files).
    """

    written: dict
    summary: dict
    evaluation: dict | None
    run_json: pathlib.Path
    stage_seconds: dict


def write_ply(path, mesh) -> None:
    """Write a triangle mesh as binary little-endian PLY (float32 positions and normals, int32 faces), atomically,
    through VTK (:func:`seismo3d.viz.save_polydata`).

    Parameters
    ----------
    path : str or os.PathLike
    mesh : TriangleMesh
    """
    import pyvista as pv

    from ..viz.fault_meshes import save_polydata

    faces = np.asarray(mesh.faces, np.int64).reshape(-1, 3)
    poly = pv.PolyData(np.asarray(mesh.vertices, np.float32).reshape(-1, 3),
                       np.column_stack([np.full(len(faces), 3), faces]).ravel() if len(faces) else None)
    if poly.n_points:  # (pyvista refuses empty arrays; an empty map is written without them)
        poly.point_data["Normals"] = np.asarray(mesh.normals, np.float32).reshape(-1, 3)
        poly.point_data.active_normals_name = "Normals"
    save_polydata(poly, path)


def _loop(sequence, mapper, frames, steps, skipped):
    """Map ``frames`` of ``sequence``; returns True when interrupted (Ctrl-C)."""
    start = time.perf_counter()
    for count, i in enumerate(frames, 1):
        entry = sequence.entries[i]
        try:
            try:
                frame = sequence.read(i)
                mapper.process(frame, index=i)
            except (DataNotFoundError, DataIntegrityError, InputError, RegistrationError) as exc:
                skipped.append(dict(index=int(i), timestamp=float(entry.timestamp), reason=str(exc)))
                warnings.warn(f"frame {i} (t = {entry.timestamp:.3f} s) skipped: {exc}", FrameSkippedWarning,
                              stacklevel=2)
                if mapper.filter is not None:
                    try:
                        mapper.predict(i, entry.timestamp)
                    except InputError:
                        pass
        except KeyboardInterrupt:
            return True
        fps = count / max(time.perf_counter() - start, 1e-9)
        steps.advance(1, status=f"{fps:.1f} frames/s, {len(mapper.graph.keyframes)} keyframes, "
                                f"{mapper.graph.n_loops} loops")
    return False


def _evaluation(sequence, timestamps, poses):
    if sequence.groundtruth is None or len(poses) < 3:
        return None
    ref_t, ref_p = sequence.groundtruth
    try:
        ate = absolute_trajectory_error(timestamps, poses, ref_t, ref_p)
        rpe_t, rpe_r = relative_pose_error(timestamps, poses, ref_t, ref_p)
    except InputError:
        return None
    return dict(ate_rmse_m=ate.rmse, ate_max_m=ate.max, rpe_translation_rmse_m=rpe_t.rmse,
                rpe_rotation_rmse_deg=rpe_r.rmse, n_associated=ate.n)


def _reference(sequence, timestamps, poses):
    """The sequence's ground truth in the map's frame over the mapped frames (aligned as the ATE aligns it), or
    None without one."""
    if sequence.groundtruth is None or len(poses) < 3:
        return None
    try:
        return reference_in_map_frame(timestamps, poses, *sequence.groundtruth)
    except InputError:
        return None


def run_map_job(sequence, output, *, options=None, max_frames: int | None = None, progress: bool = True,
                render: bool = True, overwrite: bool = False) -> MapJobResult:
    """Map an RGB-D sequence and write the outputs listed in the module docstring.

    Parameters
    ----------
    sequence : str or os.PathLike
        Folder of a TUM RGB-D or 7-Scenes sequence.
    output : str or os.PathLike
        Output folder (created if missing); not the sequence folder nor one holding it, and not one holding an
        earlier run's files unless ``overwrite`` (:mod:`seismo3d.jobs.outputs`; checked before the sequence is
        read).
    options : MapperOptions, optional
    max_frames : int, optional
        Map only the first this many frames.
    progress : bool
        Report progress with frames per second (:mod:`seismo3d._progress`: a bar on a terminal, log lines
        otherwise).
    render : bool
        Write ``map.png`` (pyvista off screen).
    overwrite : bool
        Replace the files of an earlier run in ``output``.

    Returns
    -------
    MapJobResult

    Raises
    ------
    DataNotFoundError
        The sequence folder does not exist.
    InputError
        The folder is not a sequence, the output folder breaks the output policy, or ``max_frames`` < 1.
    KeyboardInterrupt
        Re-raised after the outputs of the frames done so far have been written.
    """
    record = RunRecord("map", locals())  # first: the arguments as called
    out = pathlib.Path(output)
    check_outputs([output_folder(out, RESULTS, f"{pathlib.Path(sequence).name}_map")], [sequence],
                  overwrite=overwrite)
    if max_frames is not None and int(max_frames) < 1:
        raise InputError(f"max_frames must be >= 1; got {max_frames!r}")
    seq = open_sequence(sequence)
    frames = range(len(seq) if max_frames is None else min(len(seq), int(max_frames)))
    mapper = RGBDMapper(options)
    skipped = []
    start = time.perf_counter()
    # numpy's BLAS threads only slow the small (N, 3) products of the loop down; numba runs the parallel parts
    with threadpool_limits(1, user_api="blas"):
        try:
            with progress_steps(len(frames), "map", unit="frame", enabled=progress) as steps, record.stage("map"):
                interrupted = _loop(seq, mapper, frames, steps, skipped)
        except Exception:
            # an unexpected failure: still keep what the frames before it built, then report the failure
            _write_outputs(out, seq, mapper, skipped, time.perf_counter() - start, True, False, record)
            raise
    elapsed = time.perf_counter() - start
    written = _write_outputs(out, seq, mapper, skipped, elapsed, interrupted, render, record)
    if interrupted:
        raise KeyboardInterrupt
    return written


def _write_outputs(out, seq, mapper, skipped, elapsed, interrupted, render, record: RunRecord) -> MapJobResult:
    """The files of the run and its ``run.json``, moved into ``out`` together once every one is written."""
    with StagedFolder(out) as stage:
        with record.stage("write"):
            written, summary, evaluation = _write_files(stage.path, seq, mapper, skipped, elapsed, interrupted,
                                                        render)
        final = {key: stage.final(path) for key, path in written.items()}
        final["run_json"] = stage.final(record.write(stage.path / RUN_JSON, inputs={"sequence": seq.root},
                                                     outputs=final, results=dict(summary, evaluation=evaluation)))
    return MapJobResult(final, summary, evaluation, final["run_json"], dict(record.stage_seconds))


def _write_files(out, seq, mapper, skipped, elapsed, interrupted, render):
    traj = mapper.trajectory()
    timestamps, poses, status = traj.timestamps, traj.poses, traj.status
    written = {"trajectory": out / "trajectory.txt", "keyframes": out / "keyframes.json", "mesh": out / "mesh.ply"}
    write_tum_trajectory(written["trajectory"], timestamps, poses)
    tracked = [s != "lost" for s in status]
    lost = [dict(index=f.index, timestamp=f.timestamp) for f in mapper.frames if f.status == "lost"]
    summary = dict(sequence=str(seq.root), layout=seq.layout, frames_in_sequence=len(seq),
                   frames_processed=len(mapper.frames), frames_tracked=int(sum(tracked)), frames_skipped=len(skipped),
                   keyframes=len(mapper.graph.keyframes), loop_closures=mapper.graph.n_loops,
                   seconds=elapsed, frames_per_second=(len(mapper.frames) + len(skipped)) / max(elapsed, 1e-9),
                   map_blocks=mapper.volume.n_blocks, map_mib=mapper.volume.nbytes / 2**20,
                   interrupted=bool(interrupted))
    keep = np.array(tracked, bool)
    evaluation = _evaluation(seq, timestamps[keep], poses[keep]) if keep.any() else None
    payload = dict(summary=summary, evaluation=evaluation, skipped_frames=skipped, lost_frames=lost,
                   **mapper.graph.to_dict())
    with atomic_path(written["keyframes"]) as tmp:
        tmp.write_text(json.dumps(payload, indent=1) + "\n")
    mesh = mapper.volume.extract_mesh()
    write_ply(written["mesh"], mesh)
    if render:
        from ..viz.maps import render_map

        reference, title = _reference(seq, timestamps[keep], poses[keep]), None
        if reference is not None and evaluation is not None:
            title = (f"ATE RMSE {100 * evaluation['ate_rmse_m']:.1f} cm over {evaluation['n_associated']} frames "
                     "against the ground truth (green)")
        written["map"] = render_map(mesh, poses, mapper.graph.poses(), out / "map.png", reference=reference,
                                    title=title)
    return written, summary, evaluation
