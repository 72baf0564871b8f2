"""Pictures: offscreen renders that show the mode, every foot and electrode (each seen from its side), markers
that move with the body in an animation, a colour bar with units beside (not over) the device, and the title
saying when the picture is unfolded from a half or quarter model."""

from __future__ import annotations

import numpy as np
import pytest

from modalfe.scene import load_scene
from modalfe.solve.api import solve_modes

pv = pytest.importorskip("pyvista")


@pytest.fixture(scope="module")
def plate():
    scene = load_scene("cube_plate", **{"mesh.elements_per_wavelength": 4.0})
    return solve_modes(scene, near=40e3, count=4, error_estimate=False)


@pytest.fixture(scope="module")
def glass():
    scene = load_scene("glass_plate", **{"mesh.elements_per_wavelength": 4.0})
    return solve_modes(scene, near=66e3, count=3, error_estimate=False)


def _actors(plotter) -> dict:
    """Named actors of every panel (``plotter.actors`` holds the active panel's only)."""
    return {k: a for r in plotter.renderers for k, a in r.actors.items()}


def _visible_pixels(plotter, name: str) -> int:
    """Pixels of the actor ``name`` in the rendered picture: every other marker hidden, this one drawn in an
    unlit magenta that nothing else in the picture has (the body and nodal lines stay, so occlusion counts)."""
    actors = _actors(plotter)
    markers = [k for k in actors if k.startswith("marker:")]
    saved = {k: (actors[k].visibility, actors[k].prop.color, actors[k].prop.lighting) for k in markers}
    for k in markers:
        actors[k].visibility = k == name
    actor = actors[name]
    actor.prop.color, actor.prop.lighting = (1.0, 0.0, 1.0), False
    plotter.ren_win.Render()  # screenshot() alone may return the previous frame
    image = plotter.screenshot(return_img=True).astype(int)
    for k, (vis, colour, light) in saved.items():
        actors[k].visibility, actors[k].prop.color, actors[k].prop.lighting = vis, colour, light
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return int(np.sum((r > 230) & (g < 25) & (b > 230)))


@pytest.mark.parametrize("fixture, expected", [
    ("plate", {"foot_1", "foot_2", "foot_3", "foot_4", "electrode_top", "electrode_bottom"}),
    ("glass", {"electrode_outer", "electrode_inner"}),
])
def test_every_foot_and_electrode_is_marked_and_visible_from_its_side(fixture, expected, request):
    from modalfe.plot.render import render_mode

    modes = request.getfixturevalue(fixture)
    plotter = render_mode(modes[0], window_size=(900, 320), view="iso+bottom")
    try:
        markers = plotter._modalfe["markers"]
        assert {m.group for m in markers} == expected  # mirrored feet (foot_3, foot_4) included
        for i, m in enumerate(markers):
            views = [v for v in m.seen_from() if v in plotter._modalfe["views"]]
            assert views, f"{m.group}: faces no view of the picture"
            # 20 pixels: a 3 x 3 mm foot is ~8 x 8 pixels here, the thinnest outline ~2 px wide and ~100 long
            seen = max(_visible_pixels(plotter, f"marker:{m.group}:{i}:{v}") for v in views)
            assert seen > 20, f"{m.group} is hidden in the {views} view(s): {seen} pixels"
        if fixture == "plate":  # occlusion counts: a foot's sole is not seen from above, through the plate
            assert _visible_pixels(plotter, "marker:foot_1:2:iso") == 0
    finally:
        plotter.close()


def test_colour_bar_has_units_and_sits_beside_the_device(plate):
    from modalfe.plot.render import COLOUR_BAR_TITLES, render_mode

    plotter = render_mode(plate[0], window_size=(600, 300), view="iso")
    try:
        title = COLOUR_BAR_TITLES["w"]  # a bending mode: coloured by the normal displacement
        assert "[m per unit modal" in title and "mass-normalised" in title
        bars = list(plotter.scalar_bars.values())
        assert len(bars) == 1 and bars[0].GetTitle() == title
        # the device is drawn in the first panel, the bar in the last: their viewports do not overlap
        device, bar = plotter.renderers[0], plotter.renderers[-1]
        assert device.GetViewport()[2] <= bar.GetViewport()[0]
        props = bar.GetViewProps()
        assert bars[0] in [props.GetItemAsObject(i) for i in range(props.GetNumberOfItems())]
    finally:
        plotter.close()


def test_title_says_when_a_half_or_quarter_model_is_unfolded(plate, glass):
    from modalfe.plot.render import symmetry_note

    assert symmetry_note(plate.model.scene) == "whole device drawn from the half model about y = 19 mm"
    assert symmetry_note(glass.model.scene) == "whole device drawn from the quarter model about x = 30 mm and y = 10 mm"
    assert symmetry_note(load_scene("honeycomb_tile")) == ""


def test_two_modes_give_different_pictures(plate):
    from modalfe.plot.render import render_mode

    images = []
    for mode in plate[:2]:
        plotter = render_mode(mode, window_size=(500, 300), view="iso")
        images.append(plotter.screenshot(return_img=True).astype(float))
        plotter.close()
    assert images[0].std() > 20  # a white background alone has std 0
    assert np.mean(np.abs(images[0] - images[1])) > 2  # mean absolute difference per channel, 0-255 scale


def test_markers_and_nodal_lines_follow_the_body_in_an_animation(plate, tmp_path, monkeypatch):
    from modalfe.plot import render

    frames = []
    real = render.render_mode

    def spy(*args, **kwargs):
        plotter = real(*args, **kwargs)
        original = plotter.write_frame

        def record():
            frames.append({name: np.array(a.mapper.dataset.points) for name, a in _actors(plotter).items()
                           if name.startswith(("marker:", "device:", "nodal:"))})
            original()

        monkeypatch.setattr(plotter, "write_frame", record)
        return plotter

    monkeypatch.setattr(render, "render_mode", spy)
    path = render.animate_mode(plate[1], str(tmp_path / "mode.gif"), frames=4, window_size=(300, 200))
    with open(path, "rb") as f:
        assert f.read(6) in (b"GIF89a", b"GIF87a")
    assert len(frames) == 4
    device = next(k for k in frames[0] if k.startswith("device:"))
    foot = next(k for k in frames[0] if k.startswith("marker:foot_1"))
    # frames 0 and 2 are half a period apart: body and foot marker both move, by the same displacement field
    moved_body = np.abs(frames[0][device] - frames[2][device]).max()
    moved_foot = np.abs(frames[0][foot] - frames[2][foot]).max()
    assert moved_body > 0 and moved_foot > 0
    rest = 0.5 * (frames[0][foot] + frames[2][foot])  # the rest position (cos 0 = -cos pi)
    marker = next(m for m in render.marker_set(plate[1]) if m.group == "foot_1")
    np.testing.assert_allclose(rest, marker.poly.points, atol=1e-12)


@pytest.fixture(scope="module")
def beam():
    scene = load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0})
    return solve_modes(scene, near=21.6e3, count=2, error_estimate=False)


def test_title_states_the_frequency_its_error_and_the_model(plate):
    from dataclasses import replace

    from modalfe.plot.render import mode_title

    mode = plate[0]
    assert mode_title(mode) == (f"cube_plate: {mode.label}  {mode.frequency:.1f} Hz error not estimated  "
                                f"(3-D solid, half model)")  # solved with error_estimate=False
    stated = replace(mode, error_estimate=0.00283)
    assert f"{mode.frequency:.1f} Hz +- 0.28 %" in mode_title(stated)


def test_nodal_lines_follow_the_zero_of_the_mode_s_own_field(plate):
    """The lines are the zero of w probed on a subdivided surface: at their points the mode's (quadratic) field is
    near zero, closer than the contour of its linear interpolation between the drawn vertices (jagged lines)."""
    from modalfe.plot.render import mode_grid, nodal_lines

    mode = plate[0]
    surface = mode_grid(mode).extract_surface(algorithm=None).triangulate()
    peak = float(np.abs(surface.point_data["w"]).max())
    coarse = surface.contour([0.0], scalars="w")
    fine = nodal_lines(mode, surface)
    off_coarse = np.abs(mode.displacement(coarse.points)[:, 2]).max() / peak
    off_fine = np.abs(mode.displacement(fine.points)[:, 2]).max() / peak
    # measured 0.13 (coarse) and 0.03 (fine): a quadratic field interpolated over a quarter of the element is ~16x
    # closer in theory; 5 % of the peak is a line drawn within a few pixels of the true one at this scale
    assert off_fine < 0.05 and off_fine < off_coarse / 3


def _projected_inside(plotter, renderer, bounds) -> bool:
    """Whether the eight corners of ``bounds`` project inside ``renderer``'s viewport (display pixels)."""
    width, height = plotter.window_size
    x0, y0, x1, y1 = renderer.GetViewport()
    for x in bounds[0:2]:
        for y in bounds[2:4]:
            for z in bounds[4:6]:
                renderer.SetWorldPoint(x, y, z, 1.0)
                renderer.WorldToDisplay()
                u, v, _ = renderer.GetDisplayPoint()
                if not (x0 * width <= u <= x1 * width and y0 * height <= v <= y1 * height):
                    return False
    return True


def test_whole_beam_in_every_panel_with_its_clamp_hatched_named_points_and_a_legend(beam):
    from modalfe.plot.render import FILL_OPACITY, LEGEND, render_mode

    plotter = render_mode(beam[0], window_size=(1000, 400), view="iso+bottom")
    try:
        actors = _actors(plotter)
        for col, view in enumerate(("iso", "bottom")):
            device = actors[f"device:{view}"]
            # the deformed beam, tip included, projects inside its panel (the old zoom cut the tip off)
            assert _projected_inside(plotter, plotter.renderers[col], device.GetBounds()), view
        clamp = [k for k in actors if k.startswith("marker:clamp")]
        fill = [k for k in actors if k.startswith("fill:clamp")]
        assert clamp and fill and actors[fill[0]].prop.opacity == FILL_OPACITY
        assert actors[clamp[0]].mapper.dataset.n_lines >= 8  # the hatching strokes
        props = plotter.renderers[-1].GetViewProps()
        texts = [props.GetItemAsObject(i) for i in range(props.GetNumberOfItems())]
        entries = [t.GetEntryString(i) for t in texts if hasattr(t, "GetEntryString")
                   for i in range(t.GetNumberOfEntries())]
        assert {LEGEND["clamp"], LEGEND["electrode"], "nodal line", "named point"} <= set(entries)
        # the scene's named output points (tip, x_47.25mm, ...) drawn in each panel
        named = [o for o in beam[0].model.scene.drive.outputs if not isinstance(o, str)]
        assert actors["points:iso"].mapper.dataset.n_points == len(named) >= 2
    finally:
        plotter.close()


def test_a_ring_s_electrodes_on_its_curved_walls_are_marked():
    """Electrodes on curved faces (a radially poled ring's walls, issue 37: not marked) are found on the mesh's
    facets of their face groups and drawn as outlines, seen in the iso panel."""
    from modalfe.plot.render import render_mode
    from tests.oracles.discs import radial_ring_scene

    modes = solve_modes(radial_ring_scene(50e3), near=50e3, count=1, error_estimate=False)
    plotter = render_mode(modes[0], window_size=(600, 300), view="iso")
    try:
        markers = plotter._modalfe["markers"]
        assert {m.group for m in markers} == {"electrode_a", "electrode_b"}
        for i, m in enumerate(markers):
            assert _visible_pixels(plotter, f"marker:{m.group}:{i}:iso") > 20, m.group  # as for the plates above
    finally:
        plotter.close()


@pytest.fixture(scope="module")
def ring():
    """The free steel ring of examples/steel_ring.toml (quadratic hexahedra, curved walls): its in-plane n = 2 pair
    near 1.56 kHz and its out-of-plane (2,0) pair near 2.50 kHz."""
    from pathlib import Path

    scene = load_scene(Path(__file__).parents[2] / "examples" / "steel_ring.toml")
    return solve_modes(scene, near=2e3, count=4, error_estimate=False, fidelity="solid")


def _lattice(mode):
    from modalfe.plot.render import mode_grid, surface_field

    surface = mode_grid(mode).extract_surface(algorithm=None).triangulate()
    return surface, surface_field(mode, surface)


def test_the_field_is_read_at_every_point_of_a_ring_s_surface_curved_walls_included(ring):
    """Issue 37: the ring's nodal lines were jagged and broken because its field was read at none of the subdivided
    points (a point of the inner wall's chord lies in the hole: the probes refused the whole set, and the lines fell
    back to w interpolated linearly between the drawn vertices). Now every point is read in the curved element under
    it at the same reference coordinates: the vertices' values at the corners, the quadratic field between them."""
    mode = ring.labelled("(2,0)")
    surface, fine = _lattice(mode)
    w, linear = fine.point_data["w"], fine.point_data["displacement"][:, 2]
    peak = float(np.abs(surface.point_data["w"]).max())
    corner = fine.point_data["weights"].max(axis=1) == 1.0
    np.testing.assert_allclose(w[corner], linear[corner], rtol=0, atol=1e-12 * peak)  # the same nodal values
    # between the corners the old lines' field (linear) is not the mode's: the quadratic part over an element,
    # measured 2.4 % of the peak here
    assert np.abs(w[~corner] - linear[~corner]).max() > 1e-2 * peak


@pytest.mark.parametrize("fixture", ["plate", "glass"])
def test_the_field_read_on_the_surface_is_the_mode_s_own_in_the_mirrored_copies_too(fixture, request):
    """On the box scenes (flat faces: the drawn triangles are the elements' faces) the field read by reference
    coordinates equals the point probes' at every subdivided point, the half (plate) and quarter (glass) models'
    mirrored copies included: the elements, their vertices' order and the components' signs are found right."""
    mode = request.getfixturevalue(fixture)[0]
    surface, fine = _lattice(mode)
    peak = float(np.abs(surface.point_data["w"]).max())
    # the same element's field at the same point by two routes (reference coordinates here, the point search and
    # the box's affine map there): round-off only, far below the 1e-9 of the peak allowed
    np.testing.assert_allclose(fine.point_data["w"], mode.displacement(fine.points)[:, 2], rtol=0, atol=1e-9 * peak)


def test_a_ring_s_nodal_lines_are_closed_loops(ring):
    """The (2,0) mode's four nodal lines cross the top face, the walls and the bottom face: each a closed loop around
    the ring's section (its field is continuous across every drawn triangle), not broken where the walls begin."""
    from modalfe.plot.render import nodal_lines

    mode = ring.labelled("(2,0)")
    surface, _ = _lattice(mode)
    lines = nodal_lines(mode, surface).clean(tolerance=1e-9)  # the triangles' own copies of their shared points
    lines = lines.connectivity()
    ends = np.bincount(lines.lines.reshape(-1, 3)[:, 1:].ravel(), minlength=lines.n_points)
    assert len(np.unique(lines.point_data["RegionId"])) == 4  # n = 2: four nodal diameters
    assert np.all(ends == 2), f"{int(np.sum(ends != 2))} line ends (a closed loop has none)"


def test_an_in_plane_mode_is_coloured_by_its_displacement_s_magnitude(ring, plate):
    from modalfe.plot.render import COLOUR_BAR_TITLES, coloured_by, mode_grid, render_mode

    in_plane = ring.labelled("n=2")
    assert coloured_by(mode_grid(plate[0]).extract_surface(algorithm=None)) == "w"  # the plate's (0,6): bending
    assert coloured_by(mode_grid(ring.labelled("(2,0)")).extract_surface(algorithm=None)) == "w"
    assert coloured_by(mode_grid(in_plane).extract_surface(algorithm=None)) == "magnitude"
    plotter = render_mode(in_plane, window_size=(600, 300), view="iso")
    try:
        actors = _actors(plotter)
        device = actors["device:iso"].mapper
        assert device.array_name == "magnitude" and device.scalar_range[0] == 0.0
        title = next(iter(plotter.scalar_bars.values())).GetTitle()
        assert title == COLOUR_BAR_TITLES["magnitude"] and "in-plane mode" in title
        assert not any(k.startswith("nodal:") for k in actors)  # the zero of a near-zero w is not drawn
    finally:
        plotter.close()


def test_a_second_process_draws_the_same_picture_as_this_one(plate, tmp_path):
    # ``show``'s PNG comes from a process that loaded VTK while the solve ran: the same pixels as drawn here
    from PIL import Image

    from modalfe.plot.render import render_mode
    from modalfe.plot.render_process import RenderProcess

    here, there = tmp_path / "here.png", tmp_path / "there.png"
    render_mode(plate[0], out=str(here), view="iso+bottom").close()
    RenderProcess().render(plate[0], str(there), "iso+bottom")
    assert np.array_equal(np.asarray(Image.open(here)), np.asarray(Image.open(there)))


def test_the_second_process_loads_before_the_mode_comes_all_that_drawing_it_imports(plate, tmp_path):
    # what it imports once the mode has come (its classes, VTK's filters, Pillow's plugins) is on `show`'s critical
    # path: a fresh interpreter, prepared as the second process is, then a mode unpickled and drawn, imports nothing
    import json
    import os
    import pickle
    import subprocess
    import sys
    from pathlib import Path

    from modalfe.plot.render_process import sent

    payload = tmp_path / "mode.pickle"
    payload.write_bytes(pickle.dumps(sent(plate[0])))
    script = ("import json, pickle, sys\n"
              "from modalfe.plot.render_process import prepared\n"
              "plotter = prepared('iso')\n"
              "from modalfe.plot.render import render_mode\n"
              "before = set(sys.modules)\n"
              f"mode = pickle.loads(open({str(payload)!r}, 'rb').read())\n"
              f"render_mode(mode, out={str(tmp_path / 'm.png')!r}, view='iso', plotter=plotter).close()\n"
              "print(json.dumps(sorted(set(sys.modules) - before)))\n")
    import modalfe

    env = {**os.environ, "PYTHONPATH": str(Path(modalfe.__file__).resolve().parents[1])}  # this modalfe
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True, env=env)
    assert json.loads(run.stdout.splitlines()[-1]) == []


def test_a_deferred_module_is_loaded_by_its_first_use_not_by_its_import(tmp_path, monkeypatch):
    # matplotlib.pyplot, pooch and numpy.f2py, which pyvista and scipy import but no picture uses, are left to their
    # first use in the second process; a package's module is its package's attribute, as an import makes it
    import sys

    from modalfe.plot.render_process import Deferred, defer

    (tmp_path / "deferred_probe").mkdir()
    (tmp_path / "deferred_probe" / "__init__.py").write_text("")
    (tmp_path / "deferred_probe" / "sub.py").write_text("VALUE = 3\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        defer("deferred_probe.sub")
        import deferred_probe.sub as probe

        assert isinstance(sys.modules["deferred_probe.sub"], Deferred)  # bound, not run
        assert sys.modules["deferred_probe"].sub is probe
        assert probe.VALUE == 3 and not isinstance(sys.modules["deferred_probe.sub"], Deferred)
    finally:
        for name in ("deferred_probe.sub", "deferred_probe"):
            sys.modules.pop(name, None)


def test_a_failed_second_process_says_why(plate, tmp_path):
    # a picture it cannot write (no such folder) comes back as RenderProcessError with the reason, for ``show`` to
    # draw in its own process (where the same failure is the user's error)
    from modalfe.plot.render_process import RenderProcess, RenderProcessError

    with pytest.raises(RenderProcessError, match="rendering process failed"):
        RenderProcess().render(plate[0], str(tmp_path / "missing" / "x.png"), "iso")


def test_an_axisymmetric_mode_is_drawn_revolved_with_its_marks_and_nodal_lines():
    """Issue 36 item 1: the axisymmetric answer is drawn on its meridian mesh swept round the axis; the PZT-5A
    disc's (3,1) mode shows both electrodes (top and bottom faces) and nodal lines at the zero of its revolved field
    (as the plate's above: within 5 % of the peak)."""
    from modalfe.plot.render import mode_grid, nodal_lines, render_mode
    from tests.oracles.discs import PZT5A_DISC

    modes = solve_modes(PZT5A_DISC, fidelity="axisymmetric", harmonics=3, near=77e3, count=2, error_estimate=False)
    mode = modes.labelled("(3,1)")
    plotter = render_mode(mode, window_size=(600, 300), view="iso+bottom")
    try:
        markers = plotter._modalfe["markers"]
        assert {m.group for m in markers} == {"electrode_a", "electrode_b"}
        for i, m in enumerate(markers):  # each seen from its side, as the plates' markers above
            view = "iso" if "iso" in m.seen_from() else "bottom"
            assert _visible_pixels(plotter, f"marker:{m.group}:{i}:{view}") > 20, m.group
    finally:
        plotter.close()
    surface = mode_grid(mode).extract_surface(algorithm=None).triangulate()
    peak = float(np.abs(surface.point_data["w"]).max())
    lines = nodal_lines(mode, surface)
    assert lines.n_points and np.abs(mode.displacement(lines.points)[:, 2]).max() < 0.05 * peak


def test_a_ring_stack_s_bonded_electrode_and_nodal_lines_are_drawn_on_the_body():
    """Two PZT-4 rings bonded on one axis, the electrode between them (a Langevin stack's core), axisymmetric: the
    bonded electrode's outline is its circles (inner and outer radius, grown), its displacement read on the face;
    the nodal lines' points on the inner wall, which the drawing's chords cut inside the hole, are read on the wall.
    Before, `show` failed on both: the outline's square corners and the chords' points lay off the body (an internal
    error, "Point is outside of the mesh")."""
    from modalfe.plot.render import marker_set, mode_grid, nodal_lines
    from modalfe.scene import scene_from_dict

    rings = [{"name": f"pzt{k}", "shape": "ring", "material": "PZT-4", "centre": [0, 0, 5 * k], "axis": "z",
              "inner": 3, "outer": 10, "height": 5, "poling": 1 - 2 * k} for k in (0, 1)]
    scene = scene_from_dict({"units": "mm", "parts": rings, "faces": {"mid": ["pzt0.top"], "ends": ["pzt0.bottom",
                             "pzt1.top"]}, "electrodes": {"mid": "drive", "ends": "ground"},
                             "analysis": {"near": 100e3, "count": 4}})
    modes = solve_modes(scene, fidelity="axisymmetric", harmonics=2, error_estimate=False)
    mode = max(modes, key=lambda m: m.frequency)
    outline = next(m for m in marker_set(mode) if m.group == "mid" and m.outline)
    radii = np.unique(np.round(np.hypot(outline.poly.points[:, 0], outline.poly.points[:, 1]) * 1e3, 2))
    assert len(radii) == 2 and radii[0] < 3 < 10 < radii[1] < 10.5  # two circles just off the ring's walls
    surface = mode_grid(mode).extract_surface(algorithm=None).triangulate()
    assert nodal_lines(mode, surface).n_points
    # the 3-D solid of the same stack: the outline read inside its meshed walls (quadratic arcs off the circle)
    solid = max(solve_modes(scene, fidelity="solid", error_estimate=False), key=lambda m: m.frequency)
    assert any(m.group == "mid" and m.outline for m in marker_set(solid))
