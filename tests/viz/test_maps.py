"""RGB-D map scenes (seismo3d.viz.maps) rendered off screen, and `seismo3d render` on a `seismo3d map` folder."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from seismo3d.cli import app
from seismo3d.jobs.map import write_ply
from seismo3d.mapping import TriangleMesh, write_tum_trajectory
from seismo3d.viz.maps import render_map

runner = CliRunner()


def _floor():
    """A 2 m x 2 m floor at y = 1 (cameras look along +z with -y up), as a triangle mesh of 20 x 20 quads."""
    g = np.linspace(-1.0, 1.0, 21)
    x, z = np.meshgrid(g, g + 2.0, indexing="ij")
    vertices = np.column_stack([x.ravel(), np.ones(x.size), z.ravel()])
    idx = np.arange(x.size).reshape(21, 21)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return TriangleMesh(vertices=vertices, faces=faces, normals=np.tile([0.0, -1.0, 0.0], (x.size, 1)))


def _poses(n=12):
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, 0, 3] = np.linspace(-0.5, 0.5, n)  # a sideways walk
    return poses


def _pixels(path):
    from matplotlib.image import imread

    return (imread(path)[..., :3] * 255).round()


def test_map_with_trajectory_and_keyframes(tmp_path):
    out = render_map(_floor(), _poses(), _poses()[::4], tmp_path / "map.png", window_size=(400, 300))
    img = _pixels(out)
    red = (img[..., 0] > 200) & (img[..., 1] < 60) & (img[..., 2] < 60)
    blue = (img[..., 2] > 200) & (img[..., 0] < 60) & (img[..., 1] < 60)
    assert red.mean() > 0.001 and blue.mean() > 0.001
    assert (img.min(axis=-1) < 250).mean() > 0.1  # the floor


@pytest.mark.slow
def test_map_with_its_reference_and_a_scale_bar(tmp_path):
    """The reference trajectory in green beside the red one, and a black scale bar of a round length (0.5 m on a
    2 m floor) labelled on the floor."""
    from seismo3d.viz.maps import _round_length

    assert [_round_length(e) for e in (2.0, 0.9, 7.0, 30.0)] == [0.5, 0.2, 1.0, 5.0]
    reference = _poses()
    reference[:, 2, 3] += 0.3  # 30 cm off, in the map's frame
    plain = _pixels(render_map(_floor(), _poses(), [], tmp_path / "plain.png", window_size=(400, 300)))
    img = _pixels(render_map(_floor(), _poses(), [], tmp_path / "map.png", window_size=(400, 300),
                             reference=reference))
    green = (img[..., 1] > 180) & (img[..., 0] < 100) & (img[..., 2] < 100)
    assert green.mean() > 0.002 and not ((plain[..., 1] > 180) & (plain[..., 0] < 100) & (plain[..., 2] < 100)).any()
    black = img[: int(0.7 * img.shape[0])].max(axis=-1) < 40  # above the colour bar's black labels
    assert black.sum() > 100  # the scale bar and its label


@pytest.mark.slow
@pytest.mark.parametrize("window_size", [(400, 300), (1280, 960)])
def test_the_colour_bar_has_its_own_slot(colour_bars, window_size, tmp_path):
    """The height bar inside the window, its title and tick labels drawn inside its rectangle (at the size of
    `seismo3d render` and of `seismo3d map`'s map.png)."""
    import seismo3d.viz.plotting as plotting
    from seismo3d.viz.maps import show_map

    bars = colour_bars(plotting, lambda: show_map(_floor(), _poses(), _poses()[::4], screenshot=tmp_path / "map.png",
                                                   window_size=window_size))
    assert [title.strip() for title in bars] == ["height (m)"]


@pytest.mark.slow
def test_render_a_map_folder(tmp_path):
    folder = tmp_path / "map"
    folder.mkdir()
    poses = _poses()
    write_ply(folder / "mesh.ply", _floor())
    write_tum_trajectory(folder / "trajectory.txt", np.arange(len(poses)) / 30.0, poses)
    graph = {"keyframes": [{"id": k, "pose": p.tolist()} for k, p in enumerate(poses[::4])]}
    (folder / "keyframes.json").write_text(json.dumps(graph))
    out = tmp_path / "map.png"
    res = runner.invoke(app, ["render", str(folder), "-o", str(out), "--size", "400x300"])
    assert res.exit_code == 0, res.output
    assert "441 mesh vertices, 12 camera poses, 3 keyframes" in res.stdout
    img = _pixels(out)
    assert ((img[..., 2] > 200) & (img[..., 0] < 60)).mean() > 0.001  # the keyframe pyramids
    (tmp_path / "empty").mkdir()
    res = runner.invoke(app, ["render", str(tmp_path / "empty"), "-o", str(tmp_path / "empty.png")])
    assert res.exit_code == 2 and "mesh.ply" in res.stderr
