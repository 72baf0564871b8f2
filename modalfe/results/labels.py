"""Mode labels from the mode shape: plate (a,b) nodal-line counts, beam kind and order, and the
rigid-body names of suspension modes. A device's working mode is found by label, never by index.

Plate labels count nodal lines of the normal displacement w over the device's main parts:
``(a,b)`` has ``a`` nodal lines along x (sign changes met walking along y) and ``b`` nodal lines
across x (met walking along x), so the Cu-Be plate's working mode is ``(0,6)``. Each count is read on
the rows (columns) of a grid over the plate that carry a significant w and lie in its outer quarters: the
count most of them agree on (the smaller on a tie), so that nodal lines that curve or join near an edge
are outvoted and a closed nodal curve inside the plate (e.g. round a centre mass) does not change it. Beam labels
(``bending-z 6``, ``bending-y 2``, ``torsion 1``, ``axial 1``) take the dominant cross-section motion
and its order (sign changes along x, plus one: the count for a cantilever).

All modes of one solve are labelled together by ``unique_labels``, which makes labels unique: two
modes within 1e-3 relative frequency (a degenerate pair, whose shapes are any basis of a plane) are
first rotated within their span to the basis with the clearest patterns, so the pair's labels do
not depend on the basis the eigen solver returned; then, of several modes with the same pattern,
the one with the clearest pattern (fewest closed nodal curves, then lowest frequency) keeps the
plain label and the others, by frequency, get ``#2``, ``#3``... (``(1,1)#2``). A mode more than half of
whose kinetic energy is in the scene's attached masses (``CARRIED``) is that mass bouncing, rocking or
twisting on the structure, not the structure's own pattern: it yields the plain label to any mode that is not
(the honeycomb tile's 2.3 kg actuator pad twists at ~970 Hz with a clear (1,1) on the facing and 97 % of the
kinetic energy in the pad, the plate's own twisting mode at ~1119 Hz has 2 %). The suffix only
tells modes of one solve apart: ``Modes.labelled`` and ``select`` with a frequency pick the nearest
mode of the pattern whatever its suffix.

Discs and rings (a device whose main part has an ``axis``) are labelled in polar coordinates about that axis
instead (``disc_label``): flexural modes ``(d,c)`` with ``d`` nodal diameters and ``c`` nodal circles, the
boundary not counted (Leissa, "Vibration of Plates", NASA SP-160, 1969, ch. 2: the free disc's fundamental is
``(2,0)``, the clamped disc's ``(0,0)``); in-plane modes ``R1``, ``R2``... (radial, axisymmetric; the order is the
radial sign changes of u_r plus one), ``T1``... (circumferential, axisymmetric), ``n=2``, ``n=3``... (n waves
round the circumference: a ring's in-plane flexural modes; ``n=2 k=2`` for the second radial order; also a twist
odd through the thickness with next to no motion along the axis, ``_NO_AXIAL``: a thick cylinder's torsion ``T1``),
and ``thickness`` (u along the axis odd through the thickness). A field whose energy is not mostly one harmonic of
the angle is ``?``.
"""

from __future__ import annotations

import itertools
import re

import numpy as np

RIGID_NAMES = ("sway-x", "sway-y", "heave", "roll", "pitch", "yaw")
CARRIED = 0.5  # attached masses' share of a mode's kinetic energy above which it is the masses' own mode
_SMALL = 0.08  # samples below this fraction of the line's peak carry no sign (noise near nodal lines)
# a field odd through the thickness whose motion along the axis carries less energy than this fraction of its in-plane
# motion is no bending mode but a twist: a bending wave's in-plane share is ~(k h)^2 / 12 of its u_z's (Kirchhoff), so
# this needs k h > 11, a wavelength under 0.6 thicknesses (a thick cylinder's own torsion mode has u_z = 0)
_NO_AXIAL = 0.1
_LINE = 0.25  # a grid line whose peak |w| is below this fraction of the plate's peak does not vote
_ISLAND = 0.02  # a closed nodal region counts if its peak |w| is above this fraction of the plate's peak
_RIGID = 0.98  # main parts moving 98 % as a rigid body: a suspension mode (plate modes reach ~0.9)
# an eigenvalue (omega^2) below this fraction of a solve's highest is a free body's rigid-body mode (~0 Hz): it is named
# as one whatever its fit (the solver's zero-frequency space mixes in elastic noise that a fit of 98 % may miss)
RIGID_FRACTION = 1e-6
DEGENERATE = 1e-3  # relative frequency gap below which two modes are a degenerate pair
_ANGLES = 36  # rotations tried within a degenerate pair's span (every 2.5 degrees of a quarter turn)
SUFFIX = "#"  # ``(0,3)#2``: the second mode of one solve with the pattern ``(0,3)``


# every label ``label`` gives (or a plate family with ``n`` for any count), with an optional ambiguity suffix
LABEL_FORM = re.compile(r"(\((\d+|n),(\d+|n)\)|(axial|bending-y|bending-z|torsion) \d+|in-plane|thickness|\?|[RT]\d+"
                        r"|n=\d+( k=\d+)?|" + "|".join(RIGID_NAMES) + r")(#\d+)?")


def check_selector(selector: object, field: str = "mode") -> str:
    """``selector`` when it has the form of a mode label or family (``(0,6)``, ``(0,n)``, ``bending-z 6``, ``heave``,
    ``in-plane#2``...), checked before any solve; SceneError naming ``field`` otherwise (a number is an index, which
    only ``modalfe show --mode N`` takes)."""
    from modalfe.errors import SceneError

    if not isinstance(selector, str) or not selector.strip():
        raise SceneError(f"{field}: must be a label such as '(0,6)' or 'bending-z 6', got {selector!r}")
    if selector.strip().lstrip("+-").isdigit():
        raise SceneError(f"{field}: '{selector}' is a number, not a mode label such as '(0,6)', 'bending-z 6' or "
                         f"'heave' (labels name modes; an index among the computed modes is `modalfe show --mode N`)")
    if not LABEL_FORM.fullmatch(selector.strip()):
        raise SceneError(f"{field}: '{selector}' is not a mode label: labels are '(A,B)' (a family '(0,n)'), "
                         f"'bending-z N', 'bending-y N', 'torsion N', 'axial N', 'in-plane', a rigid motion "
                         f"({', '.join(RIGID_NAMES)}), or a disc's 'RN', 'TN', 'n=N', 'thickness'; '#2' for the second")
    return selector.strip()


def base_label(name: str) -> str:
    """The pattern of a label without its ambiguity suffix: ``(0,3)#2`` -> ``(0,3)``."""
    return name.split(SUFFIX, 1)[0]


def label(model, x: np.ndarray) -> tuple[str, float]:
    """(label, wavelength along x [m] or NaN) of the full DOF vector ``x`` of any assembled model (solid, plate
    or beam), read from its ``label_field`` (the whole device's main surfaces or vertices): a rigid-body name
    for an unsupported body moving rigidly, else the disc label of a device whose main part has an axis, or the
    beam or plate label of the scene's kind."""
    points, u = model.label_field(x)
    name, wavelength, _ = _describe(model.scene, points, u, axial=axial_frame(model.scene))
    return name, wavelength


def unique_labels(model, shapes: np.ndarray, frequencies, carried=None) -> list[tuple[str, float]]:
    """(label, wavelength [m] or NaN) of every mode of one solve (``shapes`` (n_dofs, n_modes) full DOF
    vectors, ``frequencies`` [Hz] ascending), unique within the solve: degenerate pairs rotated to their
    clearest basis (none on a model whose ``pairs_apart``: the axisymmetric one solves one member per pair),
    repeated patterns suffixed ``#2``, ``#3``... (module docstring); ``carried`` (n_modes,) the attached
    masses' share of each mode's kinetic energy (``attached_share`` of the models), None for none."""
    f = np.asarray(frequencies, dtype=float)
    n = len(f)
    carried = np.zeros(n, dtype=bool) if carried is None else np.asarray(carried) > CARRIED
    fields = [model.label_field(shapes[:, i]) for i in range(n)]
    axial = axial_frame(model.scene)
    rigid = f**2 < RIGID_FRACTION * float(np.max(f**2, initial=0.0))
    described: list[tuple[str, float, float]] = [None] * n  # type: ignore[list-item]
    i = 0
    while i < n:
        j = i + 1
        while j < n and abs(f[j] - f[j - 1]) <= DEGENERATE * max(abs(f[j]), 1e-300):
            j += 1
        if j - i == 2 and f[i] > 0 and not rigid[i] and not getattr(model, "pairs_apart", False):
            described[i], described[i + 1] = _pair(model.scene, fields[i], fields[i + 1], axial)
        else:
            for k in range(i, j):
                described[k] = _describe(model.scene, *fields[k], axial=axial, rigid=bool(rigid[k]))
        i = j
    groups: dict[str, list[int]] = {}
    for k, (name, _, _) in enumerate(described):
        groups.setdefault(name, []).append(k)
    out = [(name, wavelength) for name, wavelength, _ in described]
    for name, members in groups.items():
        if len(members) < 2:
            continue
        # not carried by attached masses, then clearest, then lowest
        plain = min(members, key=lambda k: (bool(carried[k]), -round(described[k][2], 6), f[k]))
        rest = [k for k in members if k != plain]
        for number, k in enumerate(rest, start=2):
            out[k] = (f"{name}{SUFFIX}{number}", out[k][1])
    return out


def _describe(scene, points: np.ndarray, u: np.ndarray, grid=None, axial=None,
              rigid: bool = False) -> tuple[str, float, float]:
    """(label, wavelength, clarity in [0, 1]) of one displacement field of the main parts; ``axial`` the
    (axis, centre) of a disc or ring device (``axial_frame``), else None; ``rigid`` for a mode at ~0 Hz
    (``RIGID_FRACTION``), named as a rigid motion on an unclamped body."""
    if not scene.clamps:  # only a free or spring-supported body has rigid-body modes
        name, fraction, purity = _rigid(points, u)
        if rigid or fraction > _RIGID:
            return name, float("nan"), purity
    if axial is not None:
        name, clarity = _disc(points, u, *axial)
        return name, float("nan"), clarity
    if scene.kind == "beam":
        name, purity = _beam(points, u)
        return name, float("nan"), purity
    return _plate(points, u, grid)


def _pair(scene, first, second, axial=None) -> tuple[tuple[str, float, float], tuple[str, float, float]]:
    """Labels of a degenerate pair: the basis of the pair's span (rotations over a quarter turn) whose two
    shapes have the clearest patterns; the two labels are returned in sorted order (their frequencies are
    equal to the pair's precision, so which eigenvector carries which is arbitrary)."""
    (p, u1), (_, u2) = first, second
    n1, n2 = np.sqrt(np.sum(u1**2)), np.sqrt(np.sum(u2**2))
    u1, u2 = u1 / max(n1, 1e-300), u2 / max(n2, 1e-300)
    plate = scene.kind != "beam" and axial is None
    g1 = _grid_w(p, u1) if plate else None
    g2 = _grid_w(p, u2) if plate else None
    best, best_score = None, -1.0
    for theta in np.linspace(0.0, np.pi / 2, _ANGLES, endpoint=False):
        c, s = np.cos(theta), np.sin(theta)
        grids = (None, None)
        if plate:
            grids = ((g1[0], g1[1], c * g1[2] + s * g2[2]), (g1[0], g1[1], -s * g1[2] + c * g2[2]))
        a = _describe(scene, p, c * u1 + s * u2, grids[0], axial)
        b = _describe(scene, p, -s * u1 + c * u2, grids[1], axial)
        score = a[2] + b[2] + 0.5 * (a[0] != b[0])  # prefer two clear and different patterns
        if score > best_score + 1e-9:
            best, best_score = (a, b), score
    a, b = sorted(best, key=lambda d: d[0])
    return a, b


def rigid_motion(points: np.ndarray, u: np.ndarray) -> tuple[str, float]:
    """Best rigid-body fit u ~ t + theta x (r - rc): (name of its largest component, energy fraction)."""
    name, fraction, _ = _rigid(points, u)
    return name, fraction


def _rigid(points: np.ndarray, u: np.ndarray) -> tuple[str, float, float]:
    """(name, fitted energy fraction, purity: the largest component's share of the fitted motion)."""
    G, pseudo_inverse, radius = _rigid_basis(points)
    b = u.T.ravel()
    coef = pseudo_inverse @ b  # least squares, as np.linalg.lstsq with its default cutoff
    fitted = G @ coef
    total = float(b @ b)
    if total == 0:
        return "zero", 0.0, 0.0
    weights = np.abs(coef) * np.array([1, 1, 1, radius, radius, radius])
    purity = float(weights.max() ** 2 / max(np.sum(weights**2), 1e-300))
    return RIGID_NAMES[int(np.argmax(weights))], float(fitted @ fitted / total), purity


_RIGID_BASES: dict = {}


def _rigid_basis(points: np.ndarray):
    """(G (3n, 6): the six rigid motions at ``points``, its pseudo-inverse, rms radius about the centroid), once per
    point set: every mode of a solve (and every rotation of a degenerate pair) shares its model's sample points."""
    key = (points.shape, hash(points.tobytes()))
    if key not in _RIGID_BASES:
        r = points - points.mean(axis=1, keepdims=True)
        n = r.shape[1]
        G = np.zeros((3 * n, 6))
        for k in range(3):
            G[k::3, k] = 1.0
        # theta x r = (ty rz - tz ry, tz rx - tx rz, tx ry - ty rx)
        G[0::3, 4], G[0::3, 5] = r[2], -r[1]
        G[1::3, 3], G[1::3, 5] = -r[2], r[0]
        G[2::3, 3], G[2::3, 4] = r[1], -r[0]
        radius = float(np.sqrt((r**2).sum(axis=0).mean()))
        if len(_RIGID_BASES) > 8:
            _RIGID_BASES.clear()
        _RIGID_BASES[key] = (G, np.linalg.pinv(G, rcond=np.finfo(float).eps * max(G.shape)), radius)
    return _RIGID_BASES[key]


def _grid_w(points: np.ndarray, u: np.ndarray, samples: int = 48):
    """w on a regular (x, y) grid over the top of the main parts (max z at each sample): ``samples`` along
    the longer side, at least 24 (and the same spacing) along the other; linear on the Delaunay triangles of the
    top points (as ``scipy.interpolate.griddata``), NaN outside them."""
    top, xs, ys, vertices, weights = _grid_interpolation(points, samples)
    W = np.einsum("gk,gk->g", u[2, top][vertices], weights).reshape(len(ys), len(xs))
    return xs, ys, W


_INTERPOLATIONS: dict = {}


def _grid_interpolation(points: np.ndarray, samples: int):
    """(top points mask, grid xs, ys, (n_grid, 3) triangle vertices and barycentric weights of every grid point,
    NaN weights outside the triangulation), computed once per point set: every mode of a solve shares its model's
    sample points, so the point location (the costly part) is done once, not per mode."""
    from scipy.spatial import Delaunay

    key = (points.shape, hash(points.tobytes()), samples)
    if key in _INTERPOLATIONS:
        return _INTERPOLATIONS[key]
    z_top = points[2].max()
    thickness = points[2].max() - points[2].min()
    top = points[2] > z_top - 0.05 * thickness
    lx = np.ptp(points[0, top])
    ly = np.ptp(points[1, top])
    nx = samples if lx >= ly else max(24, round(samples * lx / max(ly, 1e-300)))
    ny = samples if ly > lx else max(24, round(samples * ly / max(lx, 1e-300)))
    xs = np.linspace(points[0, top].min(), points[0, top].max(), nx)
    ys = np.linspace(points[1, top].min(), points[1, top].max(), ny)
    X, Y = np.meshgrid(xs, ys)
    grid = np.column_stack([X.ravel(), Y.ravel()])
    triangulation = Delaunay(points[:2, top].T)
    simplex = triangulation.find_simplex(grid)
    inside = simplex >= 0
    transform = triangulation.transform[simplex]  # (n_grid, 3, 2): barycentric map of each grid point's triangle
    b = np.einsum("gij,gj->gi", transform[:, :2], grid - transform[:, 2])
    weights = np.column_stack([b, 1.0 - b.sum(axis=1)])
    weights[~inside] = np.nan
    vertices = np.where(inside[:, None], triangulation.simplices[simplex], 0)
    if len(_INTERPOLATIONS) > 8:
        _INTERPOLATIONS.clear()
    _INTERPOLATIONS[key] = (top, xs, ys, vertices, weights)
    return _INTERPOLATIONS[key]


def _sign_changes(values: np.ndarray, threshold: float) -> list[int]:
    """Indices where the sign of the significant samples flips."""
    flips, last = [], 0
    for i, v in enumerate(values):
        if not np.isfinite(v) or abs(v) < threshold:
            continue
        s = 1 if v > 0 else -1
        if last and s != last:
            flips.append(i)
        last = s
    return flips


def _flip_counts(lines: np.ndarray, thresholds: np.ndarray) -> np.ndarray:
    """Sign flips along each row of ``lines`` among its significant samples (finite, |w| >= the row's
    threshold), all rows at once: ``len(_sign_changes(row, threshold))`` of every row."""
    values = np.nan_to_num(lines, nan=0.0)
    signs = np.where(np.isfinite(lines) & (np.abs(values) >= thresholds[:, None]), np.sign(values), 0.0)
    columns = np.arange(signs.shape[1])
    last = np.maximum.accumulate(np.where(signs != 0, columns, -1), axis=1)  # last significant sample so far
    previous = np.take_along_axis(signs, np.maximum(last[:, :-1], 0), axis=1) * (last[:, :-1] >= 0)
    return np.sum((signs[:, 1:] != 0) & (previous != 0) & (signs[:, 1:] != previous), axis=1)


def _line_count(lines: np.ndarray, peak: float) -> tuple[int, float]:
    """(nodal lines crossed, consistency in [0, 1]) from the sign changes along each grid line (rows of
    ``lines``) whose peak is significant: the count most of the lines in the outer quarters agree on (the
    smaller on a tie), as a closed nodal curve inside the plate crosses none of them; consistency: the share of
    all significant lines that agree."""
    amplitude = np.max(np.abs(np.nan_to_num(lines, nan=0.0)), axis=1)  # 0 for a row with no finite sample
    voting = np.flatnonzero(amplitude >= _LINE * peak)
    if len(voting) == 0:
        return 0, 0.0
    counts = _flip_counts(lines[voting], _SMALL * amplitude[voting])
    quarter = len(lines) / 4
    outer = counts[(voting < quarter) | (voting >= len(lines) - quarter)]
    values, tally = np.unique(outer if len(outer) else counts, return_counts=True)
    count = int(values[np.argmax(tally)])  # the most common; the smallest on a tie (np.unique sorts)
    return count, float(np.mean(counts == count))


def _islands(W: np.ndarray, peak: float) -> int:
    """Regions of one sign of w enclosed by a closed nodal curve (touching no edge of the grid), with a peak
    above ``_ISLAND`` of the plate's: nodal circles, e.g. round a centre mass."""
    from scipy import ndimage

    finite = np.isfinite(W)
    found = 0
    for sign in (1.0, -1.0):
        regions, count = ndimage.label(finite & (sign * np.where(finite, W, 0.0) > _ISLAND * peak))
        if count == 0:
            continue
        edge = set(np.unique(np.r_[regions[0], regions[-1], regions[:, 0], regions[:, -1]])) - {0}
        found += count - len(edge)
    return found


def plate_label(points: np.ndarray, u: np.ndarray) -> tuple[str, float]:
    """``(a,b)`` nodal-line counts of w and the wavelength along x [m]; ``in-plane`` if w is minor."""
    name, wavelength, _ = _plate(points, u)
    return name, wavelength


def _plate(points: np.ndarray, u: np.ndarray, grid=None) -> tuple[str, float, float]:
    """(``(a,b)`` or ``in-plane``, wavelength along x [m], clarity: the share of grid lines agreeing with the
    counts, less a tenth per closed nodal curve)."""
    if np.sum(u[2] ** 2) < 0.5 * np.sum(u**2):
        return "in-plane", float("nan"), 0.0
    xs, ys, W = _grid_w(points, u) if grid is None else grid
    if not np.isfinite(W).any() or np.nanmax(np.abs(W)) == 0:
        return "in-plane", float("nan"), 0.0
    peak = float(np.nanmax(np.abs(W)))
    b, along_x = _line_count(W, peak)
    a, along_y = _line_count(W.T, peak)
    clarity = 0.5 * (along_x + along_y) - 0.1 * _islands(W, peak)
    centre = W[len(ys) // 2]
    crossings = _zero_crossings(xs, centre, _SMALL * peak)
    wavelength = 2 * float(np.mean(np.diff(crossings))) if len(crossings) >= 2 else float("nan")
    return f"({a},{b})", wavelength, clarity


def _zero_crossings(xs: np.ndarray, w: np.ndarray, threshold: float) -> np.ndarray:
    """x of each sign change of ``w`` (linear interpolation between the bracketing samples)."""
    out = []
    significant = [i for i in range(len(w)) if np.isfinite(w[i]) and abs(w[i]) >= threshold]
    for i, j in itertools.pairwise(significant):
        if np.sign(w[i]) != np.sign(w[j]):
            k = i + int(np.argmin(np.abs(w[i : j + 1])))
            k = min(max(k, i), j - 1)
            x0, x1, w0, w1 = xs[k], xs[k + 1], w[k], w[k + 1]
            out.append(x0 - w0 * (x1 - x0) / (w1 - w0) if w1 != w0 else x0)
    return np.array(out)


def beam_label(points: np.ndarray, u: np.ndarray, stations: int = 60) -> str:
    """Kind and order of a beam mode along x from cross-section averages."""
    return _beam(points, u, stations)[0]


def _beam(points: np.ndarray, u: np.ndarray, stations: int = 60) -> tuple[str, float]:
    """(kind and order, purity: the dominant motion's share of the cross-section motion)."""
    x = points[0]
    edges = np.linspace(x.min(), x.max(), stations + 1)
    which = np.clip(np.digitize(x, edges) - 1, 0, stations - 1)
    yc, zc = points[1].mean(), points[2].mean()
    radius = np.sqrt(((points[1] - yc) ** 2 + (points[2] - zc) ** 2).mean())
    count = np.bincount(which, minlength=stations)
    filled = np.maximum(count, 1)  # an empty station keeps 0

    def station_mean(values: np.ndarray) -> np.ndarray:
        return np.bincount(which, weights=values, minlength=stations) / filled

    dy, dz = points[1] - yc, points[2] - zc
    curves = {"axial": station_mean(u[0]), "bending-y": station_mean(u[1]), "bending-z": station_mean(u[2]),
              "torsion": station_mean(dy * u[2] - dz * u[1]) / radius}
    energy = {k: float(np.sum(c**2)) for k, c in curves.items()}
    kind = max(energy, key=energy.get)
    curve = curves[kind]
    order = len(_sign_changes(curve, _SMALL * np.abs(curve).max())) + 1
    return f"{kind} {order}", energy[kind] / max(sum(energy.values()), 1e-300)


# -- discs and rings ----------------------------------------------------------------------------------------

_PURE = 0.7  # a disc mode holds >= 70 % of its energy in one harmonic of the angle; below that the label is "?"
_HARMONICS = 16  # highest harmonic of the angle resolved (nodal diameters, in-plane waves)
_POLAR: dict = {}


def axial_frame(scene) -> tuple[np.ndarray, np.ndarray] | None:
    """(unit axis (3,), a point on the axis (3,)) [m] of the device's main part when it has an axis (a disc,
    ring or cylinder: any part with ``axis``, one of "x", "y", "z" or a 3-vector, and ``centre``), else None
    (boxes keep the plate and beam labels). The whole device's part (``full_assembly``) where the scene has one:
    the label field is unfolded to the whole device."""
    assembly = getattr(scene, "full_assembly", None) or getattr(scene, "assembly", None)
    if assembly is None:
        return None
    part = assembly().main_part
    axis, centre = getattr(part, "axis", None), getattr(part, "centre", None)
    if axis is None or centre is None:
        return None
    if isinstance(axis, str):
        axis = np.eye(3)["xyz".index(axis.lstrip("+-"))]
    axis = np.asarray(axis, dtype=float)
    return axis / np.linalg.norm(axis), np.asarray(centre, dtype=float)


def disc_label(points: np.ndarray, u: np.ndarray, *, axis, centre) -> str:
    """Label of a disc or ring mode from the displacement ``u`` (3, n) [m] at ``points`` (3, n) [m] (a mid-surface
    or the whole volume) of a part whose axis runs along ``axis`` (3,) through ``centre`` (3,) [m]: ``(d,c)``
    nodal diameters and circles of a flexural mode, ``R1``, ``T1``, ``n=2`` or ``thickness`` for the others, ``?``
    for a field that is no single harmonic of the angle (module docstring)."""
    axis = np.asarray(axis, dtype=float)
    return _disc(points, u, axis / np.linalg.norm(axis), np.asarray(centre, dtype=float))[0]


def _disc(points: np.ndarray, u: np.ndarray, axis: np.ndarray, centre: np.ndarray) -> tuple[str, float]:
    """(label, clarity: the dominant harmonic's share of the energy) of a disc or ring mode.

    The field is split about the mid-plane normal to the axis (each point paired with the sample nearest its
    mirror image): the flexural part (u_z even, in-plane odd through the thickness) and the membrane part. The
    larger one is expanded in harmonics cos(k theta), sin(k theta) on rings of r; the strongest harmonic gives the
    diameters (waves), and the sign changes along r of its radial profile the circles (radial order)."""
    polar = _polar(points, axis, centre)
    local = polar.frame @ u
    image = local[:, polar.mirror] * np.array([[1.0], [1.0], [-1.0]])
    membrane, flexural = (local + image) / 2, (local - image) / 2
    if np.sum(flexural**2) >= np.sum(membrane**2):
        if np.sum(flexural[2] ** 2) < _NO_AXIAL * np.sum(flexural[:2] ** 2):  # odd through the thickness but
            return _in_plane(polar, polar.side * flexural)  # in-plane: a twist (a thick cylinder's u_theta ~ r cos(pi
            # z / h): T1), read on one side's sign as the thickness mode
        spectrum = _Spectrum(polar, flexural[2])
        n, purity = spectrum.dominant()
        if purity < _PURE:
            return "?", purity
        return f"({n},{spectrum.sign_changes(n)})", purity
    if np.sum(membrane[2] ** 2) > np.sum(membrane[:2] ** 2):
        n, purity = _Spectrum(polar, polar.side * membrane[2]).dominant()  # odd in z: read one side's sign
        return ("thickness", purity) if n == 0 and purity >= _PURE else ("?", purity)
    return _in_plane(polar, membrane)


def _in_plane(polar, field: np.ndarray) -> tuple[str, float]:
    """(label, clarity) of a field (3, n) moving in the plane normal to the axis: ``R1``..., ``T1``... (n = 0, radial
    or circumferential; radial sign changes plus one), ``n=2``, ``n=2 k=2``... (n waves round it)."""
    c, s = np.cos(polar.theta), np.sin(polar.theta)
    radial = _Spectrum(polar, c * field[0] + s * field[1])
    circumferential = _Spectrum(polar, -s * field[0] + c * field[1])
    energy = radial.energy + circumferential.energy
    n = int(np.argmax(energy))
    purity = float(energy[n] / max(radial.totals[n] + circumferential.totals[n], 1e-300))
    if purity < _PURE:
        return "?", purity
    major = radial if radial.energy[n] >= circumferential.energy[n] else circumferential
    order = major.sign_changes(n) + 1
    if n == 0:
        return f"{'R' if major is radial else 'T'}{order}", purity
    return (f"n={n}" if order == 1 else f"n={n} k={order}"), purity


class _Polar:
    """Polar sampling of one point set about an axis: local frame (rows e1, e2, axis), angle, side of the
    mid-plane and mirror partner about it of each point, and per ring of r the points, the least-squares map
    from their values to the harmonic coefficients [a0, a1, b1, ...] and k (``_harmonic_fit``)."""

    def __init__(self, points: np.ndarray, axis: np.ndarray, centre: np.ndarray) -> None:
        from scipy.spatial import cKDTree

        helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
        e1 = np.cross(axis, helper)
        e1 /= np.linalg.norm(e1)
        self.frame = np.array([e1, np.cross(axis, e1), axis])
        local = self.frame @ (points - centre[:, None])
        r = np.hypot(local[0], local[1])
        self.theta = np.arctan2(local[1], local[0])
        mid = 0.5 * (local[2].max() + local[2].min())
        self.side = np.sign(local[2] - mid)  # +1 above the mid-plane, -1 below, 0 on it
        mirrored = local.copy()
        mirrored[2] = 2 * mid - local[2]
        self.mirror = cKDTree(local.T).query(mirrored.T)[1]
        count = int(np.clip(round(np.sqrt(points.shape[1]) / 3), 6, 24))
        edges = np.linspace(r.min(), r.max(), count + 1)
        which = np.clip(np.digitize(r, edges) - 1, 0, count - 1)
        self.rings, self.area = [], []
        for j in range(count):
            members = np.flatnonzero(which == j)
            if len(members) == 0:
                continue
            fit, k = _harmonic_fit(self.theta[members])
            if k == 0:
                # angles too few to resolve harmonic 1 cannot tell n = 0 from the others either: the vertices inside a
                # half ring's wall lie on its cut lines only (two angles), where cos 2 theta's mean read as n = 0
                # and made the half's even modes "?"
                continue
            self.rings.append((members, fit, k))
            self.area.append(0.5 * (edges[j] + edges[j + 1]) * (edges[j + 1] - edges[j]))  # r dr of the ring
        self.area = np.array(self.area)


def _harmonic_fit(theta: np.ndarray) -> tuple[np.ndarray, int]:
    """(least-squares map from values at the angles ``theta`` to [a0, a1, b1, ..., ak, bk], k): k as high as
    ``_HARMONICS`` allows while the samples determine the harmonics well (at least 3 distinct angles per
    coefficient and a basis condition number below 100, so noise is not amplified into high harmonics)."""
    distinct = len(np.unique(np.round(theta, 9)))
    k = min(_HARMONICS, (distinct - 1) // 6)
    angles = np.outer(theta, np.arange(1, k + 1))
    basis = np.ones((len(theta), 2 * k + 1))
    basis[:, 1::2], basis[:, 2::2] = np.cos(angles), np.sin(angles)
    gram = basis.T @ basis
    while k > 0:
        eigenvalues = np.linalg.eigvalsh(gram[: 2 * k + 1, : 2 * k + 1])  # cond(basis)^2 = cond(gram)
        if eigenvalues[-1] < 100**2 * eigenvalues[0]:
            break
        k -= 1
    used = basis[:, : 2 * k + 1]
    return np.linalg.solve(gram[: 2 * k + 1, : 2 * k + 1], used.T), k


def _polar(points: np.ndarray, axis: np.ndarray, centre: np.ndarray) -> _Polar:
    """``_Polar`` of a point set, computed once: every mode of a solve (and every rotation of a degenerate
    pair) shares its model's sample points."""
    key = (points.shape, hash(points.tobytes()), axis.tobytes(), centre.tobytes())
    if key not in _POLAR:
        if len(_POLAR) > 8:
            _POLAR.clear()
        _POLAR[key] = _Polar(points, axis, centre)
    return _POLAR[key]


class _Spectrum:
    """Harmonic coefficients a_k(r), b_k(r) of one scalar field on the rings of a ``_Polar`` (rows: rings),
    the energy of each harmonic (sum over rings of r dr times the mean square over the angle) and, per harmonic n,
    the field's energy on the rings whose samples resolve n (``totals``): a ring of r with too few distinct angles
    (between a ring's or tube's walls, only the end faces' few vertices) resolves no harmonic, and counting its
    energy against every harmonic made a ring's clear modes "?" (issue 35)."""

    def __init__(self, polar: _Polar, values: np.ndarray) -> None:
        rings = len(polar.rings)
        self.a, self.b = np.zeros((rings, _HARMONICS + 1)), np.zeros((rings, _HARMONICS + 1))
        self.totals = np.zeros(_HARMONICS + 1)
        for j, (members, fit, k) in enumerate(polar.rings):
            c = fit @ values[members]
            self.a[j, : k + 1], self.b[j, 1 : k + 1] = c[np.r_[0, 1 : 2 * k : 2]], c[2::2]
            self.totals[: k + 1] += polar.area[j] * float(np.mean(values[members] ** 2))
        self.area = polar.area
        self.energy = self.area @ (self.a**2 + self.b**2) * np.r_[1.0, np.full(_HARMONICS, 0.5)]

    def dominant(self) -> tuple[int, float]:
        """(harmonic with the most energy, its share of the field's energy on the rings that resolve it)."""
        n = int(np.argmax(self.energy))
        return n, float(self.energy[n] / max(self.totals[n], 1e-300))

    def sign_changes(self, n: int) -> int:
        """Sign changes along r of harmonic ``n``'s radial profile, taken along the orientation in the angle that
        carries most of it (a standing pattern cos(n (theta - theta0)) from any basis)."""
        a, b = self.a[:, n], self.b[:, n]
        moments = np.array([[self.area @ (a * a), self.area @ (a * b)], [self.area @ (a * b), self.area @ (b * b)]])
        direction = np.linalg.eigh(moments)[1][:, -1]
        profile = a * direction[0] + b * direction[1]
        return len(_sign_changes(profile, _SMALL * float(np.max(np.abs(profile)))))
