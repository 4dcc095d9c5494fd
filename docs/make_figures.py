"""Make the pictures of the documentation from the real data of the data folder, with the ``seismo3d`` command.

Run from the repository's root (a few minutes on 2 cores; the faults of Penobscot crossline 1155 take the longest):

    SEISMO3D_DATA_DIR=../shared/data python docs/make_figures.py [--work DIR] [NAME ...]

Each picture is made by the command a user would run, in a work folder (default: a temporary one), then copied into
``docs/figures/``. NAME picks some of them (see ``FIGURES``). The data are never copied into the repository.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

FIGURES_DIR = Path(__file__).resolve().parent / "figures"


def _data() -> Path:
    folder = os.environ.get("SEISMO3D_DATA_DIR")
    if not folder or not Path(folder).is_dir():
        sys.exit("set SEISMO3D_DATA_DIR to the data folder (see docs/data.md)")
    return Path(folder)


def _seismo3d(*args) -> None:
    """Run one ``seismo3d`` command (this checkout's code), failing loudly."""
    command = [sys.executable, "-m", "seismo3d.cli", *map(str, args)]
    print("$ seismo3d", " ".join(map(str, args)), flush=True)
    subprocess.run(command, check=True)


MAX_WIDTH = 960  # pixels: pictures in the documentation are at most this wide


def _copy(source: Path, name: str) -> None:
    """Copy a picture into docs/figures, at most MAX_WIDTH pixels wide and with at most 256 colours (a few hundred
    kB each: the folder stays under 3 MB)."""
    from PIL import Image

    FIGURES_DIR.mkdir(exist_ok=True)
    with Image.open(source) as image:
        image = image.convert("RGB")
        if image.width > MAX_WIDTH:
            image = image.resize((MAX_WIDTH, round(image.height * MAX_WIDTH / image.width)), Image.LANCZOS)
        image.quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(
            FIGURES_DIR / name, optimize=True)
    print(f"  -> docs/figures/{name} ({(FIGURES_DIR / name).stat().st_size // 1000} kB)", flush=True)


def faults_xl1155(data: Path, work: Path) -> None:
    """Faults of Penobscot crossline 1155: faults.png and the section with its faults (render)."""
    out = work / "xl1155"
    if not (out / "faults.vtp").is_file():
        _seismo3d("faults", data / "seismic" / "penobscot_xl1155.sgy", "-o", out)
    _copy(out / "faults.png", "faults_xl1155.png")
    _seismo3d("render", out, "-o", work / "xl1155_section.png", "--overwrite")
    _copy(work / "xl1155_section.png", "render_xl1155_faults.png")
    _seismo3d("render", out, "-o", work / "xl1155_throw.png", "--color-by", "throw", "--overwrite")
    _copy(work / "xl1155_throw.png", "render_xl1155_throw.png")


def faults_demo(data: Path, work: Path) -> None:  # noqa: ARG001 - generated data
    """The quick start's demo: faults.png and the 3D scene of its faults over the seismic."""
    out = work / "faults_demo"
    if not (out / "faults.vtp").is_file():
        _seismo3d("faults", "--demo", "-o", out)
    _copy(out / "faults.png", "faults_demo.png")
    _seismo3d("render", out, "-o", work / "faults_demo_3d.png", "--overwrite")
    _copy(work / "faults_demo_3d.png", "render_faults_demo_3d.png")


def _run_guide_example(page: str, marker: str, work: Path) -> None:
    """Run the Python block of ``docs/guide/<page>`` that holds ``marker`` in ``work``, as the page prints it (the
    suite runs the same block: tests/test_docs.py), so that the picture is the page's own run."""
    import re

    text = (Path(__file__).resolve().parent / "guide" / page).read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M) if marker in b]
    if len(blocks) != 1:
        sys.exit(f"docs/guide/{page} has {len(blocks)} Python blocks with {marker!r}; expected one")
    print(f"$ python  # the block of docs/guide/{page} with {marker}", flush=True)
    here = Path.cwd()
    os.chdir(work)
    try:
        exec(compile(blocks[0], f"{page}[{marker}]", "exec"), {"__name__": "__docs__"})  # noqa: S102 - the docs' own
    finally:
        os.chdir(here)


def faults_parihaka(data: Path, work: Path) -> None:  # noqa: ARG001 - the guide's example reads it
    """The faults guide's real cube: the Parihaka example's faults.png."""
    _run_guide_example("faults.md", "load_parihaka_timeslices", work)
    _copy(work / "parihaka_faults" / "faults.png", "faults_parihaka.png")


def cube_f3(data: Path, work: Path) -> None:
    """The F3 crop in 3D with its geometry."""
    _seismo3d("render", data / "seismic" / "f3_crop.sgy", "-o", work / "f3_crop.png", "--overwrite")
    _copy(work / "f3_crop.png", "render_f3_crop.png")


def horizon_xl1155(data: Path, work: Path) -> None:
    """A horizon tracked along Penobscot crossline 1155 from one seed, over the section."""
    line = data / "seismic" / "penobscot_xl1155.sgy"
    _seismo3d("horizon", line, "--seed", "1300,1155,2040", "-o", work / "xl1155_horizon.txt", "--overwrite")
    _seismo3d("render", work / "xl1155_horizon.txt", "--seismic", line, "-o", work / "xl1155_horizon.png",
              "--overwrite")
    _copy(work / "xl1155_horizon.png", "render_xl1155_horizon.png")


def terrain(data: Path, work: Path) -> None:
    """The DFW DEM in 3D with its lineaments, their rose diagram and map, and a path planned over it."""
    dem = data / "terrain" / "dem_hydrosheds_dfw.tif"
    _seismo3d("render", dem, "--lineaments", "-o", work / "dem.png", "--overwrite")
    _copy(work / "dem.png", "render_dem_lineaments.png")
    _seismo3d("lineaments", dem, "-o", work / "lineaments", "--overwrite")
    _copy(work / "lineaments" / "rose.png", "lineaments_rose.png")
    _copy(work / "lineaments" / "lineaments.png", "lineaments_map.png")
    _seismo3d("plan", dem, "--start", "40,40", "--goal", "300,320", "--max-slope", "3", "-o", work / "path.csv",
              "--overwrite")
    _seismo3d("render", dem, "--path", work / "path.csv", "-o", work / "dem_path.png", "--overwrite")
    _copy(work / "dem_path.png", "render_dem_path.png")


def match_tum(data: Path, work: Path) -> None:
    """HOG-pyramid matches between two real TUM fr1/xyz frames."""
    pair = data / "rgbd" / "tum_fr1xyz_pair"
    _seismo3d("match", pair / "img_prev.png", pair / "img_curr.png", "-o", work / "matches.csv", "--overwrite")
    _copy(work / "matches.png", "match_tum.png")


def mapping(data: Path, work: Path) -> None:
    """The mapping loop on the first 30 frames of the 7-Scenes kitchen."""
    _seismo3d("map", data / "rgbd" / "7scenes_redkitchen_0000_0495", "-o", work / "kitchen", "--max-frames", "30",
              "--overwrite")
    _copy(work / "kitchen" / "map.png", "map_7scenes.png")


def volumes_f3(data: Path, work: Path) -> None:  # noqa: ARG001 - the guide's example makes it
    """The sub-volume guide's example: a part of the F3 crop, stretched in time, registered back onto it."""
    import numpy as np

    from seismo3d.seismic import open_segy, register_volumes, resample_volume
    from seismo3d.viz import plot_volume_registration

    with open_segy(data / "seismic" / "f3_crop.sgy") as cube:
        fixed = np.asarray(cube.read(), dtype=np.float32)
        inlines, xlines, samples = cube.inlines, cube.xlines, cube.samples
    stretch = np.eye(4)
    stretch[2, 2], stretch[:3, 3] = 1.25, (-3, -2, -6)
    moving = resample_volume(fixed, stretch, (18, 15, 80))
    result = register_volumes(fixed, moving)
    plot_volume_registration(fixed, moving, resample_volume(moving, result.transform_index, fixed.shape),
                             path=work / "volumes_f3.png", inline=11, xlines=xlines, samples=samples,
                             sample_unit="ms", inline_number=inlines[11])
    _copy(work / "volumes_f3.png", "volumes_f3.png")


FIGURES = {"faults_xl1155": faults_xl1155, "faults_demo": faults_demo, "faults_parihaka": faults_parihaka,
           "cube_f3": cube_f3,
           "horizon_xl1155": horizon_xl1155, "volumes_f3": volumes_f3, "terrain": terrain, "match_tum": match_tum, "mapping": mapping}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("names", nargs="*", help=f"pictures to make, of {', '.join(FIGURES)} (default: all)")
    parser.add_argument("--work", type=Path, help="work folder kept between runs (default: a temporary one)")
    args = parser.parse_args(argv)
    unknown = sorted(set(args.names) - set(FIGURES))
    if unknown:
        parser.error(f"unknown pictures {unknown}; choose from {', '.join(FIGURES)}")
    data = _data()
    with tempfile.TemporaryDirectory() as tmp:
        work = args.work or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        for name in args.names or FIGURES:
            FIGURES[name](data, work)


if __name__ == "__main__":
    main()
