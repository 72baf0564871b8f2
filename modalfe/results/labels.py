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
plain label and the others, by frequency, get ``#2``, ``#3``... (``(1,1)#2``). The suffix only
tells modes of one solve apart: ``Modes.labelled`` and ``select`` with a frequency pick the nearest
mode of the pattern whatever its suffix.
"""

from __future__ import annotations

import itertools
from collections import Counter

import numpy as np

RIGID_NAMES = ("sway-x", "sway-y", "heave", "roll", "pitch", "yaw")
_SMALL = 0.08  # samples below this fraction of the line's peak carry no sign (noise near nodal lines)
_LINE = 0.25  # a grid line whose peak |w| is below this fraction of the plate's peak does not vote
_ISLAND = 0.02  # a closed nodal region counts if its peak |w| is above this fraction of the plate's peak
_RIGID = 0.98  # main parts moving 98 % as a rigid body: a suspension mode (plate modes reach ~0.9)
DEGENERATE = 1e-3  # relative frequency gap below which two modes are a degenerate pair
_ANGLES = 36  # rotations tried within a degenerate pair's span (every 2.5 degrees of a quarter turn)
SUFFIX = "#"  # ``(0,3)#2``: the second mode of one solve with the pattern ``(0,3)``


def base_label(name: str) -> str:
    """The pattern of a label without its ambiguity suffix: ``(0,3)#2`` -> ``(0,3)``."""
    return name.split(SUFFIX, 1)[0]


def label(model, x: np.ndarray) -> tuple[str, float]:
    """(label, wavelength along x [m] or NaN) of the full DOF vector ``x`` of any assembled model (solid, plate
    or beam), read from its ``label_field`` (the whole device's main surfaces or vertices): a rigid-body name
    for an unsupported body moving rigidly, else the beam or plate label of the scene's kind."""
    points, u = model.label_field(x)
    name, wavelength, _ = _describe(model.scene, points, u)
    return name, wavelength


def unique_labels(model, shapes: np.ndarray, frequencies) -> list[tuple[str, float]]:
    """(label, wavelength [m] or NaN) of every mode of one solve (``shapes`` (n_dofs, n_modes) full DOF
    vectors, ``frequencies`` [Hz] ascending), unique within the solve: degenerate pairs rotated to their
    clearest basis, repeated patterns suffixed ``#2``, ``#3``... (module docstring)."""
    f = np.asarray(frequencies, dtype=float)
    n = len(f)
    fields = [model.label_field(shapes[:, i]) for i in range(n)]
    described: list[tuple[str, float, float]] = [None] * n  # type: ignore[list-item]
    i = 0
    while i < n:
        j = i + 1
        while j < n and abs(f[j] - f[j - 1]) <= DEGENERATE * max(abs(f[j]), 1e-300):
            j += 1
        if j - i == 2 and f[i] > 0:
            described[i], described[i + 1] = _pair(model.scene, fields[i], fields[i + 1])
        else:
            for k in range(i, j):
                described[k] = _describe(model.scene, *fields[k])
        i = j
    groups: dict[str, list[int]] = {}
    for k, (name, _, _) in enumerate(described):
        groups.setdefault(name, []).append(k)
    out = [(name, wavelength) for name, wavelength, _ in described]
    for name, members in groups.items():
        if len(members) < 2:
            continue
        plain = min(members, key=lambda k: (-round(described[k][2], 6), f[k]))  # clearest, then lowest
        rest = [k for k in members if k != plain]
        for number, k in enumerate(rest, start=2):
            out[k] = (f"{name}{SUFFIX}{number}", out[k][1])
    return out


def _describe(scene, points: np.ndarray, u: np.ndarray, grid=None) -> tuple[str, float, float]:
    """(label, wavelength, clarity in [0, 1]) of one displacement field of the main parts."""
    if not scene.clamps:  # only a free or spring-supported body has rigid-body modes
        name, fraction, purity = _rigid(points, u)
        if fraction > _RIGID:
            return name, float("nan"), purity
    if scene.kind == "beam":
        name, purity = _beam(points, u)
        return name, float("nan"), purity
    return _plate(points, u, grid)


def _pair(scene, first, second) -> tuple[tuple[str, float, float], tuple[str, float, float]]:
    """Labels of a degenerate pair: the basis of the pair's span (rotations over a quarter turn) whose two
    shapes have the clearest patterns; the two labels are returned in sorted order (their frequencies are
    equal to the pair's precision, so which eigenvector carries which is arbitrary)."""
    (p, u1), (_, u2) = first, second
    n1, n2 = np.sqrt(np.sum(u1**2)), np.sqrt(np.sum(u2**2))
    u1, u2 = u1 / max(n1, 1e-300), u2 / max(n2, 1e-300)
    plate = scene.kind != "beam"
    g1 = _grid_w(p, u1) if plate else None
    g2 = _grid_w(p, u2) if plate else None
    best, best_score = None, -1.0
    for theta in np.linspace(0.0, np.pi / 2, _ANGLES, endpoint=False):
        c, s = np.cos(theta), np.sin(theta)
        grids = (None, None)
        if plate:
            grids = ((g1[0], g1[1], c * g1[2] + s * g2[2]), (g1[0], g1[1], -s * g1[2] + c * g2[2]))
        a = _describe(scene, p, c * u1 + s * u2, grids[0])
        b = _describe(scene, p, -s * u1 + c * u2, grids[1])
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
    r = points - points.mean(axis=1, keepdims=True)
    n = r.shape[1]
    G = np.zeros((3 * n, 6))
    for k in range(3):
        G[k::3, k] = 1.0
    # theta x r = (ty rz - tz ry, tz rx - tx rz, tx ry - ty rx)
    G[0::3, 4], G[0::3, 5] = r[2], -r[1]
    G[1::3, 3], G[1::3, 5] = -r[2], r[0]
    G[2::3, 3], G[2::3, 4] = r[1], -r[0]
    b = u.T.ravel()
    coef, *_ = np.linalg.lstsq(G, b, rcond=None)
    fitted = G @ coef
    total = float(b @ b)
    if total == 0:
        return "zero", 0.0, 0.0
    radius = np.sqrt((r**2).sum(axis=0).mean())
    weights = np.abs(coef) * np.array([1, 1, 1, radius, radius, radius])
    purity = float(weights.max() ** 2 / max(np.sum(weights**2), 1e-300))
    return RIGID_NAMES[int(np.argmax(weights))], float(fitted @ fitted / total), purity


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
    counts = dict(zip(voting.tolist(), _flip_counts(lines[voting], _SMALL * amplitude[voting]).tolist()))
    quarter = len(lines) / 4
    outer = [counts[i] for i in voting if i < quarter or i >= len(lines) - quarter] or list(counts.values())
    tally = Counter(outer)
    top = max(tally.values())
    count = min(c for c, k in tally.items() if k == top)
    return count, sum(c == count for c in counts.values()) / len(voting)


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
