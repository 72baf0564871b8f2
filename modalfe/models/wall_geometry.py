"""What the geometry of a swept mesh's round walls may cost a frequency.

A swept mesh meets a circle at its nodes and spans it between them by quadratic arcs (``modalfe.models.swept``), so
that every element order on it solves one geometry: steps between orders cannot see how far that geometry is from
the true one. Its effect on an eigenvalue follows Hadamard's shape derivative (e.g. Henrot & Pierre, Shape
Variation and Optimization, EMS 2018, ch. 5): moving a free wall outward by dn changes

    d lambda = int_wall (sigma : epsilon - lambda rho |u|^2) dn dA / int rho |u|^2 dV.

With |dn| <= eps r on a wall of radius r (``wall_deviations``), the slice between the two walls holds at most
2 eps of its part's volume; its kinetic energy density is the part's mean (a foot or a disc moves its wall with
the rest) and its strain energy density at most ``WALL_ENERGY_RATIO`` times the mean. Then

    |d f| / f = |d lambda| / (2 lambda) <= eps (WALL_ENERGY_RATIO s_K + s_M),

s_K and s_M the part's shares of the mode's strain and kinetic energy (``wall_errors``; the round parts' together, at
the largest deviation of any): the geometry term of an estimate from the orders on one swept grid.
"""

from __future__ import annotations

import numpy as np

from modalfe.geometry.shapes import axis_distance

# strain energy density at a circular section's wall over its mean in bending (stress ~ distance from the neutral
# axis: y^2 = r^2 at the wall, r^2 / 4 averaged over the disc); axial and torsional loading give at most 1 and 2
WALL_ENERGY_RATIO = 4.0
_SAMPLES = np.linspace(0.0, 1.0, 17)[1:-1]  # points along each quadratic edge between its nodes


def wall_deviations(model) -> dict[str, float]:
    """Round part name -> largest distance between its round walls (``radii``) in the mesh and the true ones, over
    that radius: every quadratic element edge whose two ends lie on a wall (within 1e-6 of its radius), sampled
    between them. Only parts with round walls (cylinders, rings) on a mesh with edge nodes (MeshHex2)."""
    mesh = model.mesh.mesh
    if mesh.doflocs.shape[1] == mesh.nvertices:
        return {}
    ends, middle = _edge_nodes(mesh.elem.doflocs)
    out = {}
    for part in model.scene.assembly().parts:
        radii = [r for r in getattr(part, "radii", ()) if r > 0]
        if not radii:
            continue
        nodes = mesh.doflocs[:, mesh.dofs.element_dofs[:, model.mesh.parts[part.name]]]  # (3, ngeo, nel)
        a, m, b = nodes[:, ends[:, 0]], nodes[:, middle], nodes[:, ends[:, 1]]  # (3, nedges, nel)
        t = _SAMPLES[:, None, None, None]
        x = np.moveaxis(a * (1 - t) * (1 - 2 * t) + 4 * m * t * (1 - t) + b * t * (2 * t - 1), 0, 1)  # (3, ns, ...)
        worst = 0.0
        for r in radii:
            on = np.ones(a.shape[1:], dtype=bool)
            for point in (a, b):
                on &= np.abs(axis_distance(part, np.moveaxis(point, 0, -1)) / r - 1) <= 1e-6
            if on.any():
                worst = max(worst, float(np.max(np.abs(axis_distance(part, np.moveaxis(x, 0, -1))[:, on] / r - 1))))
        out[part.name] = worst
    return out


def wall_errors(model, shapes: np.ndarray, omega2: np.ndarray) -> tuple[np.ndarray, dict[str, float]]:
    """(bound on the relative frequency error of the round walls' geometry (module docstring) of each mode, zeros
    where no wall deviates; the deviations it used, ``wall_deviations``): ``shapes`` (model DOFs, m) and their
    eigenvalues ``omega2`` (m,) [rad^2/s^2]."""
    from modalfe.models.solid import parts_matrices

    deviations = {name: eps for name, eps in wall_deviations(model).items() if eps > 0}
    if not deviations:
        return np.zeros(shapes.shape[1]), deviations
    u = shapes[:model.n_u]
    kinetic = np.einsum("im,im->m", shapes, model.M @ shapes)  # M has no potential rows: u^T M_uu u
    K, M = parts_matrices(model, set(deviations))  # the round parts at once, at the largest deviation of any
    s_K = np.einsum("im,im->m", u, K @ u) / (omega2 * kinetic)
    s_M = np.einsum("im,im->m", u, M @ u) / kinetic
    return max(deviations.values()) * (WALL_ENERGY_RATIO * np.abs(s_K) + np.abs(s_M)), deviations


def _edge_nodes(reference: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(end nodes (nedges, 2), middle node (nedges,)) of the edges of a quadratic hexahedron whose nodes sit at
    ``reference`` (ngeo, 3) on the unit cube: an edge node has one coordinate 1/2, its ends 0 and 1 there."""
    ends, middle = [], []
    for j, x in enumerate(reference):
        half = np.flatnonzero(np.isclose(x, 0.5))
        if len(half) != 1:
            continue
        pair = []
        for end in (0.0, 1.0):
            y = x.copy()
            y[half[0]] = end
            pair.append(int(np.flatnonzero(np.all(np.isclose(reference, y), axis=1))[0]))
        ends.append(pair)
        middle.append(j)
    return np.array(ends), np.array(middle)

