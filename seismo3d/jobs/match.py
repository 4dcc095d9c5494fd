"""The ``seismo3d match`` job: match two images, verify the matches with a RANSAC homography and write them as CSV."""

from __future__ import annotations

import pathlib
from dataclasses import dataclass

import numpy as np

from ..errors import DataNotFoundError, InputError
from .outputs import check_outputs, output_file
from .runinfo import RunRecord, run_json_output, run_json_path

__all__ = ["MatchJob", "companion_files", "run_match_job", "read_image"]


@dataclass(frozen=True, eq=False)
class MatchJob:
    """What :func:`run_match_job` did.

    Attributes
    ----------
    result : MatchResult
        The verified matches and the homography (:func:`seismo3d.features.match_images`).
    n_written : int
        Matches written to the CSV file.
    output : pathlib.Path
        The CSV file.
    run_json : pathlib.Path
        The record of the run (:mod:`seismo3d.jobs.runinfo`).
    stage_seconds : dict
        Wall time of each stage (``read``, ``match``, ``write``).
    picture : pathlib.Path
        The matches drawn between the two images (``matches.png`` beside ``matches.csv``).
    homography_file : pathlib.Path
        The fitted homography as JSON (``matches.homography.json``).
    """

    result: object
    n_written: int
    output: pathlib.Path | None = None
    run_json: pathlib.Path | None = None
    stage_seconds: dict | None = None
    picture: pathlib.Path | None = None
    homography_file: pathlib.Path | None = None


def run_match_job(image1, image2, output, *, method: str = "hog", ratio: float = 0.8,
                  threshold: float = 3.0, overwrite: bool = False) -> MatchJob:
    """Match ``image1`` to ``image2``, verify with a RANSAC homography and write ``x1,y1,x2,y2,score`` rows.

    Pixel coordinates have their origin at the centre of the top-left pixel, x to the right, y down.

    Parameters
    ----------
    image1, image2 : str or path-like
        Images OpenCV can read (colour is converted to grey by the matcher).
    output : str or path-like
        The CSV file (written atomically); not an input, and not an existing file unless ``overwrite`` (see
        :mod:`seismo3d.jobs.outputs`; checked before the images are read). Beside it (:func:`companion_files`):
        ``<stem>.png``, the verified matches drawn between the two images, and ``<stem>.homography.json``, the
        fitted homography (under the same output policy).
    method : {'hog', 'sift', 'orb', 'akaze', 'brisk'}
        The HOG-pyramid matcher (method.md section 2) or an OpenCV detector.
    ratio : float
        Lowe's ratio-test threshold.
    threshold : float
        RANSAC inlier reprojection error, pixels.
    overwrite : bool
        Replace an existing ``output``.

    Returns
    -------
    MatchJob

    Raises
    ------
    DataNotFoundError
        An image file is missing.
    InputError
        An output that is an input, exists (without ``overwrite``) or cannot be written; a file OpenCV cannot read
        as an image, or a bad option.
    """
    record = RunRecord("match", locals())  # first: the arguments as called
    from ..features import match_images, write_matches_csv

    main = output_file(output, "matches.csv")
    picture, homography_file = companion_files(output)
    check_outputs([main, run_json_output(main), output_file(picture), output_file(homography_file)],
                  [image1, image2], overwrite=overwrite)
    with record.stage("read"):
        images = [read_image(p) for p in (image1, image2)]
    with record.stage("match"):
        result = match_images(*images, method=method, ratio=ratio, threshold=threshold, verify="homography")
    with record.stage("write"):
        n_written = write_matches_csv(output, result)
        homography = None if result.homography is None else np.asarray(result.homography)
        _write_homography(homography_file, homography, n_written)
        _draw_matches(picture, images, result, n_written, method)
    run_json = record.write(run_json_path(main), inputs={"image1": image1, "image2": image2},
                            outputs={"matches": output, "picture": picture, "homography": homography_file},
                            results=dict(n_putative=result.n_putative, n_verified=n_written, homography=homography))
    return MatchJob(result, n_written, pathlib.Path(output), run_json, dict(record.stage_seconds), picture,
                    homography_file)


def companion_files(output) -> tuple:
    """The picture and the homography file written beside the matches CSV ``output``.

    Parameters
    ----------
    output : str or os.PathLike
        The CSV, e.g. ``matches.csv``.

    Returns
    -------
    (pathlib.Path, pathlib.Path)
        ``matches.png`` (the matches drawn between the images) and ``matches.homography.json``.
    """
    output = pathlib.Path(output)
    picture = output.with_name(output.stem + ".png")
    if picture == output:
        picture = output.with_name(output.stem + "_matches.png")
    return picture, output.with_name(output.stem + ".homography.json")


def _write_homography(path: pathlib.Path, homography, n_verified: int) -> None:
    """The fitted homography as JSON: ``homography`` (3 x 3, image1 pixel (x, y, 1) to image2's; null when none
    could be fitted) and the number of verified matches that support it."""
    import json

    from .._atomic import atomic_path

    payload = {"homography": None if homography is None else homography.tolist(),
               "maps": "image1 pixel (x, y, 1) -> image2 pixel, x right, y down", "n_verified": int(n_verified)}
    with atomic_path(path) as tmp:
        tmp.write_text(json.dumps(payload, indent=2) + "\n")


def _draw_matches(path: pathlib.Path, images, result, n_verified: int, method: str) -> None:
    """The verified matches drawn between the two images side by side (:func:`seismo3d.viz.plot_matches`): a spread
    of them, the best-scored (Lowe's ratio) in each cell of a grid over the first image."""
    from .._atomic import atomic_path
    from ..viz import plot_matches

    keep = np.arange(len(result.scores))
    if getattr(result, "inliers", None) is not None:
        keep = keep[np.asarray(result.inliers, bool)]
    keep = keep[np.argsort(-np.asarray(result.scores)[keep], kind="stable")]  # best first: the one drawn per cell
    fig = plot_matches(images[0], images[1], np.asarray(result.xy1)[keep], np.asarray(result.xy2)[keep],
                       title=f"{n_verified} verified matches of {result.n_putative} putative ({method}, RANSAC "
                             "homography)")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)


def read_image(path) -> np.ndarray:
    """An image file as an (H, W) or (H, W, 3) RGB uint8 array (OpenCV; alpha dropped).

    Raises
    ------
    DataNotFoundError
        No such file.
    InputError
        OpenCV cannot read it as an image.
    """
    import cv2

    path = pathlib.Path(path)
    if not path.is_file():
        raise DataNotFoundError(f"{path}: no such file; check the path")
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if image is None:
        raise InputError(f"{path} is not an image OpenCV can read (PNG, JPEG, TIFF, BMP, PPM/PGM)")
    if image.ndim == 3:
        image = cv2.cvtColor(image, cv2.COLOR_BGRA2RGB if image.shape[2] == 4 else cv2.COLOR_BGR2RGB)
    return image
