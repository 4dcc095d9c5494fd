"""A seismic line as a section (seismo3d.viz.sections): the vertical exaggeration, labelled axes, faults as lines."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.viz import plot_section, section_exaggeration


@pytest.mark.parametrize("n_traces, spacing, height, expected", [
    (601, 12.5, 6000.0, 1.0),   # Penobscot crossline 1155: 7.5 km by 6 km, never squashed below 1x
    (400, 25.0, 1000.0, 5.0),   # 10 km by 1 km: 5.5x rounds to 5x
    (200, 25.0, 2000.0, 1.5),   # 5 km by 2 km: 1.4x rounds to 1.5x
    (5000, 25.0, 100.0, 20.0),  # very long and shallow: capped at 20x
])
def test_exaggeration_is_a_round_factor(n_traces, spacing, height, expected):
    assert section_exaggeration(n_traces, spacing, height) == expected


def _section():
    """(80, 120): dipping reflectors, offset by a fault at trace 40."""
    traces, samples = np.mgrid[0:80, 0:120].astype(float)
    shift = np.where(traces > 40, 6.0, 0.0)
    return np.sin(2 * np.pi * (samples - 0.2 * traces - shift) / 12.0).astype(np.float32)


@pytest.mark.slow
def test_section_with_faults_and_horizon(tmp_path):
    import pyvista as pv
    from matplotlib.image import imread

    k = np.arange(10, 110, dtype=float)
    fault = pv.PolyData(np.column_stack([40 + 0.1 * (k - 10), np.zeros_like(k), -k]),
                        lines=np.concatenate([[k.size], np.arange(k.size)]))
    fault.point_data["fault_id"] = np.full(k.size, 1)
    caption = plot_section(_section(), path=tmp_path / "s.png", traces=np.arange(1000, 1080),
                           samples=4.0 * np.arange(120), trace_name="inline", sample_unit="ms", trace_spacing=25.0,
                           faults=fault, horizon=np.full(80, 30.0), width=6.0, dpi=100)
    # 1975 m along, 476 ms (476 m at 2000 m/s) down: 2.3x makes it about half as tall as wide, rounded to 2x
    assert caption == "inlines 1000-1079, time 0-476 ms, vertical exaggeration 2x (time as depth at 2000 m/s)"
    img = (imread(tmp_path / "s.png")[..., :3] * 255).round()
    assert img.shape[1] == 600
    blue = (img[..., 2] > 150) & (img[..., 0] < 80)  # fault 1 in tab10 blue, a line over the section
    yellow = (img[..., 0] > 200) & (img[..., 1] > 150) & (img[..., 2] < 80)  # the horizon
    rows, cols = np.nonzero(blue)
    assert blue.sum() > 100 and np.ptp(rows) > 3 * np.ptp(cols)  # a steep line, not a blob
    assert yellow.sum() > 100


@pytest.mark.slow
def test_people_sticks_are_drawn_apart_from_the_traced_faults(tmp_path):
    """People's fault sticks: white dashes over a dark casing (in a legend below the section), where the traced
    faults keep their colours; the title counts both."""
    import pyvista as pv
    from matplotlib.image import imread

    def line(x0, fid):
        k = np.arange(10, 110, dtype=float)
        mesh = pv.PolyData(np.column_stack([x0 + 0.1 * (k - 10), np.zeros_like(k), -k]),
                           lines=np.concatenate([[k.size], np.arange(k.size)]))
        mesh.point_data["fault_id"] = np.full(k.size, fid)
        return mesh

    section = _section()
    kw = dict(traces=np.arange(1000, 1080), samples=4.0 * np.arange(120), trace_name="inline", sample_unit="ms",
              trace_spacing=25.0, faults=line(20, 1), width=6.0, dpi=100)
    plot_section(section, path=tmp_path / "faults.png", **kw)
    plot_section(section, path=tmp_path / "both.png", sticks=line(60, 1), **kw)
    faults, both = ((imread(tmp_path / n)[..., :3] * 255).round() for n in ("faults.png", "both.png"))
    assert faults.shape == both.shape
    rows = slice(int(0.15 * both.shape[0]), int(0.75 * both.shape[0]))  # the section: the title above, the legend below
    changed = np.abs(both[rows] - faults[rows]).max(axis=-1) > 60
    white = changed & (both[rows].min(axis=-1) > 230)
    blue = lambda img: (img[..., 2] > 150) & (img[..., 0] < 80)  # the traced fault in tab10 blue
    _, cols = np.nonzero(changed)
    _, fault_cols = np.nonzero(blue(faults[rows]))
    assert white.sum() > 100 and white.sum() > 0.15 * changed.sum()  # white dashes on a twice as wide dark casing
    assert np.percentile(cols, 5) > np.percentile(fault_cols, 95)  # drawn where the sticks are, right of the fault
    assert abs(int(blue(both[rows]).sum()) - int(blue(faults[rows]).sum())) < 0.1 * blue(faults[rows]).sum()
    legend = np.abs(both[int(0.8 * both.shape[0]):] - faults[int(0.8 * faults.shape[0]):]).max(axis=-1) > 60
    assert legend.sum() > 50  # the legend below the section names them


def test_section_refuses_wrong_shapes(tmp_path):
    with pytest.raises(InputError, match="traces and samples"):
        plot_section(_section(), path=tmp_path / "s.png", traces=np.arange(10))
    with pytest.raises(InputError, match="does not exist"):
        plot_section(_section(), path=tmp_path / "nope" / "s.png")
    with pytest.raises(InputError, match="values"):
        plot_section(_section(), path=tmp_path / "s.png", values="velocity")
    assert not (tmp_path / "s.png").exists()


@pytest.mark.slow
@pytest.mark.parametrize("exaggeration", [1.0, 5.0, 20.0])
def test_the_section_fills_the_picture_at_any_exaggeration(tmp_path, exaggeration):
    """A section shaped like Penobscot crossline 1155 (601 traces 12.5 m apart, 0-6000 ms): at 20x it is a strip 16
    times as tall as wide, which a picture of 1200 x 1716 pixels left 90 % white beside; the picture now follows
    the section's shape, so that the section covers most of it (its colour bar below it when it is tall)."""
    from matplotlib.image import imread

    rng = np.random.default_rng(0)
    section = rng.normal(size=(601, 1501)).astype(np.float32)
    plot_section(section, path=tmp_path / "s.png", traces=np.arange(1000, 1601), samples=4.0 * np.arange(1501),
                 trace_name="inline", sample_unit="ms", trace_spacing=12.5, vertical_exaggeration=exaggeration,
                 width=10.0, dpi=60)
    img = imread(tmp_path / "s.png")[..., :3]
    covered = (img.min(axis=-1) < 0.95).mean()  # the section's noise is grey: not white
    assert covered > 0.5, covered
    assert img.shape[0] <= 4 * 10 * 60 + 60 and img.shape[1] <= 10 * 60  # at most 4x as tall as the width given
