"""Fault rendering (seismo3d.viz.faults): the pyvista scene off screen and the slice pictures of traced faults."""

import numpy as np
import pytest

from seismo3d.data.synthetic import synthetic_cube
from seismo3d.errors import InputError
from seismo3d.seismic import trace_faults


@pytest.fixture(scope="module")
def small_cube():
    syn = synthetic_cube((48, 48, 48), n_faults=2, seed=1)
    return syn.cube, trace_faults(syn.cube, progress=False)


@pytest.mark.slow
def test_show_faults_off_screen(small_cube, tmp_path):
    """VTK renders off screen here: the picture shows the slices (grey) and fault 1 in its tab10 blue."""
    from matplotlib.image import imread

    from seismo3d.viz.faults import show_faults

    cube, res = small_cube
    shot = tmp_path / "scene.png"
    show_faults(cube, res.faults, throws=res.throws, screenshot=shot, window_size=(400, 300))
    img = (imread(shot)[..., :3] * 255).round()
    assert img.shape == (300, 400, 3)
    blue = np.all(np.abs(img - [31, 119, 180]) < 60, axis=-1) & (img[..., 2] > img[..., 0] + 60)
    grey = (np.ptp(img, axis=-1) < 8) & (img.mean(axis=-1) < 200)
    assert blue.mean() > 0.01 and grey.mean() > 0.01
    with pytest.raises(InputError):
        show_faults(cube, res.faults, color_by="colour", screenshot=shot)


@pytest.mark.slow
@pytest.mark.parametrize("color_by", ["fault_id", "throw"])
def test_the_colour_bar_has_its_own_slot(small_cube, colour_bars, color_by, tmp_path):
    """The fault bar inside the window, its title and tick labels drawn inside its rectangle (main's pyvista
    default, 0.35-0.95 of the width and 0.05-0.13 of the height, drew 'fault id' above it)."""
    import seismo3d.viz.plotting as plotting
    from seismo3d.viz.faults import show_faults

    cube, res = small_cube
    bars = colour_bars(plotting, lambda: show_faults(cube, res.faults, throws=res.throws, color_by=color_by,
                                                     screenshot=tmp_path / "scene.png", window_size=(400, 300)))
    assert [title.strip() for title in bars] == [{"fault_id": "fault id"}.get(color_by, color_by)]


@pytest.mark.slow
def test_plot_fault_slices_arguments(small_cube, tmp_path):
    from seismo3d.viz.faults import plot_fault_slices

    cube, res = small_cube
    path = plot_fault_slices(cube, res.thin, path=tmp_path / "thin.png", slices=(10, 20, 30))
    assert path.read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(InputError, match="slices"):
        plot_fault_slices(cube, res.faults, path=tmp_path / "x.png", slices=(10, 20, 48))
    with pytest.raises(InputError, match="shape"):
        plot_fault_slices(cube, res.thin[:, :, :10], path=tmp_path / "x.png")
    with pytest.raises(InputError, match="does not exist"):
        plot_fault_slices(cube, res.faults, path=tmp_path / "no" / "x.png")
    assert not (tmp_path / "x.png").exists()


@pytest.mark.slow
def test_the_picture_s_title_names_the_faults_and_their_colouring(small_cube, tmp_path, monkeypatch):
    """faults.png's title: the input, the count and the colouring, without nested brackets (it read
    'demo_seismic: 3 faults (coloured by confidence (fault_summary.csv))')."""
    from matplotlib.figure import Figure

    from seismo3d.viz.faults import plot_fault_slices

    cube, res = small_cube
    titles = []
    suptitle = Figure.suptitle
    monkeypatch.setattr(Figure, "suptitle", lambda self, text, **kw: titles.append(text) or suptitle(self, text, **kw))
    values = {f.id: 0.5 + 0.1 * f.id for f in res.faults}
    plot_fault_slices(cube, res.faults, path=tmp_path / "f.png", title="cube", fault_values=values,
                      value_label="confidence (fault_summary.csv)")
    plot_fault_slices(cube, res.faults, path=tmp_path / "g.png")
    plot_fault_slices(cube, res.faults[:1], path=tmp_path / "h.png")
    n = len(res.faults)
    assert n > 1 and titles == [f"cube: {n} faults, coloured by confidence (fault_summary.csv)",
                                f"{n} faults, coloured by id", "1 fault, coloured by id"]


@pytest.mark.parametrize("label, title", [("time (ms)", "time slice 204 ms"), ("depth (m)", "depth slice 204 m"),
                                          ("sample", "sample slice 204")])
def test_the_time_slice_title_has_its_unit(label, title):
    from seismo3d.viz.faults import _slice_title

    assert _slice_title(label, 204.0) == title


def test_the_throw_colour_bar_says_when_it_clips():
    """Over 10 faults, colours by a value per fault span its 5th to 95th percentile; the bar's label then says so,
    with the least and largest values (its arrows: extend='both'), and the figure's title names the quantity without
    the note."""
    from seismo3d.viz.faults import _FaultColours

    ids = np.repeat(np.arange(1, 21), 3)
    skewed = _FaultColours(ids, {i: float(i) for i in range(1, 20)} | {20: 60.0}, "|median throw| (ms)")
    assert skewed.clipped and skewed.extend == "both"
    assert skewed.mappable.norm.vmin == pytest.approx(1.95) and skewed.mappable.norm.vmax == pytest.approx(21.05)
    assert skewed.label == "|median throw| (ms)\nclipped at the 5th-95th pct; values 1 to 60"
    assert skewed.title() == "faults, coloured by |median throw| (ms)"
    even = _FaultColours(ids, {i: 5.0 for i in range(1, 21)}, "|median throw| (ms)")
    assert not even.clipped and even.label == "|median throw| (ms)"
    assert not _FaultColours(ids, None, "value").clipped  # colours by id: no bar
    assert _FaultColours(np.zeros(0, np.int32), {}, "confidence").mappable is None  # no faults: no bar


def test_the_colours_spread_over_the_values_the_faults_have():
    """The confidences of the 5 faults traced on Teapot Dome line tp73 (0.52-0.95): the colour scale runs from the
    least to the largest, so that no fault is in a clipped colour and the colours differ (from 0 to the 95th
    percentile, 3 of the 5 sat in the top fifth of the colour map, the largest beyond it)."""
    from seismo3d.viz.faults import _FaultColours

    confidence = {1: 0.94949, 2: 0.73404, 3: 0.52402, 4: 0.80868, 5: 0.56657}
    colours = _FaultColours(np.arange(1, 6), confidence, "confidence")
    assert not colours.clipped and colours.extend == "neither"
    norm = colours.mappable.norm
    assert (norm.vmin, norm.vmax) == (0.52402, 0.94949)
    position = norm(np.array(list(confidence.values())))
    assert position.min() == 0.0 and position.max() == 1.0
    assert np.unique(colours.rgba.round(3), axis=0).shape[0] == 5


@pytest.mark.parametrize("value", [0.8637, -3.876, 0.0])
def test_one_fault_s_colour_bar_shows_its_value_only(value, tmp_path):
    """One fault (the Parihaka cube's): its colour scale is centred on its value within 5 % of it (0.5 for a 0),
    and the bar is labelled with that value alone (a scale from the value to the value + 1 drew a confidence bar up
    to 1.86)."""
    import matplotlib.pyplot as plt

    from seismo3d.viz.faults import _FaultColours

    colours = _FaultColours(np.ones(7, np.int32), {1: value}, "confidence")
    norm = colours.mappable.norm
    half = 0.05 * abs(value) if value else 0.5
    assert norm.vmin == pytest.approx(value - half) and norm.vmax == pytest.approx(value + half)
    assert norm(value) == pytest.approx(0.5) and not colours.clipped and colours.extend == "neither"
    fig, ax = plt.subplots()
    try:
        colours.bar(fig, ax)
        bar_ax = fig.axes[-1]
        assert [t.get_text() for t in bar_ax.get_yticklabels()] == [f"{value:.3g}"]
    finally:
        plt.close(fig)


@pytest.mark.parametrize("dead", [False, True])
def test_the_colour_limits_are_the_percentile_of_every_step_th_finite_sample(dead):
    """faults.png's grey scale: +- the 99th percentile of |amplitude| over every (size // 10^6)-th finite sample, with
    NaN (dead traces) left out before the samples are taken."""
    from seismo3d.viz.faults import _symmetric_limits

    data = np.random.default_rng(3).standard_t(3, size=(64, 64, 600)).astype(np.float32)  # 2.46 M: every 2nd
    if dead:
        data[5:9] = np.nan
    finite = data[np.isfinite(data)]
    clip = float(np.percentile(np.abs(finite[::2]), 99.0))
    assert _symmetric_limits(data, 99.0) == {"vmin": -clip, "vmax": clip}
