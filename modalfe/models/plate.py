"""2-D Reissner-Mindlin laminate plate in the xy plane, on scikit-fem: the ``plate`` rung of the fidelity ladder.

The device's boxes are cut into cells at every part's and face window's x and y boundaries; each cell's
section is the stack of boxes covering it (plate, patches, feet, facings and core). Five unknowns per node
on one reference plane z_r shared by all cells (first-order shear deformation theory),

    q = (u, v, w, beta_x, beta_y),   U(x, y, z) = (u + zeta beta_x, v + zeta beta_y, w),   zeta = z - z_r

with generalised strains e = (eps0_xx, eps0_yy, gamma0_xy, kappa_xx, kappa_yy, kappa_xy, gamma_xz, gamma_yz),
kappa_xx = beta_x,x, gamma_xz = w,x + beta_x. Section resultants from the classical lamination ABD matrices
of plane-stress layer stiffnesses about z_r (Reddy, Mechanics of Laminated Composite Plates and Shells, 2nd
ed. 2004, eqs. 3.3.17 and 3.4.28), so unsymmetric stacks (a patch on one face, a foot below) keep their
membrane-bending coupling. Transverse shear stiffness per direction from the equilibrium shear-stress
distribution of cylindrical bending, A_s = 1 / int g(zeta)^2 / G dzeta, g(zeta) = int_bottom^zeta E (s - z_n) ds
/ int E (s - z_n)^2 ds (the energy-consistent correction, e.g. Vlachoutsis, Int. J. Numer. Meth. Eng. 34
(1992) 105-121): 5/6 G h for one layer, the core's shear for a sandwich. Inertia int rho P^T P dzeta keeps
rotary inertia and offsets.

Quadratic 9-node quadrilaterals (``ElementQuad2``) on a tensor grid, fully integrated: at the default
element size (a sixth of the shortest bending wavelength) the elements are no thinner than the plates
(h / l_e >~ 0.5), where the shear locking of full integration is small and shows in the Richardson estimate.

Piezoelectric layers (poled along z, electrodes on their z faces): E3 uniform through each layer, plane
stress constants e* = Q d_in and eps* = eps33^T - d_in Q d_in from ``modalfe.models.layered.thin_layer_constants``;
one potential per electrode face group, as the 3-D model. Springs and masses on z faces act at the face's
height (zeta_f): K += P(zeta_f)^T diag(k / A) P(zeta_f), spread over the face like the 3-D model's.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError
from modalfe.geometry.parts import contact_area
from modalfe.models.constraints import shared_unknowns
from modalfe.models.layered import (
    LayeredModel,
    capacitance_matrix,
    electrode_layers,
    element_size,
    flexural_wavenumber,
    thin_layer_constants,
)
from modalfe.models.symmetry import fold, mirror_planes, mirrored

SLENDERNESS = 5.0  # smaller in-plane side / mean section thickness below which a plate model is refused
PLANE_STRESS = [0, 1, 5]  # Voigt xx, yy, xy
_SHEAR_SAMPLES = 64  # Gauss points per layer for the shear-correction integrals (exact to ~1e-12)
_COMPONENT_DOFS = {"x": (0, 3), "y": (1, 4), "z": (2,)}  # a side face fixed along x stops u and beta_x


@dataclass(frozen=True)
class Layer:
    """One box in a stack: z0..z1 [m], plane-stress stiffness Q (3, 3) [Pa] in (xx, yy, xy), transverse
    shear moduli (G_xz, G_yz) [Pa], rho [kg/m^3]; piezo constants e* (3,) [C/m^2], eps* [F/m] (0 if passive);
    ``structural`` False for a post (see ``is_post``): mass and rotary inertia only."""

    part: str
    z0: float
    z1: float
    Q: np.ndarray
    G: tuple[float, float]
    rho: float
    e: np.ndarray
    eps: float
    structural: bool = True

    @property
    def thickness(self) -> float:
        return self.z1 - self.z0


@dataclass(frozen=True, eq=False)
class Section:
    """Properties of one stack about the reference plane: stiffness (8, 8) on the generalised strains,
    mass (5, 5) on q, and the layers (bottom first)."""

    layers: tuple[Layer, ...]
    stiffness: np.ndarray
    mass: np.ndarray

    @property
    def bounds(self) -> tuple[float, float]:
        return self.layers[0].z0, self.layers[-1].z1

    @property
    def thickness(self) -> float:
        return self.bounds[1] - self.bounds[0]


def _displacement_map(zeta: float) -> np.ndarray:
    """P (3, 5): (ux, uy, uz) at height zeta above the reference plane from q = (u, v, w, beta_x, beta_y)."""
    P = np.zeros((3, 5))
    P[0, 0], P[1, 1], P[2, 2], P[0, 3], P[1, 4] = 1.0, 1.0, 1.0, zeta, zeta
    return P


def _strain_maps() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(E0, Ex, Ey), each (8, 5): generalised strains e = E0 q + Ex q,x + Ey q,y."""
    E0, Ex, Ey = np.zeros((8, 5)), np.zeros((8, 5)), np.zeros((8, 5))
    Ex[0, 0] = Ex[2, 1] = Ex[3, 3] = Ex[5, 4] = Ex[6, 2] = 1.0  # u,x; v,x; beta_x,x; beta_y,x; w,x
    Ey[1, 1] = Ey[2, 0] = Ey[4, 4] = Ey[5, 3] = Ey[7, 2] = 1.0  # v,y; u,y; beta_y,y; beta_x,y; w,y
    E0[6, 3] = E0[7, 4] = 1.0  # + beta_x, + beta_y
    return E0, Ex, Ey


def shear_stiffness(layers: tuple[Layer, ...], direction: int) -> float:
    """Transverse shear stiffness A_s [N/m] along x (0) or y (1) from the cylindrical-bending stress
    distribution (module docstring); E = Q11 (Q22), G = G_xz (G_yz)."""
    nodes, weights = np.polynomial.legendre.leggauss(_SHEAR_SAMPLES)
    zs, ws, E, G = [], [], [], []
    layers = tuple(la for la in layers if la.structural)
    for la in layers:
        half = 0.5 * la.thickness
        zs.append(la.z0 + half * (nodes + 1))
        ws.append(half * weights)
        E.append(np.full(_SHEAR_SAMPLES, la.Q[direction, direction]))
        G.append(np.full(_SHEAR_SAMPLES, la.G[direction]))
    z, w, E, G = (np.concatenate(a) for a in (zs, ws, E, G))
    z_n = np.sum(w * E * z) / np.sum(w * E)
    D = np.sum(w * E * (z - z_n) ** 2)
    # g(zeta) = int_bottom^zeta E (s - z_n) ds / D, exactly per layer (E constant there)
    g = np.empty_like(z)
    below = 0.0
    for i, la in enumerate(layers):
        sl = slice(i * _SHEAR_SAMPLES, (i + 1) * _SHEAR_SAMPLES)
        Ei = la.Q[direction, direction]
        g[sl] = below + Ei * 0.5 * ((z[sl] - z_n) ** 2 - (la.z0 - z_n) ** 2)
        below += Ei * 0.5 * ((la.z1 - z_n) ** 2 - (la.z0 - z_n) ** 2)
    return float(1.0 / np.sum(w * (g / D) ** 2 / G))


def section_properties(layers: tuple[Layer, ...], zr: float) -> Section:
    """ABD (with transverse shear) and inertia of a stack about the reference plane ``zr`` [m]."""
    A, B, D = np.zeros((3, 3)), np.zeros((3, 3)), np.zeros((3, 3))
    mass = np.zeros((5, 5))
    for la in layers:
        a, b = la.z0 - zr, la.z1 - zr
        m0, m1, m2 = b - a, (b**2 - a**2) / 2, (b**3 - a**3) / 3
        P0, P1 = _displacement_map(0.0), _displacement_map(1.0) - _displacement_map(0.0)
        mass += la.rho * (m0 * P0.T @ P0 + m1 * (P0.T @ P1 + P1.T @ P0) + m2 * P1.T @ P1)
        if la.structural:
            A += la.Q * m0
            B += la.Q * m1
            D += la.Q * m2
    stiffness = np.zeros((8, 8))
    stiffness[:3, :3], stiffness[:3, 3:6], stiffness[3:6, :3], stiffness[3:6, 3:6] = A, B, B, D
    stiffness[6, 6], stiffness[7, 7] = shear_stiffness(layers, 0), shear_stiffness(layers, 1)
    return Section(layers, stiffness, mass)


def widest_part(assembly):
    """The part with the largest footprint (the plate, a facing), the thicker on a tie."""
    return max(assembly.parts, key=lambda p: ((p.hi[0] - p.lo[0]) * (p.hi[1] - p.lo[1]), p.hi[2] - p.lo[2]))


def is_post(part, assembly, widest=None) -> bool:
    """A part standing off the plate (a foot, a pillar): it stands on (or hangs from) another part's z face, is
    bonded to no part along its sides, and is taller than its footprint is wide. Plane sections cannot hold
    through it, so the plate model carries it as non-structural mass with its rotary inertia and leaves out how
    it stiffens its footprint (for the Cu-Be plate's feet the cross-check measures the cost). A box of a plate
    built side by side from narrow strips is no post: its neighbours hold its sides."""
    widest = widest_part(assembly) if widest is None else widest
    if part is widest or part.hi[2] - part.lo[2] <= min(part.hi[0] - part.lo[0], part.hi[1] - part.lo[1]):
        return False
    tol = assembly.tolerance
    stands, held = False, False
    for other in assembly.parts:
        if other is part or contact_area(part, other, tol) <= 0:
            continue
        if abs(part.lo[2] - other.hi[2]) <= tol or abs(part.hi[2] - other.lo[2]) <= tol:
            stands = True
        else:
            held = True  # bonded through an x or y face
    return stands and not held


def _layer(part, material, structural: bool) -> Layer:
    """Plate constants of one box (short-circuit stiffness for a piezo, poled by the part)."""
    if part.poling and not structural:
        raise SceneError(f"part '{part.name}': a piezo post (taller than wide) is beyond the plate model")
    mat = material.poled(part.poling) if part.poling else material
    Q, e, eps = thin_layer_constants(mat, PLANE_STRESS)
    s = np.linalg.inv(mat.C)
    return Layer(part.name, part.lo[2], part.hi[2], Q, (float(1 / s[4, 4]), float(1 / s[3, 3])), float(mat.rho),
                 e, eps, structural)


@dataclass(frozen=True, eq=False)
class Stacks:
    """The in-plane cell grid of a device: breakpoints xs (nx+1,), ys (ny+1,) [m], the section index of
    every cell (nx, ny), the sections, the parts in each cell, each part's layer, and the reference plane
    z_r [m]."""

    xs: np.ndarray
    ys: np.ndarray
    cell_section: np.ndarray
    sections: tuple[Section, ...]
    cell_parts: tuple[tuple[tuple[str, ...], ...], ...]
    layers: dict[str, Layer]
    reference: float


def _breakpoints(values, tol: float) -> np.ndarray:
    v = np.unique(np.asarray(values, dtype=float))
    return v[np.r_[True, np.diff(v) > tol]]


def plate_stacks(scene) -> Stacks:
    """The cells and sections of a plate scene; SceneError naming what a 2-D plate cannot represent."""
    if scene.kind != "plate":
        raise SceneError(f"kind: the plate model needs a scene of kind 'plate', got '{scene.kind}'")
    assembly = scene.assembly()
    (x0, y0, _), (x1, y1, _) = scene.full_assembly().bounds
    tol = 1e-9 * max(x1 - x0, y1 - y0)
    xs_all, ys_all = [], []
    for p in assembly.parts:
        xs_all += [p.lo[0], p.hi[0]]
        ys_all += [p.lo[1], p.hi[1]]
    for faces in assembly.faces.values():
        for f in faces:
            if f.window is not None and f.side[0] == "z":
                (a, b), (c, d) = f.window
                xs_all += [a, c]
                ys_all += [b, d]
    xs, ys = _breakpoints(xs_all, tol), _breakpoints(ys_all, tol)
    widest = widest_part(assembly)
    xc, yc = 0.5 * (xs[:-1] + xs[1:]), 0.5 * (ys[:-1] + ys[1:])
    layers, signatures, sections_raw = {}, {}, []
    cell_section = np.empty((len(xc), len(yc)), dtype=int)
    cell_parts = []
    area_weighted = []
    for i, x in enumerate(xc):
        row = []
        for j, y in enumerate(yc):
            parts = sorted((p for p in assembly.parts if p.lo[0] < x < p.hi[0] and p.lo[1] < y < p.hi[1]),
                           key=lambda p: p.lo[2])
            if not parts:
                raise SceneError(f"parts: nothing covers (x, y) = ({x:g}, {y:g}) m; the plate model needs a "
                                 f"plate covering its rectangular outline")
            for a, b in itertools.pairwise(parts):
                if abs(a.hi[2] - b.lo[2]) > tol:
                    raise SceneError(f"parts: '{a.name}' and '{b.name}' do not touch through the thickness at "
                                     f"({x:g}, {y:g}) m (the plate model needs one bonded stack)")
            for p in parts:
                if p.name not in layers:
                    layers[p.name] = _layer(p, scene.material(p.material), not is_post(p, assembly, widest))
            if not any(layers[p.name].structural for p in parts):
                raise SceneError(f"parts: '{parts[0].name}' is a post (taller than wide, standing on another part) "
                                 f"but reaches beyond it at (x, y) = ({x:g}, {y:g}) m; the plate model cannot carry "
                                 f"it (use --fidelity solid)")
            key = tuple((p.material, p.lo[2], p.hi[2], p.poling) for p in parts)
            if key not in signatures:
                signatures[key] = len(sections_raw)
                sections_raw.append(tuple(layers[p.name] for p in parts))
            cell_section[i, j] = signatures[key]
            row.append(tuple(p.name for p in parts))
            cell_area = (xs[i + 1] - xs[i]) * (ys[j + 1] - ys[j])
            area_weighted.append((cell_area, parts))
        cell_parts.append(tuple(row))
    total = sum(a for a, _ in area_weighted)
    mean_thickness = sum(a * (parts[-1].hi[2] - parts[0].lo[2]) for a, parts in area_weighted) / total
    if min(x1 - x0, y1 - y0) < SLENDERNESS * mean_thickness:
        raise SceneError(f"parts: not a plate (smaller side {min(x1 - x0, y1 - y0):g} m < {SLENDERNESS:g} x mean "
                         f"thickness {mean_thickness:g} m)")
    # one reference plane: the area- and modulus-weighted mean membrane centroid of the structural layers
    weight = {n: la.Q[0, 0] * la.thickness * la.structural for n, la in layers.items()}
    centroid = [(a * sum(weight[p.name] for p in parts),
                 sum(weight[p.name] * 0.5 * (p.lo[2] + p.hi[2]) for p in parts) / sum(weight[p.name] for p in parts))
                for a, parts in area_weighted]
    zr = float(sum(w * z for w, z in centroid) / sum(w for w, _ in centroid))
    sections = tuple(section_properties(ls, zr) for ls in sections_raw)
    return Stacks(xs, ys, cell_section, sections, tuple(cell_parts), layers, zr)


def bending_wavenumber(section: Section, frequency: float) -> float:
    """Largest propagating wavenumber [rad/m] at ``frequency`` [Hz] of the section's flexural (Mindlin:
    D A_s k^4 - w^2 (I0 D + I2 A_s) k^2 + I0 w^2 (I2 w^2 - A_s) = 0, Mindlin, J. Appl. Mech. 18 (1951) 31-38,
    about the section's neutral plane) and membrane waves, along x and y."""
    w2 = (2 * np.pi * frequency) ** 2
    I0 = section.mass[0, 0]
    ks = []
    for k in (0, 1):
        A, B, D = section.stiffness[k, k], section.stiffness[k, 3 + k], section.stiffness[3 + k, 3 + k]
        D_n = D - B * B / A  # about the neutral plane
        I1, I2 = section.mass[k, 3 + k], section.mass[3 + k, 3 + k]
        I2_n = I2 - I1 * I1 / I0
        As = section.stiffness[6 + k, 6 + k]
        ks += [flexural_wavenumber(w2, D_n, As, I0, I2_n), math.sqrt(w2 * I0 / A)]
    return max(ks)


@dataclass(frozen=True, eq=False)
class PlateModel(LayeredModel):
    """Assembled plate (full DOF set, no constraint applied), with the 3-D model's interface.

    K, M : (n, n), n = n_u + n_phi; u DOFs node-major (5 i + component, order u, v, w, beta_x, beta_y; i the
    scalar Q2 DOF of ``basis``), then one potential per electrode; ``stacks`` the cell grid and sections.
    """

    stacks: Stacks | None = None

    def displacement_probes(self, points: np.ndarray) -> sp.csr_matrix:
        """(3 n, ndofs) matrix giving (ux, uy, uz) [m] at ``points`` (n, 3) [m] from a full DOF vector, rows
        component-major like ``modalfe.response.forced.probes``: U = P(z - z_r) q at each point's (x, y)."""
        p = np.array(np.atleast_2d(points), dtype=float)
        if p.ndim != 2 or p.shape[1] != 3:
            raise SceneError(f"points: must be an (n, 3) array of coordinates [m], got shape {p.shape}")
        full_lo, full_hi = (np.array(b[:2]) for b in self.scene.full_assembly().bounds)
        span = float(np.max(full_hi - full_lo))
        off = np.any((p[:, :2] < full_lo - 1e-9 * span) | (p[:, :2] > full_hi + 1e-9 * span), axis=1)
        if np.any(off):
            raise SceneError(f"points: (x, y) = ({p[off, 0][0]:g}, {p[off, 1][0]:g}) m lies off the plate")
        n = p.shape[0]
        folded, sign = fold(self.scene, p.T)  # a point in a mirrored half reads its image
        p = folded.T
        lo, hi = self.mesh.p.min(axis=1), self.mesh.p.max(axis=1)
        inside = lo + 1e-9 * span * np.sign(0.5 * (lo + hi) - lo)
        xy = np.clip(p[:, :2].T, inside[:, None], (hi - (inside - lo))[:, None])
        P = self.basis.probes(xy).tocoo()
        zeta = p[P.row, 2] - self.stacks.reference
        rows, cols, vals = [], [], []
        for c, a, coef in ((0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0), (0, 3, zeta), (1, 4, zeta)):
            rows.append(c * n + P.row)
            cols.append(5 * P.col + a)
            vals.append(P.data * coef * sign[c, P.row])
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(3 * n, self.ndofs))

    def surface_points(self) -> np.ndarray:
        """(m, 3) points [m] on the top and bottom faces of the widest part (the plate, a facing) at the mesh
        vertices it covers, unfolded across mirror planes: the surface the plate labels count nodal lines on,
        free of patches and feet."""
        full = self.scene.full_assembly()
        widest = widest_part(full)
        xy = self.mesh.p
        for axis, twice in mirror_planes(self.scene):  # the images beyond each plane, the plane's own points once
            image = mirrored(xy, axis, twice)
            xy = np.hstack([xy, image[:, image[axis] > xy[axis].max() + 1e-12]])
        inside = ((xy[0] >= widest.lo[0]) & (xy[0] <= widest.hi[0]) & (xy[1] >= widest.lo[1])
                  & (xy[1] <= widest.hi[1]))
        x, y = xy[0, inside], xy[1, inside]
        return np.vstack([np.column_stack([x, y, np.full(x.size, z)]) for z in (widest.hi[2], widest.lo[2])])


def _subdivided(breaks: np.ndarray, size: float) -> np.ndarray:
    out = [breaks[:1]]
    for a, b in itertools.pairwise(breaks):
        out.append(np.linspace(a, b, max(1, math.ceil((b - a) / size - 1e-9)) + 1)[1:])
    return np.concatenate(out)


def plate_mesh(stacks: Stacks, size: float):
    """skfem MeshQuad on the tensor grid through every cell boundary, ``size`` [m] or finer, and the cell
    (i, j) of every element."""
    from skfem import MeshQuad

    mx, my = _subdivided(stacks.xs, size), _subdivided(stacks.ys, size)
    mesh = MeshQuad.init_tensor(mx, my)
    centre = mesh.p[:, mesh.t].mean(axis=1)
    i = np.clip(np.searchsorted(stacks.xs, centre[0]) - 1, 0, len(stacks.xs) - 2)
    j = np.clip(np.searchsorted(stacks.ys, centre[1]) - 1, 0, len(stacks.ys) - 2)
    return mesh, i, j


def assemble_plate(scene, *, size_factor: float = 1.0) -> PlateModel:
    """Assemble the plate model of ``scene`` (see the module docstring)."""
    from skfem import Basis, BilinearForm, ElementQuad2, LinearForm

    t0 = time.perf_counter()
    stacks = plate_stacks(scene)
    mesh, ci, cj = plate_mesh(stacks, element_size(stacks.sections, scene, bending_wavenumber, size_factor))
    t_mesh = time.perf_counter() - t0
    element = ElementQuad2()
    basis = Basis(mesh, element, intorder=4)
    n_u = 5 * basis.N
    derivative = (lambda f: f, lambda f: f.grad[0], lambda f: f.grad[1])  # value, d/dx, d/dy
    E = _strain_maps()
    section_of_element = stacks.cell_section[ci, cj]
    K_terms, M_terms, attached_terms = [], [], []
    for k, s in enumerate(stacks.sections):
        sub = Basis(mesh, element, intorder=4, elements=np.flatnonzero(section_of_element == k))
        forms = {}  # (a, b) -> int derivative[a](v) derivative[b](u); the (b, a) form is its transpose
        for a in range(3):
            for b in range(3):
                block = E[a].T @ s.stiffness @ E[b]
                if not np.any(block):
                    continue
                if (b, a) in forms:
                    forms[a, b] = forms[b, a].T
                else:
                    forms[a, b] = BilinearForm(lambda u, v, _, a=a, b=b: derivative[a](v) * derivative[b](u)
                                               ).assemble(sub)
                K_terms.append(sp.kron(forms[a, b], block, format="coo"))
        S00 = forms[0, 0] if (0, 0) in forms else BilinearForm(lambda u, v, _: u * v).assemble(sub)
        M_terms.append(sp.kron(S00, s.mass, format="coo"))
    for group, stiffness, inertia in _face_loads(scene):
        sub, zeta = _face_basis(scene, group, mesh, basis, stacks, element, ci, cj)
        P = _displacement_map(zeta - stacks.reference)
        S00 = BilinearForm(lambda u, v, _: u * v).assemble(sub)
        if stiffness is not None:
            K_terms.append(sp.kron(S00, P.T @ np.diag(stiffness) @ P, format="coo"))
        if inertia is not None:
            attached_terms.append(sp.kron(S00, inertia * P.T @ P, format="coo"))
    attached = _summed(attached_terms, n_u) if attached_terms else None
    K, M = _summed(K_terms, n_u), _summed(M_terms, n_u)
    if attached is not None:
        M = M + attached
    index, piezo = electrode_layers(scene, scene.assembly())
    n_phi = len(index)
    if n_phi:
        Kup = np.zeros((n_u, n_phi))
        capacitors = []
        for part, top, bottom in piezo:
            cells = np.array([[part.name in names for names in row] for row in stacks.cell_parts])
            sub = Basis(mesh, element, intorder=4, elements=np.flatnonzero(cells[ci, cj]))
            layer = stacks.layers[part.name]
            zc = 0.5 * (layer.z0 + layer.z1) - stacks.reference
            c = np.concatenate([layer.e, zc * layer.e, [0.0, 0.0]])  # e* . (eps0 + zc kappa): int over h, / h
            coupling = np.zeros(n_u)
            for a in range(3):
                row = c @ E[a]
                if np.any(row):
                    V = LinearForm(lambda v, _, a=a: derivative[a](v)).assemble(sub)
                    coupling += np.kron(V, row)
            Kup[:, index[top]] += coupling
            Kup[:, index[bottom]] -= coupling
            area = (part.hi[0] - part.lo[0]) * (part.hi[1] - part.lo[1])
            capacitors.append((index[top], index[bottom], layer.eps * area / layer.thickness))
        Kpp = capacitance_matrix(n_phi, capacitors)
        K = sp.bmat([[K, sp.csr_matrix(Kup)], [sp.csr_matrix(Kup).T, -sp.csr_matrix(Kpp)]], format="csr")
        M = sp.block_diag([M, sp.csr_matrix((n_phi, n_phi))], format="csr")
    clamped, guided = _supported_dofs(scene, basis, mesh)
    timings = {"mesh": t_mesh, "assembly": time.perf_counter() - t0 - t_mesh}
    return PlateModel(scene, mesh, basis, K.tocsr(), M.tocsr(), n_u, {g: np.array([i]) for g, i in index.items()},
                      clamped, timings, attached_mass=attached, guided=guided, stacks=stacks)


def _summed(terms, n: int) -> sp.csr_matrix:
    """Sum of the sparse (n, n) ``terms`` in one COO-to-CSR conversion (duplicates added, zeros dropped)."""
    coo = [t.tocoo() for t in terms]
    if not coo:
        return sp.csr_matrix((n, n))
    S = sp.coo_matrix((np.concatenate([t.data for t in coo]),
                       (np.concatenate([t.row for t in coo]), np.concatenate([t.col for t in coo]))),
                      shape=(n, n)).tocsr()
    S.eliminate_zeros()
    return S


def _face_loads(scene):
    """(group, stiffness per area (3,) or None, mass per area or None) of the scene's springs and masses: the
    scene gives totals for the whole face, spread uniformly, so a symmetric part carries its share."""
    full, kept = scene.full_assembly(), scene.assembly().faces
    for group, k in scene.springs.items():
        if group in kept:
            yield group, np.asarray(k, dtype=float) / full.face_area(group), None
    for group, m in scene.masses.items():
        if group in kept:
            yield group, None, m / full.face_area(group)


def _face_basis(scene, group, mesh, basis, stacks, element, ci, cj):
    """(Basis on the elements under a z face group, the face's height [m])."""
    from skfem import Basis

    assembly = scene.assembly()
    chosen = np.zeros(mesh.t.shape[1], dtype=bool)
    heights = set()
    centre = mesh.p[:, mesh.t].mean(axis=1)
    for f in assembly.faces[group]:
        axis, z, lo, hi = assembly.part(f.part).face_bounds(f.side, f.window)
        if axis != 2:
            raise SceneError(f"{group}: springs and masses on side faces are not supported by the plate model")
        heights.add(round(z, 12))
        chosen |= (centre[0] > lo[0]) & (centre[0] < hi[0]) & (centre[1] > lo[1]) & (centre[1] < hi[1])
    if len(heights) != 1:
        raise SceneError(f"{group}: the plate model needs the faces of a group at one height")
    return Basis(mesh, element, intorder=4, elements=np.flatnonzero(chosen)), heights.pop()


def _supported_dofs(scene, basis, mesh) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """(clamped, guided) u DOFs of clamps, guides and mirror planes. On a side face (normal x or y) the displacement
    is fixed over the face's height, so fixing x stops u and beta_x, y stops v and beta_y, z stops w; on a z face
    only w can be fixed without constraining a combination of unknowns. A guide holds a component uniform over the
    face: on a side face its rotation (beta_x for x, beta_y for y) is fixed and its translation along the edge is one
    shared unknown (``modalfe.models.constraints.shared_unknowns``); on a z face only w. Edge supports: SceneError
    (the mid-surface has no lines at a face's height)."""
    if scene.edges:
        raise SceneError(f"edges.{next(iter(scene.edges))}: the plate model's mid-surface has no lines at a face's "
                         f"height; line supports are solved by the solid model")
    assembly = scene.assembly()
    span = max(np.ptp(mesh.p[0]), np.ptp(mesh.p[1]))
    tol = 1e-9 * span
    x = basis.doflocs
    fixed, shared = set(), []
    supports = [("clamps", group, components) for group, components in {**scene.clamps,
                                                                        **scene.symmetry_clamps}.items()]
    supports += [("guides", group, components) for group, components in scene.guides.items()]
    for role, group, components in supports:
        for f in assembly.faces[group]:
            axis, c, lo, hi = assembly.part(f.part).face_bounds(f.side, f.window)
            if axis == 2:
                if set(components) - {"z"}:
                    raise SceneError(f"{role}.{group}: on a z face the plate model can hold only 'z'")
                on = (x[0] >= lo[0] - tol) & (x[0] <= hi[0] + tol) & (x[1] >= lo[1] - tol) & (x[1] <= hi[1] + tol)
            else:
                other = 1 - axis
                on = (np.abs(x[axis] - c) <= tol) & (x[other] >= lo[other] - tol) & (x[other] <= hi[other] + tol)
            nodes = np.flatnonzero(on)
            for comp in components:
                translation, *rotation = _COMPONENT_DOFS[comp]
                held = _COMPONENT_DOFS[comp] if role == "clamps" else rotation
                fixed |= {5 * int(n) + a for n in nodes for a in held}
                if role == "guides":
                    shared.append(5 * nodes + translation)
    return shared_unknowns(5 * basis.N, shared, np.array(sorted(fixed), dtype=int))
