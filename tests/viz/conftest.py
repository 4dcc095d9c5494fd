"""Fixtures of the 3D scenes' tests: the colour bars as VTK draws them."""

import numpy as np
import pytest


@pytest.fixture
def colour_bars(monkeypatch):
    """``colour_bars(module, draw)``: run ``draw()``, a scene of ``module`` rendered off screen (``screenshot``
    given: that PNG is not written, as ``module.finish_scene`` is replaced), and check that every colour bar and
    its tick labels are inside the window, that its title is drawn inside its rectangle (1 pixel of anti-aliasing;
    pyvista's bars draw their text at its font size, whatever their rectangle's size; VTK lifts a vertical bar's
    title 0.75 of a label's height over it), that no bar's rectangle or text lies over another's, and that a
    horizontal bar's tick labels are half an em apart at least.

    Returns the bars as ``{title: (rectangle, drawn_title, drawn_labels, lift)}``, boxes in pixels
    ``(x0, y0, x1, y1)`` from the window's lower left corner: the bar actor's rectangle (position and size) and
    the pixels its title and its tick labels cover on screen, found without any measure of seismo3d's: the scene
    is rendered with the text black, then with the one part red, and the pixels that change are that part's.
    The end labels of a horizontal bar are centred on its strip's ends, so they reach past its rectangle."""

    def layout(module, draw):
        found, window, scene = {}, [], []

        def record(plotter, **kw):
            width, height = (int(v) for v in plotter.window_size)
            bars = list(plotter.scalar_bars.items())
            props = [(bar.GetTitleTextProperty(), bar.GetLabelTextProperty()) for _, bar in bars]
            first = plotter.screenshot(return_img=True)  # the first render: what a saved PNG shows
            for _, bar in bars:
                bar.Modified()  # every bar lays itself out again
            plotter.render()
            changed = np.any(plotter.screenshot(return_img=True) != first, axis=-1)[::-1]  # row 0 at the bottom
            if plotter.renderer.axes_widget is not None:  # VTK's orientation widget sizes its captions anew
                x0, y0, x1, y1 = np.multiply(plotter.renderer.axes_widget.GetViewport(), (width, height) * 2)
                changed[int(y0):int(np.ceil(y1)), int(x0):int(np.ceil(x1))] = False
            assert not changed.any(), \
                f"a later render differs from the first (the saved PNG) in {np.count_nonzero(changed)} pixels"
            # the text is found with the 3D content hidden: only the bars' colours change between these renders,
            # and a volume (the likelihood) costs about 0.4 CPU s a render; _drawn_scene shows it again
            content = _visible_3d_props(plotter)
            for prop in content:
                prop.VisibilityOff()
            shots = []
            for colour in ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0)):
                for (_, bar), pair in zip(bars, props):
                    for prop in pair:
                        prop.SetColor(*colour)
                        prop.SetShadow(False)
                    bar.Modified()  # the bar lays its text out again
                plotter.render()
                shots.append(plotter.screenshot(return_img=True)[::-1, :, :3].astype(int))  # row 0 at the bottom
            text = np.abs(shots[0] - shots[1]).max(axis=-1) > 0
            for n, (title, bar) in enumerate(bars):
                x0, y0 = np.multiply(bar.GetPosition(), (width, height))
                x1, y1 = np.multiply(np.add(bar.GetPosition(), bar.GetPosition2()), (width, height))
                boxes = []
                for part in (0, 1):  # this bar's title, then its tick labels, alone in red
                    for m, ((_, other), pair) in enumerate(zip(bars, props)):
                        for k, prop in enumerate(pair):
                            prop.SetColor(*((1.0, 0.0, 0.0) if (m, k) == (n, part) else (0.0, 0.0, 0.0)))
                        other.Modified()
                    plotter.render()
                    red = np.abs(plotter.screenshot(return_img=True)[::-1, :, :3].astype(int) - shots[0]).max(-1) > 0
                    rows, cols = np.nonzero(red & text)
                    boxes.append((cols.min(), rows.min(), cols.max() + 1, rows.max() + 1) if rows.size else None)
                if bar.GetOrientation() == 0 and bar.GetDrawTickLabels():
                    # the labels side by side: as many runs of pixel columns, half an em apart
                    columns = np.flatnonzero((red & text).any(axis=0))
                    em = bar.GetLabelTextProperty().GetFontSize()
                    runs = 1 + int(np.count_nonzero(np.diff(columns) > em / 2)) if columns.size else 0
                    assert runs == bar.GetNumberOfLabels(), \
                        f"{title!r}: {bar.GetNumberOfLabels()} tick labels drawn as {runs} (run into each other)"
                # a vertical bar's title is lifted 0.75 of a label's height over its rectangle's top (pyvista's
                # unconstrained fonts: vtkScalarBarActor::LayoutForUnconstrainedFont, VTK 9)
                lift = 0.75 * bar.GetLabelTextProperty().GetFontSize() if bar.GetOrientation() == 1 else 0.0
                found[title] = ((x0, y0, x1, y1), *boxes, lift)
            window.extend((width, height))
            for prop in content:
                prop.VisibilityOn()
            scene.append(_drawn_scene(plotter))
            plotter.close()
            return plotter

        monkeypatch.setattr(module, "finish_scene", record)
        draw()
        _check(found, *window)
        _check_scene(found, scene[0])
        return found

    return layout


def _overlap(a, b):
    """The overlap of two boxes (x0, y0, x1, y1) along x and y (one of them <= 0: they do not overlap)."""
    return min(a[2], b[2]) - max(a[0], b[0]), min(a[3], b[3]) - max(a[1], b[1])


def _check(bars, width, height, *, tolerance=1.0):
    """Every bar and its text inside the window, its title drawn inside its rectangle (``tolerance`` pixels of
    anti-aliasing), no bar's rectangle or text over another's."""
    items = list(bars.items())
    window = (0, 0, width, height)
    for n, (title, (rectangle, drawn_title, drawn_labels, lift)) in enumerate(items):
        assert drawn_title is not None, f"{title!r}: its title is not drawn"
        for box in (rectangle, drawn_labels or rectangle):
            assert min(np.subtract(_overlap(box, window), np.subtract(box[2:], box[:2]))) >= -tolerance, \
                f"{title!r}: {box} is not inside the {width} x {height} window"
        x0, y0, x1, y1 = rectangle
        u0, v0, u1, v1 = drawn_title
        assert u0 >= x0 - tolerance and v0 >= y0 - tolerance and u1 <= x1 + tolerance and \
            v1 <= y1 + lift + tolerance, f"{title!r}: its title covers pixels {drawn_title}, outside its rectangle " \
                                         f"{rectangle} (and {lift} pixels above it)"
        assert v1 <= height, f"{title!r}: its title covers pixels {drawn_title}, above the window"
        for other, (other_rectangle, *other_text, _) in items[n + 1:]:
            for a in (rectangle, drawn_title, drawn_labels or rectangle):
                for b in (other_rectangle, *(box for box in other_text if box is not None)):
                    assert min(_overlap(a, b)) <= 0, f"{title!r} and {other!r} overlap: {a} and {b}"


def _visible_3d_props(plotter):
    """The renderer's visible props that are not 2D actors (colour bars, text): the scene's 3D content."""
    props = plotter.renderer.GetViewProps()
    return [prop for prop in (props.GetItemAsObject(n) for n in range(props.GetNumberOfItems()))
            if prop.GetVisibility() and not prop.IsA("vtkActor2D")]


def _drawn_scene(plotter):
    """The pixels the scene's 3D content covers, row 0 at the bottom: rendered with every colour bar, text and
    other 2D actor and the orientation widget hidden, on a white and on a black background; the pixels that do
    not change by the whole difference of the two backgrounds (a white part of a slice is drawn too)."""
    for bar in plotter.scalar_bars.values():
        bar.VisibilityOff()
    props = plotter.renderer.GetViewProps()
    for n in range(props.GetNumberOfItems()):
        if props.GetItemAsObject(n).IsA("vtkActor2D"):
            props.GetItemAsObject(n).VisibilityOff()
    plotter.hide_axes()
    shots = []
    for colour in ("white", "black"):
        plotter.set_background(colour)
        plotter.render()
        shots.append(plotter.screenshot(return_img=True)[::-1, :, :3].astype(int))
    return (shots[0] - shots[1]).min(axis=-1) < 253


def _check_scene(bars, drawn, *, share=0.75):
    """The scene's drawn content (``drawn``: a boolean image, row 0 at the bottom) covers no bar's rectangle or
    text, and fills at least ``share`` of the room the bars leave (left of the vertical bars, above the bottom
    row) along one of its sides: the camera is fitted to that room with margins of at most a tenth of the
    window's width (0.08 of its height) on each side, so a fitted scene spans at least 0.8 of it."""
    height, width = drawn.shape
    x_max, y_min = width, 0
    for title, (rectangle, drawn_title, drawn_labels, _) in bars.items():
        for box in (rectangle, drawn_title, drawn_labels):
            if box is None:
                continue
            x0, y0, x1, y1 = (int(np.floor(box[0])), int(np.floor(box[1])), int(np.ceil(box[2])),
                              int(np.ceil(box[3])))
            covered = np.count_nonzero(drawn[max(y0, 0):y1, max(x0, 0):x1])
            assert covered == 0, f"the scene covers {covered} pixels of {title!r}'s bar or its text {box}"
        x0, y0, x1, y1 = rectangle
        if x1 - x0 < y1 - y0 and x0 > width / 2:  # a vertical bar at the right
            x_max = min(x_max, x0)
        else:  # a bar of the bottom row
            y_min = max(y_min, y1)
    rows, cols = np.nonzero(drawn)
    assert rows.size, "the scene draws nothing"
    spans = ((cols.max() + 1 - cols.min()) / (x_max - 0), (rows.max() + 1 - rows.min()) / (height - y_min))
    assert max(spans) >= share, f"the scene spans {spans[0]:.2f} of the room's width and {spans[1]:.2f} of its " \
                                f"height (0 .. {x_max:.0f} x {y_min:.0f} .. {height} pixels)"
