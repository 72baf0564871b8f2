"""Mode shapes in pyvista: the whole device (symmetric models unfolded), deformed, coloured by the
normal displacement (an in-plane mode, whose normal displacement is near zero, by the displacement's magnitude, as
its colour bar says), with nodal lines and the feet, electrodes, clamps, springs and masses marked.

Each panel shows the whole device (the camera fits the deformed body and its markers), an x-y-z triad and a
scale bar; electrodes are drawn as outlines over a translucent fill so that the mode shows through them, clamped
faces are hatched, feet are labelled by name, and a legend beside the colour bar names every marker. The nodal
lines are the zero contour of the normal displacement read on a subdivided surface (the finite-element field at
the finer points, in the element under each, curved walls included, not its linear interpolation between the drawn
vertices), so they are smooth. The title gives the mode, its frequency with its stated error, and the model (3-D
solid, whole, half or quarter).

Markers are found on the whole device's surface from the full assembly's face groups (so a half or
quarter model shows the mirrored feet and electrodes too), carry the mode's displacement so that they
move with the body in an animation, and are lifted off the surface along the face's outward normal.
A face bonded to another part (an electrode under a ceramic) is drawn as its outline on the exposed
surface around it. The colour bar sits in its own panel at the right, and the title says when the
picture is unfolded from a half or quarter model.

Functions return a ``pyvista.Plotter`` (off screen unless asked) or write the file they are given;
they never call ``show()`` for the caller.
"""

from __future__ import annotations

import logging
import os
import tempfile
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from modalfe.models.axisymmetric import AxisymmetricModel
from modalfe.models.symmetry import VTK_HEXAHEDRON, mirror_planes, whole_device_mesh

if TYPE_CHECKING:
    import pyvista

log = logging.getLogger(__name__)

MARKERS = {"foot": "limegreen", "electrode": "gold", "clamp": "black", "guide": "dimgray", "spring": "purple",
           "mass": "orange"}
LEGEND = {"foot": "foot", "electrode": "electrode", "clamp": "clamp (hatched)", "guide": "guided face",
          "spring": "spring", "mass": "mass"}
FILL_OPACITY = 0.25  # electrodes' and clamps' fill: the mode's colours stay readable through it
SUBDIVISIONS = 2  # nodal lines: each surface triangle split in 2**2, the field read at the new points
UNITS = "[m per unit modal\namplitude,\nmass-normalised]"
COLOUR_BAR_TITLES = {"w": f"normal displacement w\n{UNITS}",
                     "magnitude": f"displacement\nmagnitude\n(in-plane mode)\n{UNITS}"}
# an in-plane mode: w's rms over the surface's vertices below this share of the displacement's. Measured: bending
# modes 0.73-0.99 (Cu-Be plate (0,6) 0.93, (2,1) 0.73; glass plate 0.95-0.96; steel ring (2,0) 0.99), the steel ring's
# in-plane n = 2 0.001, the glass plate's in-plane mode 0.17, where a picture coloured by w shows little but round-off
IN_PLANE_SHARE = 0.3
VIEWS = ("iso", "top", "bottom", "iso+bottom")
WINDOW_SIZE = (1000, 650)  # pixels of a picture
TUBE = {"line_width": 4, "render_lines_as_tubes": True}  # outlines and hatching
LABEL = {"font_size": 11, "text_color": "black", "always_visible": True}  # feet, named points, the scale bar
LIFT = 2e-3  # markers are lifted off the surface by this fraction of the device's size (no z-fighting)
# a round part's bonded face is outlined by circles whose displacement is read this fraction of the face's radial width
# inside its walls: a meshed wall's quadratic arcs lie up to 1.06 % of the radius inside the circle (four per circle,
# an O-grid foot: modalfe.models.wall_geometry), and a point between them and the circle lies in no element
PROBE_INSET = 0.05


@dataclass(frozen=True)
class Marker:
    """A marked face group: ``poly`` at rest with point data ``displacement``; ``normal`` is the outward
    normal (axis, sign) of its faces, the direction it is seen from; ``outline`` when the face is bonded
    to another part and only its edge shows."""

    group: str
    kind: str
    colour: str
    poly: object
    normal: tuple[int, int]
    outline: bool

    def seen_from(self) -> tuple[str, ...]:
        """The views of ``render_mode`` that look at this marker's side of the device."""
        axis, sign = self.normal
        if axis == 2:
            return ("top", "iso") if sign > 0 else ("bottom",)
        return ("iso",) if sign > 0 else ()


def mode_grid(mode):
    """``pyvista.UnstructuredGrid`` of the whole device with point data ``displacement`` (mass-normalised mode
    shape), ``w`` (its z component) and ``magnitude`` (its length), cell data ``part`` (index into field data),
    ``element`` and ``vertices`` (``whole_device_mesh``'s cell number and the cell's point ids), which the surface's
    faces carry into the element they bound."""
    import pyvista as pv

    model = mode.model
    if isinstance(model, AxisymmetricModel):  # the meridian mesh swept round the axis, the mode revolved on it
        points, cells, probes, _, part_id = model.revolved_mesh
        fields = {"displacement": np.asarray(probes @ mode.shape).reshape(3, -1).T}
        kind, names = VTK_HEXAHEDRON, [reg.part for reg in model.section.regions]
    else:
        shape = model.nodal_displacement(mode.shape)  # at the vertices, which the cells drawn use
        points, cells, kind, fields, part_id, names = whole_device_mesh(model, {"displacement": shape})
    n = cells.shape[1]
    grid = pv.UnstructuredGrid(np.hstack([np.full((len(cells), 1), n), cells]).ravel(),
                               np.full(len(cells), kind, dtype=np.uint8), points)
    grid.point_data["displacement"] = fields["displacement"]
    grid.point_data["w"] = fields["displacement"][:, 2]
    grid.point_data["magnitude"] = np.linalg.norm(fields["displacement"], axis=1)
    grid.cell_data["part"] = part_id
    grid.field_data["part_names"] = np.array(names)
    if mirror_planes(model.scene):  # merge the mirrored copies of the points on the symmetry planes
        grid = grid.clean(tolerance=1e-9 * float(np.ptp(points, axis=0).max()), produce_merge_map=False)
    grid.cell_data["element"] = np.arange(len(cells))  # clean() keeps the cells and their order
    grid.cell_data["vertices"] = grid.cell_connectivity.reshape(len(cells), -1)  # after clean(): merged point ids
    return grid


def coloured_by(surface) -> str:
    """The point data a picture is coloured by: ``w`` when the normal displacement carries the mode (its rms over
    the surface's vertices at least IN_PLANE_SHARE of the displacement's), else ``magnitude`` (an in-plane mode)."""
    u = surface.point_data["displacement"]
    share = float(np.sqrt(np.mean(u[:, 2] ** 2) / (np.mean(np.sum(u ** 2, axis=1)) or 1.0)))
    return "w" if share >= IN_PLANE_SHARE else "magnitude"


def marker_kind(scene, group: str) -> str | None:
    """The role a face group is marked with, or None: feet by name, the others by the scene's tables."""
    if group.startswith("foot"):
        return "foot"
    for kind, table in (("electrode", scene.electrodes), ("clamp", scene.clamps), ("guide", scene.guides),
                        ("spring", scene.springs), ("mass", scene.masses)):
        if group in table:
            return kind
    return None


def marker_set(mode, surface=None) -> list[Marker]:
    """Every marked face group of the whole device, as found on its (undeformed) surface."""
    scene = mode.model.scene
    if surface is None:
        surface = mode_grid(mode).extract_surface(algorithm=None)
    assembly = scene.full_assembly()
    size = float(np.ptp(surface.points, axis=0).max())
    tol = 1e-6 * size
    centres = surface.cell_centers().points
    areas = surface.compute_cell_sizes(length=False, volume=False).cell_data["Area"]
    found: dict[tuple[str, bool, tuple[int, int]], list] = {}
    drawn: set[str] = set()
    for group, faces in assembly.faces.items():
        kind = marker_kind(scene, group)
        if kind is None:
            continue
        for face in faces:
            rect = assembly.face_rect(face)
            if rect is None:  # a curved wall or a geometry file's surface: the face group's own mesh facets
                if group not in drawn:
                    drawn.add(group)
                    _facet_marker(mode, group, kind, surface, centres, tol, size, found)
                continue
            axis, c, lo, hi = rect
            sign = -1 if face.side.endswith("min") else 1
            inplane = [k for k in range(3) if k != axis]
            on = np.abs(centres[:, axis] - c) < tol
            for k in inplane:
                on &= (centres[:, k] > lo[k] - tol) & (centres[:, k] < hi[k] + tol)
            area = float(np.prod([hi[k] - lo[k] for k in inplane]))
            exposed = float(areas[on].sum()) / area if area else 0.0
            lift = np.zeros(3)
            if exposed > 0.5:  # an outer face: its own surface cells, lifted outwards
                poly = surface.extract_cells(np.flatnonzero(on)).extract_surface(algorithm=None)
                lift[axis] = sign * LIFT * size
                poly.points = poly.points + lift
                found.setdefault((group, False, (axis, sign)), []).append((kind, poly))
            else:  # bonded: its outline, just outside the face, on the exposed surface of the neighbour
                poly = _outline(mode, assembly.part(face.part), axis, c, lo, hi, grow=3 * LIFT * size,
                                lift=-sign * LIFT * size)
                found.setdefault((group, True, (axis, -sign)), []).append((kind, poly))
    out = []
    for (group, outline, normal), pieces in found.items():
        kind = pieces[0][0]
        poly = pieces[0][1] if len(pieces) == 1 else pieces[0][1].merge([p for _, p in pieces[1:]])
        out.append(Marker(group, kind, MARKERS[kind], poly, normal, outline))
    return out


def _facet_marker(mode, group: str, kind: str, surface, centres: np.ndarray, tol: float, size: float,
                  found: dict) -> None:
    """The surface cells on the mesh facets of face group ``group`` (those of the solved model: a symmetric model
    marks its kept half), lifted along their outward normals; a group with no facet on the surface (bonded
    between two parts) is not drawn."""
    from scipy.spatial import cKDTree

    if isinstance(mode.model, AxisymmetricModel):
        on = np.flatnonzero(mode.model.on_face(group, centres, 10 * tol))
    else:
        mesh = mode.model.mesh.mesh
        facets = mesh.facets[:, mode.model.mesh.faces[group]]
        at = mesh.p[:, facets].mean(axis=1).T  # facet centroids (corner nodes)
        distance, _ = cKDTree(at).query(centres, distance_upper_bound=10 * tol)
        on = np.flatnonzero(np.isfinite(distance))
    if not len(on):
        return
    poly = surface.compute_normals(cell_normals=True, point_normals=True, split_vertices=False).extract_cells(on)
    poly = poly.extract_surface(algorithm=None)
    normal = poly.cell_data["Normals"].mean(axis=0)
    axis = int(np.argmax(np.abs(normal)))
    poly.points = poly.points + LIFT * size * poly.point_data["Normals"]
    found.setdefault((group, False, (axis, 1 if normal[axis] > 0 else -1)), []).append((kind, poly))


def _outline(mode, part, axis: int, c: float, lo, hi, *, grow: float, lift: float):
    """The outline of ``part``'s face in the plane x[axis] = c: the rectangle (lo, hi), or a round part's circles (its
    outer and inner radii), grown by ``grow`` and lifted by ``lift`` along the axis, as closed polylines with point
    data ``displacement`` (the mode's, probed on the face itself, inside the device: a rectangle's corners round a
    disc's face, or a ring's hole, would lie off it)."""
    import pyvista as pv

    u_axis, v_axis = [k for k in range(3) if k != axis]
    if hasattr(part, "radii"):
        angle = np.linspace(0.0, 2 * np.pi, 100, endpoint=False)
        circle = np.column_stack([np.cos(angle), np.sin(angle)])
        inner, outer = part.radii
        inset = PROBE_INSET * (outer - inner)  # read inside a meshed wall, whose arcs deviate from the circle
        rings = [(r + (inset if r == inner else -inset), r + grow if r == outer else max(r - grow, 0.0))
                 for r in part.radii if r > 0]
        uv = np.vstack([np.asarray(part.centre)[[u_axis, v_axis]] + drawn * circle for _, drawn in rings])
        on = np.vstack([np.asarray(part.centre)[[u_axis, v_axis]] + r * circle for r, _ in rings])
        loops = [np.arange(k * len(angle), (k + 1) * len(angle)) for k in range(len(rings))]
    else:
        corners = [(lo[u_axis] - grow, lo[v_axis] - grow), (hi[u_axis] + grow, lo[v_axis] - grow),
                   (hi[u_axis] + grow, hi[v_axis] + grow), (lo[u_axis] - grow, hi[v_axis] + grow)]
        uv = np.vstack([np.linspace(a, b, 25, endpoint=False) for a, b in zip(corners, corners[1:] + corners[:1])])
        on = np.column_stack([np.clip(uv[:, 0], lo[u_axis], hi[u_axis]), np.clip(uv[:, 1], lo[v_axis], hi[v_axis])])
        loops = [np.arange(len(uv))]
    points, probe = np.zeros((len(uv), 3)), np.zeros((len(uv), 3))
    points[:, u_axis], points[:, v_axis], points[:, axis] = uv[:, 0], uv[:, 1], c + lift
    probe[:, u_axis], probe[:, v_axis], probe[:, axis] = on[:, 0], on[:, 1], c
    poly = pv.PolyData(points, lines=np.concatenate([np.r_[len(loop) + 1, loop, loop[0]] for loop in loops]))
    poly.point_data["displacement"] = mode.displacement(probe)
    return poly


def quiet_vtk(verbose: bool = False) -> None:
    """Silence VTK's own warnings (an offscreen window without X prints one per render) unless ``verbose``."""
    from vtkmodules.vtkCommonCore import vtkLogger, vtkObject

    vtkObject.SetGlobalWarningDisplay(int(verbose))
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_INFO if verbose else vtkLogger.VERBOSITY_OFF)


def symmetry_note(scene) -> str:
    """'' for a whole model, else e.g. 'whole device drawn from the half model about y = 19 mm'."""
    planes = mirror_planes(scene)
    if not planes:
        return ""
    model = {1: "half", 2: "quarter", 3: "eighth"}[len(planes)]
    about = " and ".join(f"{'xyz'[axis]} = {1e3 * twice / 2:g} mm"
                         + (" (antisymmetric)" if "xyz"[axis] in scene.antisymmetry else "") for axis, twice in planes)
    return f"whole device drawn from the {model} model about {about}"


def mode_title(mode) -> str:
    """'cube_plate: (0,6)  39807.5 Hz +- 0.28 %  (3-D solid, half model)': the mode, its frequency with its stated
    error (or why there is none) and the model that answered."""
    error = mode.error_estimate
    stated = ("error not estimated" if np.isnan(error) else "error unresolved" if np.isinf(error)
              else f"+- {100 * error:.2g} %")
    planes = mirror_planes(mode.model.scene)
    model = {0: "whole", 1: "half", 2: "quarter", 3: "eighth"}[len(planes)]
    fidelity = {"Model": "3-D solid", "PlateModel": "plate", "BeamModel": "beam",
                "AxisymmetricModel": "axisymmetric"}.get(type(mode.model).__name__, type(mode.model).__name__)
    return f"{mode.model.scene.name}: {mode.label}  {mode.frequency:.1f} Hz {stated}  ({fidelity}, {model} model)"


def _scale(grid, amplification: float) -> float:
    size = float(np.ptp(grid.points, axis=0).max())
    peak = float(np.abs(grid.point_data["displacement"]).max()) or 1.0
    return amplification * size / peak


def _deformed(poly, scale: float):
    moved = poly.copy()
    moved.points = poly.points + scale * poly.point_data["displacement"]
    return moved


def surface_field(mode, surface):
    """``surface`` (``mode_grid``'s, triangulated) with every triangle split in SUBDIVISIONS**2 (``subdivided``) and
    point data ``w``, the mode's own field at every new point, read in the element the triangle bounds at the same
    reference coordinates (a curved element's face, where the drawn chord may cross a ring's hole, included: no
    point search, no parts' exact shapes asked)."""
    fine = subdivided(surface, SUBDIVISIONS)
    if isinstance(mode.model, AxisymmetricModel):  # the revolved field at the points themselves
        P = mode.model.displacement_probes(_onto_body(mode.model, np.asarray(fine.points, dtype=float)))
    else:
        P = mode.model.element_probes(fine.point_data["element"], fine.point_data["corners"],
                                      fine.point_data["weights"])
    fine.point_data["w"] = np.asarray(P @ mode.shape).reshape(3, -1)[2]
    return fine


def _onto_body(model, points: np.ndarray) -> np.ndarray:
    """``points`` (n, 3) [m] of a revolved drawing (``AxisymmetricModel.revolved_mesh``), those off the body moved
    along their radius onto the nearest part: the drawing's chords cut inside a round wall by up to r (1 - cos(pi /
    sectors)), 1.2e-3 r at 64 sectors, into a ring's hole."""
    assembly = model.scene.assembly()
    off = ~assembly.holding(points.T).any(axis=1)
    if not off.any():
        return points
    d = points[off] - model.section.origin
    along = np.outer(d @ model.section.axis, model.section.axis)
    r = np.linalg.norm(d - along, axis=1)
    moved, best = points[off].copy(), np.full(len(r), np.inf)
    for part in assembly.parts:
        radius = np.clip(r, *part.radii)
        candidate = model.section.origin + along + (d - along) * (radius / np.maximum(r, 1e-300))[:, None]
        better = part.inside(candidate, assembly.tolerance) & (np.abs(radius - r) < best)
        moved[better], best[better] = candidate[better], np.abs(radius - r)[better]
    out = points.copy()
    out[off] = moved
    return out


def nodal_lines(mode, surface):
    """The zero contour of the normal displacement w on ``surface`` (``surface_field``: the mode's own field on a
    subdivided surface, so smooth lines, not the zig-zag of a linear interpolation between the drawn vertices); point
    data ``displacement`` is the drawn surface's (linear between its vertices), so that the deformed lines lie on the
    deformed surface drawn."""
    return surface_field(mode, surface).contour([0.0], scalars="w")


def subdivided(surface, n: int):
    """``surface`` triangulated, each triangle split in n**2 on its barycentric lattice, in double precision (VTK's
    own subdivision returns single-precision points, up to 1e-7 of the size off the drawn surface); the triangles do
    not share their new points (a contour needs no more). Point data ``displacement``: the surface's, interpolated
    linearly; ``element``: the cell the point's triangle bounds (the surface's cell data, ``mode_grid``), ``corners``
    (n, 3) the positions of the triangle's corners in that cell's vertex list, ``weights`` (n, 3) the point's
    barycentric coordinates on them."""
    import pyvista as pv

    tri = surface.triangulate()
    triangles = tri.faces.reshape(-1, 4)[:, 1:]
    corners = tri.points[triangles]  # (triangles, 3, 3)
    lattice = [(a, b) for a in range(n + 1) for b in range(n + 1 - a)]
    index = {ab: k for k, ab in enumerate(lattice)}
    bary = np.array([(a, b, n - a - b) for a, b in lattice], dtype=float) / n
    small = [(index[a, b], index[a + 1, b], index[a, b + 1]) for a, b in lattice if a + b < n]
    small += [(index[a + 1, b], index[a + 1, b + 1], index[a, b + 1]) for a, b in lattice if a + b < n - 1]
    points = np.einsum("kc,tcd->tkd", bary, corners).reshape(-1, 3)
    cells = (np.arange(len(corners))[:, None, None] * len(lattice) + np.array(small)[None]).reshape(-1, 3)
    fine = pv.PolyData(points, np.column_stack([np.full(len(cells), 3), cells]).ravel())
    fine.point_data["displacement"] = np.einsum("kc,tcd->tkd", bary, tri.point_data["displacement"][triangles])\
        .reshape(-1, 3)
    fine.point_data["element"] = np.repeat(tri.cell_data["element"], len(lattice))
    ids = tri.point_data["vtkOriginalPointIds"][triangles]  # (triangles, 3): the grid's point ids
    corners = np.argmax(tri.cell_data["vertices"][:, None, :] == ids[:, :, None], axis=2)
    fine.point_data["corners"] = np.repeat(corners, len(lattice), axis=0)
    fine.point_data["weights"] = np.tile(bary, (len(corners), 1))
    return fine


def named_points(mode):
    """The scene's named output points (``drive.outputs`` given as (name, (x, y, z)) [m]) as PolyData with the mode's
    displacement, and their names; (None, []) when it names none."""
    import pyvista as pv

    named = [item for item in mode.model.scene.drive.outputs if not isinstance(item, str)]
    if not named:
        return None, []
    points = pv.PolyData(np.array([xyz for _, xyz in named], dtype=float))
    points.point_data["displacement"] = mode.displacement(points.points)
    return points, [name for name, _ in named]


def _edges(poly):
    """The boundary of a marked patch (its outline), with the patch's point data."""
    return poly.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                      non_manifold_edges=False)


def _hatch(marker: Marker, size: float):
    """Short strokes from the outline of a clamped face, outwards and slanted (the engineering symbol of a fixed
    support), carrying the displacement of the point they start from."""
    import pyvista as pv

    edge = _edges(marker.poly)
    if not edge.n_points:
        return None
    axis, sign = marker.normal
    slant = np.zeros(3)
    slant[axis] = sign
    slant[(axis + 1) % 3] = 1.0
    start = edge.points[:: max(1, edge.n_points // 24)]
    end = start + 0.04 * size * slant / np.linalg.norm(slant)
    n = len(start)
    lines = np.column_stack([np.full(n, 2), np.arange(n), np.arange(n) + n]).ravel()
    strokes = pv.PolyData(np.vstack([start, end]), lines=lines)
    at = edge.point_data["displacement"][:: max(1, edge.n_points // 24)]
    strokes.point_data["displacement"] = np.vstack([at, at])
    return strokes


def _scale_bar(bounds, size: float):
    """A bar of a round length (1, 2 or 5 x 10^k m, about a quarter of the device) along x in front of the device,
    ending at its corner nearest the iso view (largest x and y), and its label; zero displacement (it does not move
    in an animation)."""
    import pyvista as pv

    target = 0.25 * size
    step = 10.0 ** np.floor(np.log10(target))
    length = max(m * step for m in (1, 2, 5) if m * step <= target)
    x1, y0, z0 = bounds[1], bounds[3] + 0.08 * size, bounds[4]
    bar = pv.Line((x1 - length, y0, z0), (x1, y0, z0))
    bar.point_data["displacement"] = np.zeros((bar.n_points, 3))
    return bar, f"{1e3 * length:g} mm"


def _set_view(plotter, view: str) -> None:
    if view == "top":
        plotter.view_xy()
    elif view == "bottom":
        plotter.view_xy(negative=True)
    else:
        plotter.view_isometric()
    plotter.reset_camera()  # fit the whole deformed device with its markers and bar: nothing cropped


def _views(view: str) -> list[str]:
    """The panels of ``view`` ("iso+bottom": two), ValueError naming ``view`` where it is none of VIEWS."""
    if view not in VIEWS:
        raise ValueError(f"view: must be one of {VIEWS}, got '{view}'")
    return view.split("+")


def mode_plotter(view: str = "iso", *, window_size: tuple[int, int] = WINDOW_SIZE,
                 off_screen: bool = True) -> pyvista.Plotter:
    """The empty plotter ``render_mode`` draws ``view`` in: a panel a view, and the colour bar's at the right."""
    import pyvista as pv

    n = len(_views(view))
    plotter = pv.Plotter(off_screen=off_screen, window_size=list(window_size), shape=(1, n + 1),
                         col_weights=[6] * n + [2.5], border=False)
    plotter.set_background("white")
    return plotter


def render_mode(mode, *, out: str | None = None, window_size=WINDOW_SIZE, amplification: float = 0.05,
                view: str = "iso", off_screen: bool = True, plotter=None):
    """Render ``mode`` deformed (largest displacement = ``amplification`` x the device's size).

    ``view``: "iso", "top", "bottom" or "iso+bottom" (two panels). The colour bar and the legend have their own
    panel at the right. ``plotter``: the empty one to draw in, ``mode_plotter(view, ...)``'s (made before the mode
    was known; ``window_size`` and ``off_screen`` are then its own), else a new one. Returns the
    Plotter (``plotter._modalfe``: ``overlays``, the (rest PolyData, actor) pairs an animation moves; ``markers``,
    the Marker list; ``views``); with ``out`` it also writes a PNG."""
    import pyvista as pv

    quiet_vtk()
    views = _views(view)
    grid = mode_grid(mode)
    scale = _scale(grid, amplification)
    faces = grid.extract_surface(algorithm=None)
    markers = marker_set(mode, faces)  # on the mesh's own facets, which the face groups' facets match
    # triangles: drawn as the nodal lines' subdivision splits them, so that the lines lie on the drawn surface
    surface = faces.triangulate()
    colour = coloured_by(surface)
    limit = float(np.abs(surface.point_data[colour]).max()) or 1.0
    size = float(np.ptp(surface.points, axis=0).max())
    # an in-plane mode's w is near zero, its zero contour traces round-off: no nodal lines drawn
    nodal = nodal_lines(mode, surface) if colour == "w" else pv.PolyData()
    bar, bar_text = _scale_bar(surface.bounds, size)
    points, names = named_points(mode)
    if plotter is None:
        plotter = mode_plotter(view, window_size=window_size, off_screen=off_screen)
    overlays, device_actor = [], None
    note = symmetry_note(mode.model.scene)

    def draw(rest, name: str, **style):  # an overlay that moves with the body
        actor = plotter.add_mesh(_deformed(rest, scale), name=name, **style)
        overlays.append((rest, actor))
        return actor

    for col, v in enumerate(views):
        plotter.subplot(0, col)
        actor = draw(surface, f"device:{v}", scalars=colour, show_scalar_bar=False,
                     **({"cmap": "RdBu_r", "clim": [-limit, limit]} if colour == "w" else
                        {"cmap": "viridis", "clim": [0.0, limit]}))
        device_actor = device_actor or actor
        if nodal.n_points:
            draw(nodal, f"nodal:{v}", color="black", line_width=3)
        for i, m in enumerate(markers):
            if m.outline or m.kind not in ("electrode", "clamp"):
                draw(m.poly, f"marker:{m.group}:{i}:{v}", color=m.colour, **(TUBE if m.outline else {}))
                continue
            # a face: translucent fill, and its outline (electrode) or hatching (clamp) as the marker
            # triangles, split as the body's are: a quad deformed out of plane would cross the body's own triangles
            draw(m.poly.triangulate(), f"fill:{m.group}:{i}:{v}", color=m.colour, opacity=FILL_OPACITY)
            edge = _hatch(m, size) if m.kind == "clamp" else _edges(m.poly)
            if edge is not None and edge.n_points:
                draw(edge, f"marker:{m.group}:{i}:{v}", color=m.colour, **TUBE)
            if m.kind == "clamp":  # its outline too, drawn thin
                draw(_edges(m.poly), f"outline:{m.group}:{i}:{v}", color=m.colour, line_width=2)
        for m in markers:  # feet named where the view sees them
            if m.kind == "foot" and v in m.seen_from():
                plotter.add_point_labels(_deformed(m.poly, scale).center_of_mass()[None, :], [m.group],
                                         shape_opacity=0.5, name=f"label:{m.group}:{v}", **LABEL)
        if points is not None:  # drawn in every panel, named in the first (a label shows through the body)
            draw(points, f"points:{v}", color="black", point_size=12, render_points_as_spheres=True)
            if col == 0:
                plotter.add_point_labels(_deformed(points, scale).points, names, shape_opacity=0.5, show_points=False,
                                         name="point_labels", **LABEL)
        plotter.add_mesh(bar, color="black", line_width=4, name=f"scale:{v}")
        plotter.add_point_labels(bar.points.mean(axis=0)[None, :], [bar_text], shape_opacity=0.0, show_points=False,
                                 name=f"scale_label:{v}", **LABEL)
        plotter.add_axes(color="black", line_width=2, viewport=(0, 0, 0.18, 0.22))
        text = f"{mode_title(mode)}\n{note}" if note else mode_title(mode)
        plotter.add_text(f"{text}\nview: {v}" if col == 0 else f"view: {v}", position="upper_left", font_size=10,
                         color="black")
        _set_view(plotter, v)
    plotter.subplot(0, len(views))
    plotter.add_scalar_bar(COLOUR_BAR_TITLES[colour], mapper=device_actor.mapper, vertical=True, color="black",
                           position_x=0.3, position_y=0.36, width=0.35, height=0.5, title_font_size=11,
                           label_font_size=10, fmt="%.2g")
    kinds = dict.fromkeys(m.kind for m in markers)
    entries = [[LEGEND[k], MARKERS[k]] for k in kinds] + ([["nodal line", "black"]] if nodal.n_points else [])
    entries += [["named point", "black"]] if names else []
    if entries:
        plotter.add_legend(labels=entries, bcolor="white", face="rectangle", loc="lower left",
                           size=(0.95, 0.045 * len(entries)))
    plotter.subplot(0, 0)
    plotter._modalfe = {"overlays": overlays, "markers": markers, "views": views}
    if out:  # through Pillow: pyvista refuses an upper-case .PNG
        from PIL import Image

        Image.fromarray(plotter.screenshot(return_img=True)).save(out, format="PNG")
    return plotter


def animate_mode(mode, out: str, *, frames: int = 16, amplification: float = 0.08,
                 window_size=(900, 520), view: str = "iso") -> str:
    """Write an animated GIF of one period of ``mode`` to ``out``: the body, its nodal lines and every
    marker move together; returns the path."""
    grid = mode_grid(mode)
    scale = _scale(grid, amplification)
    plotter = render_mode(mode, amplification=amplification, window_size=window_size, view=view)
    # pyvista writes only a lower-case .gif: a temporary one beside ``out`` (x.GIF), renamed when complete
    handle, partial = tempfile.mkstemp(suffix=".gif", dir=os.path.dirname(os.path.abspath(out)))
    os.close(handle)
    try:
        plotter.open_gif(partial)
        for phase in np.linspace(0, 2 * np.pi, frames, endpoint=False):
            for rest, actor in plotter._modalfe["overlays"]:
                actor.mapper.dataset.points = rest.points + scale * np.cos(phase) * rest.point_data["displacement"]
            plotter.write_frame()
        plotter.close()
        os.replace(partial, out)
    finally:
        if os.path.exists(partial):
            os.remove(partial)
    return out
