"""Mode shapes in pyvista: the whole device (symmetric models unfolded), deformed, coloured by the
normal displacement, with nodal lines and the feet, electrodes and clamps marked.

Functions return a ``pyvista.Plotter`` (off screen unless asked) or write the file they are given;
they never call ``show()`` for the caller.
"""

from __future__ import annotations

import numpy as np

from modalfe.models.symmetry import mirror_planes, mirrored, whole_device_mesh

MARKERS = {"foot": "limegreen", "electrode": "gold", "clamp": "black", "mount": "purple", "actuator": "orange"}


def mode_grid(mode):
    """``pyvista.UnstructuredGrid`` of the whole device with point data ``displacement`` (mass-
    normalised mode shape) and ``w`` (its z component), cell data ``part`` (index into field data)."""
    import pyvista as pv

    model = mode.model
    shape = model.nodal_displacement(mode.shape)
    points, cells, kind, fields, part_id, names = whole_device_mesh(model, {"displacement": shape})
    n = cells.shape[1]
    grid = pv.UnstructuredGrid(np.hstack([np.full((len(cells), 1), n), cells]).ravel(),
                               np.full(len(cells), kind, dtype=np.uint8), points)
    grid.point_data["displacement"] = fields["displacement"]
    grid.point_data["w"] = fields["displacement"][:, 2]
    grid.cell_data["part"] = part_id
    grid.field_data["part_names"] = np.array(names)
    return grid


def _face_markers(model, scale: float, displacement: np.ndarray):
    """(name, colour, PolyData) of the marked face groups, deformed like the mode."""
    import pyvista as pv

    scene = model.scene
    dm = model.mesh
    out = []
    roles = {**{g: "clamp" for g in scene.clamps}}
    for group in dm.faces:
        kind = next((k for k in MARKERS if group.startswith(k)), roles.get(group))
        if kind is None:
            continue
        facets = dm.mesh.facets[:, dm.faces[group]].T
        if facets.shape[1] == 4:
            facets = _cyclic(dm.mesh.p.T, facets)
        faces = np.hstack([np.full((len(facets), 1), facets.shape[1]), facets]).ravel()
        pts = dm.mesh.p.T + scale * displacement.T
        poly = pv.PolyData(pts, faces).clean()
        for axis, twice in mirror_planes(scene):
            mirror = poly.copy()
            mirror.points = mirrored(mirror.points.T, axis, twice).T
            poly = poly.merge(mirror)
        out.append((group, MARKERS[kind], poly))
    return out


def _cyclic(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Quad vertices reordered to go round each face (skfem stores facets with sorted vertices)."""
    xyz = points[quads]  # (n, 4, 3)
    centre = xyz.mean(axis=1, keepdims=True)
    spread = np.ptp(xyz, axis=1)  # (n, 3): the face's normal axis has no spread
    normal = np.argmin(spread, axis=1)
    u_axis = (normal + 1) % 3
    v_axis = (normal + 2) % 3
    rows = np.arange(len(quads))[:, None]
    du = xyz[rows, np.arange(4), u_axis[:, None]] - centre[rows, 0, u_axis[:, None]]
    dv = xyz[rows, np.arange(4), v_axis[:, None]] - centre[rows, 0, v_axis[:, None]]
    order = np.argsort(np.arctan2(dv, du), axis=1)
    return np.take_along_axis(quads, order, axis=1)


def render_mode(mode, *, out: str | None = None, window_size=(1000, 650), amplification: float = 0.05,
                view: str = "iso", off_screen: bool = True):
    """Render ``mode`` deformed (largest displacement = ``amplification`` x the device's size).

    ``view``: "iso", "top" or "bottom". Returns the Plotter; with ``out`` it also writes a PNG."""
    import pyvista as pv

    grid = mode_grid(mode)
    size = float(np.ptp(grid.points, axis=0).max())
    peak = float(np.abs(grid.point_data["displacement"]).max()) or 1.0
    scale = amplification * size / peak
    warped = grid.warp_by_vector("displacement", factor=scale)
    surface = warped.extract_surface(algorithm=None)
    w = surface.point_data["w"]
    limit = float(np.abs(w).max()) or 1.0
    plotter = pv.Plotter(off_screen=off_screen, window_size=list(window_size))
    plotter.set_background("white")
    plotter.add_mesh(surface, scalars="w", cmap="RdBu_r", clim=[-limit, limit], show_scalar_bar=True,
                     scalar_bar_args={"title": "normal displacement (mass-normalised)", "color": "black"})
    nodal = surface.contour([0.0], scalars="w")
    if nodal.n_points:
        plotter.add_mesh(nodal, color="black", line_width=3)
    model = mode.model
    displacement = model.nodal_displacement(mode.shape)
    for group, colour, poly in _face_markers(model, scale, displacement):
        lifted = poly.compute_normals(auto_orient_normals=True)  # lift off the surface: no z-fighting
        lifted.points = lifted.points + 4e-3 * size * lifted.point_data["Normals"]
        plotter.add_mesh(lifted, color=colour, label=group)
    plotter.add_text(f"{model.scene.name}: {mode.label}  {mode.frequency:.1f} Hz", font_size=12, color="black")
    {"iso": plotter.view_isometric, "top": plotter.view_xy}.get(view, plotter.view_isometric)()
    if view == "bottom":
        plotter.view_xy(negative=True)
    plotter.camera.zoom(1.2)
    if out:
        plotter.screenshot(out)
    return plotter


def animate_mode(mode, out: str, *, frames: int = 16, amplification: float = 0.08,
                 window_size=(800, 520)) -> str:
    """Write an animated GIF of one period of ``mode`` to ``out``; returns the path."""
    grid = mode_grid(mode)
    size = float(np.ptp(grid.points, axis=0).max())
    peak = float(np.abs(grid.point_data["displacement"]).max()) or 1.0
    scale = amplification * size / peak
    plotter = render_mode(mode, amplification=0.0, window_size=window_size)
    surface = plotter.meshes[0]
    base = grid.extract_surface(algorithm=None)
    rest, u = base.points.copy(), base.point_data["displacement"]
    plotter.open_gif(out)
    for phase in np.linspace(0, 2 * np.pi, frames, endpoint=False):
        surface.points = rest + scale * np.cos(phase) * u
        plotter.write_frame()
    plotter.close()
    return out
