"""What the ``seismo3d`` commands print beside their files: arrays, a terrain registration's summary, why a
registration did not converge (in the command's flags) and how many frames a map tracked. numpy is imported only where
an array is printed: ``--help`` and the refusals before a job need none."""

from __future__ import annotations

import typer

__all__ = ["array_text", "echo_terrain", "frames_tracked", "why_not_converged"]


def array_text(array, *, precision: int, suppress_small: bool | None = None) -> str:
    """An array as ``numpy.array2string`` prints it (numpy imported here: ``--help`` and refusals need none)."""
    import numpy as np

    return np.array2string(array, precision=precision, suppress_small=suppress_small)


def echo_terrain(reg) -> None:
    """The summary of a terrain registration (:class:`~seismo3d.terrain.TerrainRegistration`)."""
    r = reg.registration
    note = ""
    if reg.held_by_features:
        note = (f"  (the surfaces alone fix the horizontal position weakly; {reg.n_agreeing_matches} hillshade "
                "matches hold it)")
    elif r.degenerate:
        note = "  (DEGENERATE geometry)"
    typer.echo(f"rotation {reg.rotation_deg:.3f} deg (heading {reg.heading_deg:.3f})  fitness {r.fitness:.3f}  "
               f"inlier RMSE {r.inlier_rmse:.4g} {reg.frame.unit}  start {reg.start} ({reg.n_feature_inliers} of "
               f"{reg.n_matches} hillshade matches)  iterations {r.n_iterations}  converged {reg.converged}" + note)
    typer.echo(array_text(reg.transform, precision=6, suppress_small=True))


def why_not_converged(job) -> str:
    """Why a registration did not converge, and what to try, in the command's flags."""
    if job.kind == "volumes":
        return job.result.reason
    result = job.result.registration if job.kind == "terrain" else job.result
    if result.degenerate and job.kind == "terrain":
        if job.result.n_matches == 0:
            return ("the surfaces alone do not fix every direction (gentle or planar terrain) and no hillshade "
                    "matches were used; drop --method point_to_plane (fused is the default) or pass a closer --init")
        return ("the surfaces alone do not fix every direction (gentle or planar terrain) and too few hillshade "
                f"matches agree with the fit to hold it ({job.result.n_agreeing_matches}); check that the files "
                "overlap")
    if result.degenerate:
        return ("the geometry does not constrain every degree of freedom (a plane slides in itself); add --features "
                "with --method fused")
    return "it stopped on its iteration limit; check the overlap, or pass a closer --init"


def frames_tracked(summary: dict, max_frames: int | None) -> str:
    """'98 of 100 frames tracked', or for a run limited by --max-frames, '30 of the first 30 frames tracked
    (--max-frames 30; the sequence has 100)'."""
    tracked, total = summary["frames_tracked"], summary["frames_in_sequence"]
    if max_frames is None or max_frames >= total:
        return f"{tracked} of {total} frames tracked"
    return f"{tracked} of the first {max_frames} frames tracked (--max-frames {max_frames}; the sequence has {total})"
