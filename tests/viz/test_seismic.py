"""The 3D seismic scene (seismo3d.viz.seismic): geometry from headers, the grid, and pictures rendered off screen."""

import numpy as np
import pytest
from numpy.testing import assert_allclose

from seismo3d.errors import InputError, Seismo3dWarning
from seismo3d.seismic import Fault
from seismo3d.viz.geometry import cube_geometry, grid_index, place_index_mesh, seismic_grid
from seismo3d.viz.seismic import show_seismic

SHAPE = (24, 32, 40)


def _cube():
    """Dipping layers: sin of (sample - 0.3 * inline)."""
    i, _, k = np.meshgrid(*(np.arange(n) for n in SHAPE), indexing="ij")
    return np.sin(2 * np.pi * (k - 0.3 * i) / 8.0).astype(np.float32)


def _fault():
    """A vertical fault on the plane inline index = 12 + 0.2 * crossline index (one sample per crossline and
    sample), facing the default (iso) camera."""
    j, k = np.meshgrid(np.arange(SHAPE[1]), np.arange(SHAPE[2]), indexing="ij")
    pts = np.column_stack([np.round(12 + 0.2 * j.ravel()), j.ravel(), k.ravel()]).astype(np.int64)
    n = pts.shape[0]
    z = np.zeros(n, np.float32)
    return Fault(id=1, points=pts, likelihood=np.ones(n, np.float32), strike_deg=z, dip_deg=z + 90,
                 normals=np.tile(np.float32([1, 0, 0]), (n, 1)))


def _survey(rotation_deg=30.0):
    """CDP X/Y of a survey rotated by ``rotation_deg``: 25 m inline bins, 12.5 m crossline bins."""
    t = np.deg2rad(rotation_deg)
    ii, jj = np.meshgrid(np.arange(SHAPE[0]), np.arange(SHAPE[1]), indexing="ij")
    x = 500_000 + 25 * ii * np.cos(t) - 12.5 * jj * np.sin(t)
    y = 6_000_000 + 25 * ii * np.sin(t) + 12.5 * jj * np.cos(t)
    return x, y


def _pixels(path):
    from matplotlib.image import imread

    return (imread(path)[..., :3] * 255).round()


@pytest.mark.parametrize("rotation", [30.0, -120.0])
def test_grid_places_every_sample_at_its_cdp_and_time(rotation):
    cube = _cube()
    x, y = _survey(rotation)
    samples = 1000.0 + 4.0 * np.arange(SHAPE[2])
    geo = cube_geometry(SHAPE, inlines=np.arange(1000, 1024), xlines=np.arange(2000, 2032), samples=samples,
                        sample_unit="ms", cdp_x=x, cdp_y=y, vertical_exaggeration=3.0)
    assert geo.map_unit == "m"
    assert_allclose(np.linalg.norm(geo.axes[:2, :2], axis=1), [25.0, 12.5], rtol=1e-9)
    assert_allclose(geo.axes[2], [0, 0, -4.0 * 3.0])  # 4 ms = 4 m at 2000 m/s two-way, times 3, downward
    grid = seismic_grid(cube, geo)
    pts = np.asarray(grid.points)
    for ijk in [(0, 0, 0), (5, 17, 3), (23, 31, 39), (11, 0, 20)]:
        world = geo.to_world(ijk)[0]
        assert_allclose(world[:2], [x[ijk[:2]], y[ijk[:2]]], atol=1e-6)
        assert_allclose(world[2], -(samples[ijk[2]] / 4.0) * 12.0, atol=1e-6)
        n = int(np.argmin(np.linalg.norm(pts - world, axis=1)))
        assert np.linalg.norm(pts[n] - world) < 1e-6
        assert grid.point_data["amplitude"][n] == cube[ijk]
        assert grid.point_data["time_or_depth"][n] == samples[ijk[2]]
        assert grid.point_data["inline"][n] == 1000 + ijk[0]
        assert np.ravel_multi_index(grid_index(geo, ijk), SHAPE, order="F") == n
    assert np.linalg.det(np.asarray(grid.direction_matrix)) > 0  # VTK's volume rendering needs a rotation


def test_geometry_without_coordinates_and_automatic_exaggeration():
    geo = cube_geometry(SHAPE, inlines=np.arange(100, 124), xlines=np.arange(10, 74, 2))
    assert geo.map_unit == "line"
    assert_allclose(geo.to_world([(2, 3, 0)]), [[102, 16, 0]])
    height = -geo.to_world([(0, 0, SHAPE[2] - 1)])[0, 2]
    assert height == pytest.approx(0.5 * 62, rel=0.02)  # half the longer side (62 crossline units)
    assert "vertical exaggeration" in geo.describe()


def test_irregular_coordinates_fall_back_to_lines_with_a_warning():
    x, y = _survey()
    x = x + np.random.default_rng(0).normal(0, 20, x.shape)
    with pytest.warns(Seismo3dWarning, match="regular grid"):
        geo = cube_geometry(SHAPE, cdp_x=x, cdp_y=y)
    assert geo.map_unit == "line"


def test_index_meshes_move_with_the_geometry():
    import pyvista as pv

    geo = cube_geometry(SHAPE, inlines=np.arange(1, 25), samples=np.arange(40) * 2.0, sample_unit="m",
                        vertical_exaggeration=2.0)
    mesh = place_index_mesh(pv.PolyData(np.array([[3.0, 4.0, -5.0]])), geo)
    assert_allclose(mesh.points, [[4.0, 4.0, -5.0 * 2.0]])  # inline number 4; 5 samples (one unit each) times 2


def test_bad_inputs_are_refused():
    with pytest.raises(InputError, match="xlines"):
        cube_geometry(SHAPE, xlines=np.arange(5))
    with pytest.raises(InputError, match="vertical_exaggeration"):
        cube_geometry(SHAPE, vertical_exaggeration=0.0)
    with pytest.raises(InputError, match="shape"):
        seismic_grid(np.zeros((2, 2, 2)), cube_geometry(SHAPE))


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("scenes")


@pytest.mark.slow
def test_slices_in_the_seismic_colours(scene_dir):
    shot = scene_dir / "slices.png"
    show_seismic(_cube(), screenshot=shot, window_size=(320, 240))
    img = _pixels(shot)
    assert img.shape == (240, 320, 3)
    red = (img[..., 0] > 150) & (img[..., 1] < 60) & (img[..., 2] < 60)
    blue = (img[..., 2] > 150) & (img[..., 0] < 60) & (img[..., 1] < 60)
    assert red.mean() > 0.02 and blue.mean() > 0.02
    assert (img.min(axis=-1) < 250).mean() > 0.15  # not blank: the white background covers under 85 %


@pytest.mark.slow
def test_faults_by_id_and_by_throw(scene_dir):
    from seismo3d.seismic import FaultThrow

    shot = scene_dir / "faults.png"
    show_seismic(_cube(), faults=[_fault()], slices=(None, None, 30), cmap="gray", screenshot=shot,
                 window_size=(320, 240))
    img = _pixels(shot)
    blue = (img[..., 2] > 80) & (img[..., 2] > img[..., 0] + 50)  # fault 1 in tab10 blue (31, 119, 180), shaded
    assert blue.mean() > 0.01
    with pytest.raises(InputError, match="throws"):
        show_seismic(_cube(), faults=[_fault()], color_faults_by="throw", screenshot=shot)
    n = _fault().size
    throw = FaultThrow(fault_id=1, throw=np.full(n, 5.0, np.float32), registered=np.ones(n, bool),
                       correlation=np.ones(n, np.float32), correlation_unshifted=np.zeros(n, np.float32),
                       median_throw=5.0, fitness=1.0, inlier_rmse=0.0,
                       n_points_used=n)
    show_seismic(_cube(), faults=[_fault()], throws=[throw], color_faults_by="throw", slices=(None, None, 30),
                 cmap="gray", screenshot=shot, window_size=(320, 240))
    img = _pixels(shot)
    # PuOr_r at +5 samples: orange, blended at the faults' 60 % opacity with the grey slice and white behind it
    brown = (img[..., 0] > img[..., 2] + 40) & (img[..., 1] > img[..., 2] + 10)
    assert brown.mean() > 0.01


def test_horizons_coloured_by_time(scene_dir):
    shot = scene_dir / "horizons.png"
    ii, jj = np.meshgrid(np.arange(SHAPE[0]), np.arange(SHAPE[1]), indexing="ij")
    shallow = 8.0 + 0.1 * ii
    deep = 30.0 + 0.05 * jj
    deep[:6, :6] = np.nan
    geo = cube_geometry(SHAPE, samples=4.0 * np.arange(SHAPE[2]), sample_unit="ms")
    show_seismic(_cube(), geo, slices=(None, None, None), horizons=[shallow, deep], screenshot=shot,
                 window_size=(320, 240))
    img = _pixels(shot)
    purple = (img[..., 2] > img[..., 1] + 30) & (img[..., 0] > img[..., 1])  # viridis low end (68, 1, 84)
    yellow = (img[..., 0] > 150) & (img[..., 1] > 150) & (img[..., 2] < 90)  # viridis high end (253, 231, 37)
    assert purple.mean() > 0.01 and yellow.mean() > 0.01


@pytest.mark.slow
def test_fault_likelihood_volume(scene_dir):
    shot = scene_dir / "likelihood.png"
    ii, jj, _ = np.meshgrid(*(np.arange(n) for n in SHAPE), indexing="ij")
    likelihood = np.exp(-((ii - 0.7 * jj) ** 2) / 4.0)
    show_seismic(_cube(), slices=(None, None, None), likelihood=likelihood, likelihood_threshold=0.5,
                 screenshot=shot, window_size=(320, 240))
    img = _pixels(shot)
    dark = img.max(axis=-1) < 120  # Greys at likelihood 1: black
    assert dark.mean() > 0.005
    with pytest.raises(InputError, match="likelihood_threshold"):
        show_seismic(_cube(), likelihood=likelihood, likelihood_threshold=1.5, screenshot=shot)


def test_slices_out_of_range_and_missing_folder(tmp_path):
    with pytest.raises(InputError, match="outside"):
        show_seismic(_cube(), slices=(99, 0, 0), screenshot=tmp_path / "x.png")
    with pytest.raises(InputError, match="does not exist"):
        show_seismic(_cube(), screenshot=tmp_path / "missing" / "x.png")


@pytest.mark.slow
def test_sliders_move_the_planes(tmp_path):
    """With sliders the scene renders the planes and three slider widgets; moving a slider replaces its plane by
    the one at the new index (the widget's callback, called as VTK would)."""
    show_seismic(_cube(), sliders=True, screenshot=tmp_path / "sliders.png", window_size=(320, 240))
    img = _pixels(tmp_path / "sliders.png")
    red = (img[..., 0] > 150) & (img[..., 1] < 60) & (img[..., 2] < 60)
    assert red.mean() > 0.02

    import pyvista as pv

    from seismo3d.viz.seismic import _add_slices  # the slider wiring itself

    geo = cube_geometry(SHAPE)
    grid = seismic_grid(_cube(), geo)
    pl = pv.Plotter(off_screen=True)
    _add_slices(pl, grid, geo, (3, None, None), cmap="gray", clim=(-1, 1), sliders=True)
    slider = getattr(pl, "widgets", pl).slider_widgets[0]  # pyvista >= 0.47 groups the widgets
    slider.GetRepresentation().SetValue(20.0)
    slider.InvokeEvent("EndInteractionEvent")  # pyvista calls back when the slider is released
    plane = pl.actors["inline"].mapper.dataset
    np.testing.assert_allclose(np.unique(np.asarray(plane.points)[:, 0]), geo.to_world([(20, 0, 0)])[0, 0])
    pl.close()


def _line():
    """One crossline of the dipping layers: (24, 1, 40)."""
    return _cube()[:, :1, :]


def _coloured(img):
    """Pixels of a colour (not grey, black or white): the grey seismic and the black text have none."""
    return (np.abs(img[..., 0] - img[..., 1]) > 40) | (np.abs(img[..., 1] - img[..., 2]) > 40)


@pytest.mark.slow
def test_a_horizon_on_a_line_is_drawn_over_its_section(scene_dir):
    """A horizon on one line is a curve (horizon_surface joins its picks), drawn over the section seen square on."""
    shot = scene_dir / "line_horizon.png"
    show_seismic(_line(), horizons=[np.full((SHAPE[0], 1), 20.0)], cmap="gray", camera="section", screenshot=shot,
                 window_size=(320, 240))
    img = _pixels(shot)
    rows, cols = np.nonzero(_coloured(img)[: int(0.8 * 240), : int(0.8 * 320)])  # left of the bar, above the widget
    assert rows.size > 100
    assert np.ptp(cols) > 0.3 * 320 and np.ptp(rows) <= 12  # a flat curve across the section


@pytest.mark.slow
def test_fault_ids_and_amplitudes_in_bars_below_the_scene(scene_dir):
    """No legend box over the data: fault ids and amplitudes are colour bars in the band below the scene."""
    shot = scene_dir / "bars.png"
    show_seismic(_cube(), faults=[_fault()], slices=(None, None, 30), screenshot=shot, window_size=(400, 300))
    img = _pixels(shot)
    band = img[int(0.82 * 300):]
    fault_bar, amplitude_bar = band[:, int(0.62 * 400):int(0.93 * 400)], band[:, int(0.24 * 400):int(0.54 * 400)]
    tab10_blue = (np.abs(fault_bar - [31, 119, 180]) < 25).all(axis=-1)
    assert tab10_blue.mean() > 0.01  # fault 1's colour in the fault-id bar
    red = (amplitude_bar[..., 0] > 150) & (amplitude_bar[..., 2] < 80)
    blue = (amplitude_bar[..., 2] > 150) & (amplitude_bar[..., 0] < 80)
    assert red.mean() > 0.01 and blue.mean() > 0.01  # the seismic colour map, both ends
    corner = img[: int(0.3 * 300), int(0.8 * 400):]
    assert not (np.abs(corner - [31, 119, 180]) < 25).all(axis=-1).any()  # no legend swatch top right


def test_the_orientation_widget_arrow_points_up_and_says_so():
    assert cube_geometry(SHAPE, sample_unit="ms").axis_labels() == ("inline", "crossline", "up")
    trace_list = cube_geometry((10, 1, 20), lateral_names=("trace", ""), samples=4.0 * np.arange(20), sample_unit="ms")
    assert trace_list.axis_labels()[0] == "trace"
    assert trace_list.describe().startswith("traces 0-9, time 0-76 ms (down)")


def test_the_lateral_numbers_stay_clear_of_the_corner_they_share():
    """The f3_crop scene (X 620182-620622 m, Y 6074233-6074795 m): round numbers every 100 m on the two lateral
    edges nearest the camera, none within 8 % of an edge's ends, so that X's and Y's numbers do not run into each
    other at the box's front corner (VTK labelled both ends of both axes: '6074795' and '620622' overlapped)."""
    from seismo3d.viz.seismic import _lateral_ticks

    class Recorder:
        def __init__(self):
            self.labels, self.ticks = [], []

        def add_points(self, points, **kw):
            self.ticks.append(np.asarray(points))

        def add_point_labels(self, points, labels, **kw):
            self.labels.append((np.asarray(points), list(labels)))

    lo, hi = np.array([620182.0, 6074233.0, -300.0]), np.array([620622.0, 6074795.0, -4.0])
    eye = np.array([621500.0, 6075600.0, 400.0])  # in front of the (hi, hi) corner, above
    plotter = Recorder()
    _lateral_ticks(plotter, lo, hi, ((lo[0], hi[0]), (lo[1], hi[1])), eye, np.array([1.0, -1.0, 0.0]))
    (x_at, x_labels), (y_at, y_labels) = plotter.labels
    assert x_labels == ["620300", "620400", "620500"]
    assert y_labels == ["6074300", "6074400", "6074500", "6074600", "6074700"]
    np.testing.assert_allclose(plotter.ticks[0][:, 1], hi[1])  # X's ticks on the front edge (y = max) ...
    np.testing.assert_allclose(plotter.ticks[1][:, 0], hi[0])  # ... and Y's on the other front edge (x = max)
    corner = hi[:2]
    for at, span in ((x_at[:, :2], hi[0] - lo[0]), (y_at[:, :2], hi[1] - lo[1])):
        assert np.linalg.norm(at - corner, axis=1).min() > 0.08 * span


def _bar_layout(monkeypatch, **scene):
    """The scene's colour bars as (title, (x0, y0, x1, y1)) in viewport fractions, and the box's 8 corners in them,
    read when the scene is finished (before the plotter is closed)."""
    import seismo3d.viz.seismic as seismic

    found = {}

    def record(plotter, **kw):
        found["bars"] = [(title, (*bar.GetPosition(), *np.add(bar.GetPosition(), bar.GetPosition2())))
                         for title, bar in plotter.scalar_bars.items()]
        width, height = plotter.window_size
        corners = []
        for p in seismic._outline(scene.get("geometry") or cube_geometry(SHAPE)).points:
            plotter.renderer.SetWorldPoint(*p, 1.0)
            plotter.renderer.WorldToDisplay()
            x, y, _ = plotter.renderer.GetDisplayPoint()
            corners.append((x / width, y / height))
        found["corners"] = np.array(corners)
        plotter.close()
        return plotter

    monkeypatch.setattr(seismic, "finish_scene", record)
    seismic.show_seismic(_cube(), window_size=(900, 650), **scene)
    return found["bars"], found["corners"]


def _throw():
    from seismo3d.seismic import FaultThrow

    n = _fault().size
    return FaultThrow(fault_id=1, throw=np.linspace(-5, 5, n).astype(np.float32), registered=np.ones(n, bool),
                      correlation=np.ones(n, np.float32), correlation_unshifted=np.zeros(n, np.float32),
                      median_throw=0.0, fitness=1.0, inlier_rmse=0.0, n_points_used=n)


_LIKELIHOOD = np.exp(-((np.arange(SHAPE[0])[:, None, None] - 0.7 * np.arange(SHAPE[1])[None, :, None]) ** 2) / 4.0
                     + np.zeros(SHAPE))


@pytest.mark.parametrize("scene", [
    dict(faults=[_fault()], horizons=[np.full(SHAPE[:2], 20.0)], likelihood=_LIKELIHOOD),  # notebook 01's first
    dict(faults=[_fault()], throws=[_throw()], color_faults_by="throw", cmap="gray"),  # and its second
    dict(faults=[_fault()], throws=[_throw()], color_faults_by="throw", horizons=[np.full(SHAPE[:2], 20.0)],
         likelihood=_LIKELIHOOD, geometry=cube_geometry(SHAPE, samples=1000 + 4.0 * np.arange(SHAPE[2]),
                                                        sample_unit="ms")),
], ids=["ids-horizon-likelihood", "throw", "throw-horizon-likelihood-ms"])
def test_every_colour_bar_has_its_own_slot(monkeypatch, scene):
    """Notebook 01's scenes: no two colour bars' rectangles (pyvista's scalar bar actors: position and size in
    viewport units, each sized by VTK's measure of its title and labels) overlap, all are inside the window, and no
    corner of the cube's box falls in one (main had the horizon's bar at x 0.84-0.92 over the likelihood's at
    0.90-0.98, and the throw bar's title over the box's inline edge)."""
    bars, corners = _bar_layout(monkeypatch, **scene)
    assert len(bars) == 2 + ("horizons" in scene) + ("likelihood" in scene)
    for n, (title, (x0, y0, x1, y1)) in enumerate(bars):
        assert 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1, title
        for other, (u0, v0, u1, v1) in bars[n + 1:]:
            overlap = min(x1, u1) - max(x0, u0), min(y1, v1) - max(y0, v0)
            assert min(overlap) <= 0, f"{title!r} and {other!r} overlap by {overlap}"
        inside = (corners[:, 0] > x0) & (corners[:, 0] < x1) & (corners[:, 1] > y0) & (corners[:, 1] < y1)
        assert not inside.any(), f"the box's corners {corners[inside]} are in {title!r}'s bar"



@pytest.mark.slow
@pytest.mark.parametrize("scene", [
    dict(color_faults_by="throw", likelihood=_LIKELIHOOD),  # notebook 01's second scene, and a likelihood bar
    dict(color_faults_by="fault_id"),  # the fault-id bar draws no tick labels (no volume: a cheaper render)
], ids=["throw-likelihood", "fault_id"])
def test_every_colour_bar_draws_its_text_in_its_slot(colour_bars, scene, tmp_path):
    """Notebook 01's scenes seen on screen (tests/viz/conftest.py): each bar's title drawn inside its rectangle,
    labels inside the window and apart, no bar's text over another's, the first render final, the cube clear of
    the bars and filling the room they leave."""
    import seismo3d.viz.seismic as seismic

    bars = colour_bars(seismic, lambda: show_seismic(_cube(), screenshot=tmp_path / "scene.png", window_size=(900, 650),
                                                     faults=[_fault()], throws=[_throw()],
                                                     horizons=[np.full(SHAPE[:2], 20.0)], **scene))
    assert len(bars) == 3 + ("likelihood" in scene)  # amplitude, fault id or throw, horizon (, likelihood)
