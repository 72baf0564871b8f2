"""Mode labels from the mode shape: plate (m,n) nodal-line counts, beam kind and order, and the
rigid-body names of suspension modes. A device's working mode is found by label, never by index.

Plate labels count sign changes of the normal displacement w over the device's main parts:
``(a,b)`` has ``a`` nodal lines along x (sign changes met walking along y) and ``b`` nodal lines
across x (met walking along x), so the Cu-Be plate's working mode is ``(0,6)``. Beam labels
(``bending-z 6``, ``bending-y 2``, ``torsion 1``, ``axial 1``) take the dominant cross-section
motion and its order (sign changes along x, plus one: the count for a cantilever).
"""

from __future__ import annotations

import itertools

import numpy as np

RIGID_NAMES = ("sway-x", "sway-y", "heave", "roll", "pitch", "yaw")
_SMALL = 0.08  # samples below this fraction of the peak carry no sign (noise near nodal lines)
_RIGID = 0.98  # main parts moving 98 % as a rigid body: a suspension mode (plate modes reach ~0.9)


def label(model, x: np.ndarray) -> tuple[str, float]:
    """(label, wavelength along x [m] or NaN) of the full DOF vector ``x`` of any assembled model (solid, plate
    or beam), read from its ``label_field`` (the whole device's main surfaces or vertices): a rigid-body name
    for an unsupported body moving rigidly, else the beam or plate label of the scene's kind."""
    points, u = model.label_field(x)
    if not model.scene.clamps:  # only a free or spring-supported body has rigid-body modes
        name, fraction = rigid_motion(points, u)
        if fraction > _RIGID:
            return name, float("nan")
    if model.scene.kind == "beam":
        return beam_label(points, u), float("nan")
    return plate_label(points, u)


def rigid_motion(points: np.ndarray, u: np.ndarray) -> tuple[str, float]:
    """Best rigid-body fit u ~ t + theta x (r - rc): (name of its largest component, energy fraction)."""
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
        return "zero", 0.0
    radius = np.sqrt((r**2).sum(axis=0).mean())
    weights = np.abs(coef) * np.array([1, 1, 1, radius, radius, radius])
    return RIGID_NAMES[int(np.argmax(weights))], float(fitted @ fitted / total)


def _grid_w(points: np.ndarray, u: np.ndarray, samples: int = 48):
    """w on a regular (x, y) grid over the top of the main parts (max z at each sample)."""
    from scipy.interpolate import griddata

    z_top = points[2].max()
    thickness = points[2].max() - points[2].min()
    top = points[2] > z_top - 0.05 * thickness
    xs = np.linspace(points[0, top].min(), points[0, top].max(), samples)
    ys = np.linspace(points[1, top].min(), points[1, top].max(), max(8, samples // 2))
    X, Y = np.meshgrid(xs, ys)
    W = griddata(points[:2, top].T, u[2, top], (X, Y), method="linear")
    return xs, ys, W


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


def plate_label(points: np.ndarray, u: np.ndarray) -> tuple[str, float]:
    """``(a,b)`` nodal-line counts of w and the wavelength along x [m]; ``in-plane`` if w is minor."""
    if np.sum(u[2] ** 2) < 0.5 * np.sum(u**2):
        return "in-plane", float("nan")
    xs, ys, W = _grid_w(points, u)
    threshold = _SMALL * np.nanmax(np.abs(W))
    rows = np.linspace(0.15, 0.85, 5)
    along_x = [len(_sign_changes(W[int(f * (len(ys) - 1))], threshold)) for f in rows]
    along_y = [len(_sign_changes(W[:, int(f * (len(xs) - 1))], threshold)) for f in rows]
    a = int(np.median(along_y))
    b = int(np.median(along_x))
    centre = W[len(ys) // 2]
    crossings = _zero_crossings(xs, centre, threshold)
    wavelength = 2 * float(np.mean(np.diff(crossings))) if len(crossings) >= 2 else float("nan")
    return f"({a},{b})", wavelength


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
    kind = max(curves, key=lambda k: np.sum(curves[k] ** 2))
    curve = curves[kind]
    order = len(_sign_changes(curve, _SMALL * np.abs(curve).max())) + 1
    return f"{kind} {order}"
