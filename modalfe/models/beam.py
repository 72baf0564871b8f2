"""1-D Timoshenko beam along x with layered sections, on scikit-fem: the ``beam`` rung of the fidelity ladder.

The device's boxes are cut into segments at every part's x-boundary; each segment's section is the stack
of boxes covering it. Six unknowns per node on one reference axis (y_r, z_r) shared by all segments,

    q = (u, v, w, theta_x, theta_y, theta_z),   U(x, y, z) = (u, v, w) + theta x (0, y - y_r, z - z_r)

so eps_xx = u' + dz theta_y' - dy theta_z', gamma_xz = w' + theta_y, gamma_xy = v' - theta_z, twist theta_x'.
Integrating E eps_xx^2 over the layers about the common axis keeps the axial-bending coupling of
unsymmetric or stepped sections exactly (laminate theory; e.g. Reddy, Mechanics of Laminated Composite
Plates and Shells, 2nd ed. 2004, ch. 3), and the section mass matrix int rho N^T N dA carries translational,
rotary and torsional inertia and their offsets. Shear: kappa G A with Cowper's kappa; torsion: Saint-Venant.

Quadratic Lagrange elements (``ElementLineP2``) for all six fields; the transverse-shear terms are
integrated with 2-point Gauss (reduced), the field-consistent rule that removes shear locking of the
quadratic Timoshenko element without spurious modes (Prathap & Bhashyam, 'Reduced integration and the
shear-flexible beam element', Int. J. Numer. Meth. Eng. 18 (1982) 195-210); everything else is exact.

Piezoelectric sheets (poled along +-z, electrodes on their z faces): field E3 uniform through each sheet,
beam (uniaxial stress) constants T1 = S1 / s11^E - e_b E3, D3 = e_b S1 + eps_b E3 with

    e_b = d31 / s11^E,  eps_b = eps33^T - d31^2 / s11^E = eps33^T (1 - k31^2)

(d-form with T2 = T3 = 0 solved for T1; Smits, Dalke & Cooney, 'The constituent equations of
piezoelectric bimorphs', Sens. Actuators A 28 (1991) 41-61; constants from IEEE Std 176-1987 relations
via ``modalfe.scene.materials.piezo_compliance_form``). One potential unknown per electrode face group, as the
3-D model's electrodes: the matrices have the same block form [[K_uu, K_uphi], [K_uphi^T, -K_phiphi]].
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError
from modalfe.models.layered import (
    LayeredModel,
    capacitance_matrix,
    electrode_layers,
    element_size,
    flexural_wavenumber,
    thin_layer_constants,
)

SLENDERNESS = 5.0  # length / largest section size below which a 1-D model is refused
SURFACE_SAMPLES = 241  # x-samples of each surface line for labels (60 label stations, 4 samples each)
_COMPONENT_DOFS = {"x": (0, 4, 5), "y": (1, 3), "z": (2, 3)}  # a face fixed along x stops u, theta_y, theta_z
# a face held uniform along x (guided) keeps its plane normal to the axis: theta_y = theta_z = 0; along y or z, no
# twist: theta_x = 0 (u_y = v - z theta_x, u_z = w + y theta_x over the section)
_GUIDED_DOFS = {"x": (4, 5), "y": (3,), "z": (3,)}


@dataclass(frozen=True)
class Layer:
    """One box of a section: extent y0..y1, z0..z1 [m]; E = 1/s11 along x, G_xz = 1/s55, G_xy = 1/s66 [Pa];
    nu = -(s12 + s13) / (2 s11); rho [kg/m^3]; piezo constants e_b [C/m^2], eps_b [F/m] (0 if passive)."""

    part: str
    y0: float
    y1: float
    z0: float
    z1: float
    E: float
    G_xz: float
    G_xy: float
    nu: float
    rho: float
    e_b: float = 0.0
    eps_b: float = 0.0

    @property
    def area(self) -> float:
        return (self.y1 - self.y0) * (self.z1 - self.z0)


@dataclass(frozen=True, eq=False)
class Section:
    """Properties of one segment x0..x1 [m].

    EI_y = int E (z - z_n)^2 dA (bending in the xz plane, deflection w), EI_z = int E (y - y_n)^2 dA [N m^2]
    about the modulus-weighted centroid (y_n, z_n); GJ [N m^2]; kGA_z, kGA_y : shear stiffness in the xz and
    xy planes [N]; stiffness (6, 6) on q' (axial-bending-torsion, about the reference axis; EA = stiffness[0, 0]
    [N]), mass (6, 6) on q (rhoA = mass[0, 0] [kg/m]).
    """

    x0: float
    x1: float
    layers: tuple[Layer, ...]
    EI_y: float
    EI_z: float
    GJ: float
    kGA_z: float
    kGA_y: float
    stiffness: np.ndarray
    mass: np.ndarray

    @property
    def length(self) -> float:
        return self.x1 - self.x0

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """(y_min, y_max, z_min, z_max) [m] of the section."""
        return (min(la.y0 for la in self.layers), max(la.y1 for la in self.layers),
                min(la.z0 for la in self.layers), max(la.z1 for la in self.layers))


def _moments(layer: Layer, yr: float, zr: float) -> tuple[float, ...]:
    """(A, int dy, int dz, int dy^2, int dz^2, int dy dz) over the layer, dy = y - yr, dz = z - zr."""
    a0, a1, b0, b1 = layer.y0 - yr, layer.y1 - yr, layer.z0 - zr, layer.z1 - zr
    wy, wz = a1 - a0, b1 - b0
    sy, sz = (a1**2 - a0**2) / 2, (b1**2 - b0**2) / 2
    return wy * wz, sy * wz, sz * wy, (a1**3 - a0**3) / 3 * wz, (b1**3 - b0**3) / 3 * wy, sy * sz


def _integrated(R0: np.ndarray, Ry: np.ndarray, Rz: np.ndarray, m: tuple[float, ...]) -> np.ndarray:
    """int R^T R dA for R = R0 + dy Ry + dz Rz, from the area moments ``m`` of ``_moments``."""
    A, Sy, Sz, Iyy, Izz, Iyz = m
    return (A * R0.T @ R0 + Sy * (R0.T @ Ry + Ry.T @ R0) + Sz * (R0.T @ Rz + Rz.T @ R0)
            + Iyy * Ry.T @ Ry + Izz * Rz.T @ Rz + Iyz * (Ry.T @ Rz + Rz.T @ Ry))


def _displacement_map() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """N = N0 + dy Ny + dz Nz (3, 6): (ux, uy, uz) at offset (dy, dz) from q = (u, v, w, tx, ty, tz)."""
    N0 = np.hstack([np.eye(3), np.zeros((3, 3))])
    Ny, Nz = np.zeros((3, 6)), np.zeros((3, 6))
    Ny[0, 5], Ny[2, 3] = -1.0, 1.0  # ux -= dy theta_z, uz += dy theta_x
    Nz[0, 4], Nz[1, 3] = 1.0, -1.0  # ux += dz theta_y, uy -= dz theta_x
    return N0, Ny, Nz


def cowper_shear_coefficient_rectangle(nu: float) -> float:
    """Timoshenko shear coefficient of a solid rectangle, kappa = 10 (1 + nu) / (12 + 11 nu).

    Cowper, 'The shear coefficient in Timoshenko's beam theory', J. Appl. Mech. 33 (1966) 335-340
    (its result for the solid rectangular section).
    """
    return 10 * (1 + nu) / (12 + 11 * nu)


def torsion_constant_rectangle(b: float, t: float, terms: int = 20) -> float:
    """Saint-Venant torsion constant J [m^4] of a b x t rectangle:

        J = b t^3 / 3 [1 - 192 t / (pi^5 b) sum_{n odd} tanh(n pi b / (2 t)) / n^5],  b >= t

    (Timoshenko & Goodier, Theory of Elasticity, 3rd ed. 1970, sec. 109; J = 0.1406 b^4 for a square).
    """
    b, t = max(b, t), min(b, t)
    n = np.arange(1, 2 * terms, 2, dtype=float)
    series = np.sum(np.tanh(n * np.pi * b / (2 * t)) / n**5)
    return b * t**3 / 3 * (1 - 192 * t / (np.pi**5 * b) * series)


def section_properties(x0: float, x1: float, layers: tuple[Layer, ...], yr: float, zr: float) -> Section:
    """Section of one segment from its layers, about the reference axis (yr, zr) [m].

    Shear: kappa sum G_i A_i with Cowper's rectangle kappa = 10 (1 + nu) / (12 + 11 nu) (Cowper, J. Appl.
    Mech. 33 (1966) 335-340) at the EA-weighted nu; exact for one material, an approximation for layers.
    Torsion: sum G_i J_i of the layers' own rectangles, or, where the layers fill their bounding rectangle,
    G_eq J(bounding rectangle) with G_eq the layers' G weighted by s^2 across the short side (s from the
    centre: exact in the thin-strip limit, where the shear stress is linear across the thickness); per
    layer G = sqrt(G_xy G_xz) (exact when isotropic).
    """
    N0, Ny, Nz = _displacement_map()
    a0 = np.zeros((1, 6))
    a0[0, 0] = 1.0
    ay, az = np.zeros((1, 6)), np.zeros((1, 6))
    ay[0, 5], az[0, 4] = -1.0, 1.0  # eps_xx = u' - dy theta_z' + dz theta_y'
    stiffness, mass = np.zeros((6, 6)), np.zeros((6, 6))
    EA = ESy = ESz = 0.0
    for la in layers:
        m = _moments(la, yr, zr)
        stiffness += la.E * _integrated(a0, ay, az, m)
        mass += la.rho * _integrated(N0, Ny, Nz, m)
        EA += la.E * m[0]
        ESy += la.E * m[1]
        ESz += la.E * m[2]
    y_n, z_n = yr + ESy / EA, zr + ESz / EA
    about_n = [_moments(la, y_n, z_n) for la in layers]
    EI_y = sum(la.E * m[4] for la, m in zip(layers, about_n))
    EI_z = sum(la.E * m[3] for la, m in zip(layers, about_n))
    nu = sum(la.E * la.area * la.nu for la in layers) / EA
    kappa = cowper_shear_coefficient_rectangle(nu)
    kGA_z = kappa * sum(la.G_xz * la.area for la in layers)
    kGA_y = kappa * sum(la.G_xy * la.area for la in layers)
    GJ = _torsion_stiffness(layers)
    stiffness[3, 3] += GJ
    return Section(x0, x1, layers, EI_y, EI_z, GJ, kGA_z, kGA_y, stiffness, mass)


def _torsion_stiffness(layers: tuple[Layer, ...]) -> float:
    """GJ [N m^2] of a section (see ``section_properties``)."""
    y0, y1 = min(la.y0 for la in layers), max(la.y1 for la in layers)
    z0, z1 = min(la.z0 for la in layers), max(la.z1 for la in layers)
    G = [math.sqrt(la.G_xy * la.G_xz) for la in layers]
    if not math.isclose(sum(la.area for la in layers), (y1 - y0) * (z1 - z0), rel_tol=1e-9):
        return sum(g * torsion_constant_rectangle(la.y1 - la.y0, la.z1 - la.z0) for g, la in zip(G, layers))
    if (y1 - y0) <= (z1 - z0):  # short side along y: weight int s^2 ds across y
        c = 0.5 * (y0 + y1)
        w = [((la.y1 - c) ** 3 - (la.y0 - c) ** 3) * (la.z1 - la.z0) for la in layers]
    else:
        c = 0.5 * (z0 + z1)
        w = [((la.z1 - c) ** 3 - (la.z0 - c) ** 3) * (la.y1 - la.y0) for la in layers]
    G_eq = sum(g * wi for g, wi in zip(G, w)) / sum(w)
    return G_eq * torsion_constant_rectangle(y1 - y0, z1 - z0)


def _layer(part, mat) -> Layer:
    """Beam constants of one box: uniaxial stress along x (s = inv(c^E), short-circuit for a piezo)."""
    s = np.linalg.inv(mat.C)
    _, e_b, eps_b = thin_layer_constants(mat, [0]) if part.poling else (None, np.zeros(1), 0.0)
    return Layer(part.name, part.lo[1], part.hi[1], part.lo[2], part.hi[2], float(1 / s[0, 0]),
                 float(1 / s[4, 4]), float(1 / s[5, 5]), float(-(s[0, 1] + s[0, 2]) / (2 * s[0, 0])),
                 float(mat.rho), float(e_b[0]), eps_b)


def beam_sections(scene) -> tuple[tuple[Section, ...], tuple[float, float]]:
    """(sections along x, reference axis (y_r, z_r) [m]) of a beam scene; SceneError naming what a 1-D
    beam along x cannot represent."""
    if scene.kind != "beam":
        raise SceneError(f"kind: the beam model needs a scene of kind 'beam', got '{scene.kind}'")
    for table in ("springs", "masses"):
        if getattr(scene, table):
            raise SceneError(f"{table}: not supported by the beam model (use fidelity 'solid')")
    assembly = scene.full_assembly()
    (xmin, ymin, zmin), (xmax, ymax, zmax) = assembly.bounds
    L = xmax - xmin
    size = max(ymax - ymin, zmax - zmin)
    if SLENDERNESS * size > L:
        raise SceneError(f"parts: not a beam along x (length {L:g} m < {SLENDERNESS:g} x section size {size:g} m)")
    tol = 1e-9 * L
    cuts = np.unique(np.array([c for p in assembly.parts for c in (p.lo[0], p.hi[0])]))
    cuts = cuts[np.r_[True, np.diff(cuts) > tol]]
    materials = {}
    raw = []
    for xa, xb in itertools.pairwise(cuts):
        parts = [p for p in assembly.parts if p.lo[0] <= xa + tol and p.hi[0] >= xb - tol]
        if not parts:
            raise SceneError(f"parts: nothing spans x = {xa:g}..{xb:g} m; the beam model needs a continuous beam")
        _check_connected(parts, f"x = {xa:g}..{xb:g} m", tol)
        if raw:
            _check_bonded_across(raw[-1][2], parts, xa, tol)
        for p in parts:
            if p.name not in materials:
                mat = scene.material(p.material)
                materials[p.name] = _layer(p, mat.poled(p.poling) if p.poling else mat)
        raw.append((float(xa), float(xb), parts))
    # one reference axis for all segments: the length- and EA-weighted mean neutral axis
    weights = [(xb - xa) * sum(materials[p.name].E * materials[p.name].area for p in parts) for xa, xb, parts in raw]
    cy = [sum(materials[p.name].E * materials[p.name].area * 0.5 * (p.lo[1] + p.hi[1]) for p in parts)
          / sum(materials[p.name].E * materials[p.name].area for p in parts) for _, _, parts in raw]
    cz = [sum(materials[p.name].E * materials[p.name].area * 0.5 * (p.lo[2] + p.hi[2]) for p in parts)
          / sum(materials[p.name].E * materials[p.name].area for p in parts) for _, _, parts in raw]
    yr, zr = float(np.average(cy, weights=weights)), float(np.average(cz, weights=weights))
    sections = tuple(section_properties(xa, xb, tuple(materials[p.name] for p in parts), yr, zr)
                     for xa, xb, parts in raw)
    return sections, (yr, zr)


def _touch(a, b, tol: float) -> bool:
    """Two boxes' y-z rectangles share an edge of positive length."""
    oy = min(a.hi[1], b.hi[1]) - max(a.lo[1], b.lo[1])
    oz = min(a.hi[2], b.hi[2]) - max(a.lo[2], b.lo[2])
    return (abs(oy) <= tol and oz > tol) or (abs(oz) <= tol and oy > tol)


def _check_connected(parts, where: str, tol: float) -> None:
    reached, todo = {0}, [0]
    while todo:
        i = todo.pop()
        for j in range(len(parts)):
            if j not in reached and _touch(parts[i], parts[j], tol):
                reached.add(j)
                todo.append(j)
    if len(reached) < len(parts):
        loose = next(p.name for j, p in enumerate(parts) if j not in reached)
        raise SceneError(f"parts: '{loose}' is not bonded to the rest of the section at {where} "
                         f"(the beam model needs one connected section)")


def _check_bonded_across(before, after, x: float, tol: float) -> None:
    for a in before:
        for b in after:
            if (min(a.hi[1], b.hi[1]) - max(a.lo[1], b.lo[1]) > tol
                    and min(a.hi[2], b.hi[2]) - max(a.lo[2], b.lo[2]) > tol):
                return
    raise SceneError(f"parts: the sections either side of x = {x:g} m do not overlap (not one beam)")


def bending_wavenumber(section: Section, frequency: float) -> float:
    """Largest propagating wavenumber [rad/m] at ``frequency`` [Hz] of the section's bending (Timoshenko),
    axial and torsion waves. Bending: EI kGA k^4 - w^2 (rhoA EI + rhoI kGA) k^2 + rhoA w^2 (rhoI w^2 - kGA) = 0
    (from the Timoshenko equations, Han, Benaroya & Wei, J. Sound Vib. 225 (1999) 935-988)."""
    w2 = (2 * np.pi * frequency) ** 2
    rhoA, EA = float(section.mass[0, 0]), float(section.stiffness[0, 0])
    ks = [math.sqrt(w2 * rhoA / EA), math.sqrt(w2 * section.mass[3, 3] / section.GJ)]
    for EI, kGA, rhoI in ((section.EI_y, section.kGA_z, section.mass[4, 4]),
                          (section.EI_z, section.kGA_y, section.mass[5, 5])):
        ks.append(flexural_wavenumber(w2, EI, kGA, rhoA, rhoI))
    return max(ks)


@dataclass(frozen=True, eq=False)
class BeamModel(LayeredModel):
    """Assembled 1-D beam (full DOF set, no constraint applied), with the 3-D model's interface.

    K, M : (n, n), n = n_u + n_phi; u DOFs first, node-major (6 i + component, component order
    u, v, w, theta_x, theta_y, theta_z; i the scalar P2 DOF of ``basis``), then one potential per electrode
    electrodes : electrode face group -> index into the phi unknowns (one each)
    clamped : u DOF indices fixed to zero; reference : beam axis (y_r, z_r) [m]
    """

    copies = 1  # the beam model always solves the whole device

    sections: tuple[Section, ...] = ()
    reference: tuple[float, float] = (0.0, 0.0)

    def displacement_probes(self, points: np.ndarray) -> sp.csr_matrix:
        """(3 n, ndofs) matrix giving (ux, uy, uz) [m] at ``points`` (n, 3) [m] from a full DOF vector,
        rows component-major (all ux, then uy, then uz) like ``modalfe.response.forced.probes``: the axis motion
        plus theta x (offset from the axis) at each point's x."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        if p.ndim != 2 or p.shape[1] != 3:
            raise SceneError(f"points: must be an (n, 3) array of coordinates [m], got shape {p.shape}")
        x0, x1 = float(self.mesh.p[0].min()), float(self.mesh.p[0].max())
        outside = (p[:, 0] < x0 - 1e-9 * (x1 - x0)) | (p[:, 0] > x1 + 1e-9 * (x1 - x0))
        if np.any(outside):
            raise SceneError(f"points: x = {p[outside, 0][0]:g} m lies off the beam ({x0:g}..{x1:g} m)")
        n = p.shape[0]
        P = self.basis.probes(np.clip(p[:, 0], x0, x1)[None, :]).tocoo()  # (n, N scalar)
        dy, dz = p[P.row, 1] - self.reference[0], p[P.row, 2] - self.reference[1]
        N0, Ny, Nz = _displacement_map()
        rows, cols, vals = [], [], []
        for c in range(3):
            for a in range(6):
                coef = N0[c, a] + dy * Ny[c, a] + dz * Nz[c, a]
                if not np.any(coef):
                    continue
                rows.append(c * n + P.row)
                cols.append(6 * P.col + a)
                vals.append(P.data * coef)
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(3 * n, self.ndofs))

    def surface_points(self) -> np.ndarray:
        """(m, 3) points [m] on four lines along the surface: top and bottom (at each section's mid-width)
        and the two sides (at mid-height), ``SURFACE_SAMPLES`` along x each."""
        xs = np.linspace(self.mesh.p[0].min(), self.mesh.p[0].max(), SURFACE_SAMPLES)
        ends = np.array([s.x1 for s in self.sections])
        which = np.minimum(np.searchsorted(ends, xs), len(self.sections) - 1)
        b = np.array([self.sections[i].bounds for i in which])  # y0, y1, z0, z1
        yc, zc = 0.5 * (b[:, 0] + b[:, 1]), 0.5 * (b[:, 2] + b[:, 3])
        lines = [(yc, b[:, 3]), (yc, b[:, 2]), (b[:, 0], zc), (b[:, 1], zc)]
        return np.vstack([np.column_stack([xs, y, z]) for y, z in lines])


def beam_mesh(sections: tuple[Section, ...], size: float):
    """skfem MeshLine with nodes at every segment boundary and ``size`` [m] or finer elements in between,
    and the element indices of each segment."""
    from skfem import MeshLine

    nodes, owners = [np.array([sections[0].x0])], []
    for i, s in enumerate(sections):
        n = max(1, math.ceil(s.length / size - 1e-9))
        nodes.append(np.linspace(s.x0, s.x1, n + 1)[1:])
        owners.append(np.full(n, i))
    return MeshLine(np.concatenate(nodes)), np.concatenate(owners)


def assemble_beam(scene, *, size_factor: float = 1.0) -> BeamModel:
    """Assemble the beam model of ``scene`` (see the module docstring)."""
    from skfem import Basis, BilinearForm, ElementLineP2

    t0 = time.perf_counter()
    sections, reference = beam_sections(scene)
    mesh, owner = beam_mesh(sections, element_size(sections, scene, bending_wavenumber, size_factor))
    t_mesh = time.perf_counter() - t0
    element = ElementLineP2()
    basis = Basis(mesh, element, intorder=4)
    N = basis.N
    n_u = 6 * N

    @BilinearForm
    def dd(u, v, _):
        return u.grad[0] * v.grad[0]

    @BilinearForm
    def d0(u, v, _):  # [i, j] = int N_i' N_j: test function derivative, trial value
        return u * v.grad[0]

    @BilinearForm
    def mass(u, v, _):
        return u * v

    Q1 = np.zeros((2, 6))
    Q1[0, 2], Q1[1, 1] = 1.0, 1.0  # gamma_xz = w' + theta_y, gamma_xy = v' - theta_z
    Q0 = np.zeros((2, 6))
    Q0[0, 4], Q0[1, 5] = 1.0, -1.0
    K = sp.csr_matrix((n_u, n_u))
    M = sp.csr_matrix((n_u, n_u))
    for i, s in enumerate(sections):
        elements = np.flatnonzero(owner == i)
        full = Basis(mesh, element, intorder=4, elements=elements)  # exact for P2 x P2
        reduced = Basis(mesh, element, intorder=2, elements=elements)  # 2-point Gauss: shear only
        S_dd, S_mm = dd.assemble(full), mass.assemble(full)
        R_dd, R_d0, R_mm = dd.assemble(reduced), d0.assemble(reduced), mass.assemble(reduced)
        D = np.diag([s.kGA_z, s.kGA_y])
        K = K + sp.kron(S_dd, s.stiffness) + sp.kron(R_dd, Q1.T @ D @ Q1) + sp.kron(R_d0, Q1.T @ D @ Q0) \
            + sp.kron(R_d0.T, Q0.T @ D @ Q1) + sp.kron(R_mm, Q0.T @ D @ Q0)
        M = M + sp.kron(S_mm, s.mass)
    Kup, Kpp, electrodes = _piezo_blocks(scene, sections, reference, basis, n_u)
    n_phi = len(electrodes)
    if n_phi:
        K = sp.bmat([[K, Kup], [Kup.T, -Kpp]], format="csr")
        M = sp.block_diag([M, sp.csr_matrix((n_phi, n_phi))], format="csr")
    clamped = _clamped_dofs(scene, basis, mesh)
    timings = {"mesh": t_mesh, "assembly": time.perf_counter() - t0 - t_mesh}
    return BeamModel(scene, mesh, basis, K.tocsr(), M.tocsr(), n_u, electrodes, clamped, timings,
                     sections=sections, reference=reference)


def _piezo_blocks(scene, sections, reference, basis, n_u):
    """K_uphi (n_u, n_phi) and K_phiphi (n_phi, n_phi) of the piezo layers, one phi per electrode group.

    Per sheet of height h_z, width b_y, field dphi/dz = (phi_zmax - phi_zmin) / h_z uniform:
    K_uphi = e_b / h_z int (int eps_xx dA) dx, where int N_i' dx over the sheet is N_i(x1) - N_i(x0) (the
    sheet acts at its ends); K_phiphi = C [[1, -1], [-1, 1]], C = eps_b b_y l / h_z its capacitance.
    """
    index, piezo = electrode_layers(scene, scene.full_assembly())
    n_phi = len(index)
    rows_up, cols_up, vals_up = [], [], []
    capacitors = []
    yr, zr = reference
    for part, top, bottom in piezo:
        layer = next(la for s in sections for la in s.layers if la.part == part.name)
        hz, by, length = part.hi[2] - part.lo[2], part.hi[1] - part.lo[1], part.hi[0] - part.lo[0]
        # int eps_xx dA = A u' + (int dz) theta_y' - (int dy) theta_z'
        a = np.zeros(6)
        a[0] = by * hz
        a[4] = by * hz * (0.5 * (part.lo[2] + part.hi[2]) - zr)
        a[5] = -by * hz * (0.5 * (part.lo[1] + part.hi[1]) - yr)
        ends = basis.probes(np.array([[part.lo[0], part.hi[0]]])).toarray()  # (2, N)
        dN = ends[1] - ends[0]
        nodes = np.flatnonzero(np.abs(dN) > 1e-12)
        coupling = np.outer(dN[nodes], layer.e_b * a / hz)  # (nodes, 6)
        rows = (6 * nodes[:, None] + np.arange(6)[None, :]).ravel()
        for g, sign in ((top, 1.0), (bottom, -1.0)):
            rows_up.append(rows)
            cols_up.append(np.full(len(rows), index[g]))
            vals_up.append(sign * coupling.ravel())
        capacitors.append((index[top], index[bottom], layer.eps_b * by * length / hz))
    Kup = sp.csr_matrix((np.concatenate(vals_up), (np.concatenate(rows_up), np.concatenate(cols_up))),
                        shape=(n_u, n_phi)) if vals_up else sp.csr_matrix((n_u, n_phi))
    return Kup, sp.csr_matrix(capacitance_matrix(n_phi, capacitors)), {g: np.array([i]) for g, i in index.items()}


def _clamped_dofs(scene, basis, mesh) -> np.ndarray:
    """u DOFs fixed by clamps on the end faces: fixing x on a face stops u, theta_y, theta_z; y stops v,
    theta_x; z stops w, theta_x; so ``xyz`` is a full clamp (all six). A guide (``Scene.guides``: a component
    uniform over the end face) fixes the rotations that would vary it (``_GUIDED_DOFS``); the node's translations are
    one unknown each already. Edge supports: SceneError (a line on the section has no beam DOFs)."""
    if scene.edges:
        raise SceneError(f"edges.{next(iter(scene.edges))}: the beam model has no lines on its end faces; line "
                         f"supports are solved by the solid model")
    assembly = scene.full_assembly()
    (xmin, _, _), (xmax, _, _) = assembly.bounds
    tol = 1e-9 * (xmax - xmin)
    fixed = set()
    for role, table, dofs in (("clamps", scene.clamps, _COMPONENT_DOFS), ("guides", scene.guides, _GUIDED_DOFS)):
        for group, components in table.items():
            for f in assembly.faces[group]:
                part = assembly.part(f.part)
                if f.window is not None:
                    raise SceneError(f"{role}.{group}: face windows are not supported by the beam model")
                if f.side == "xmin" and abs(part.lo[0] - xmin) <= tol:
                    x = xmin
                elif f.side == "xmax" and abs(part.hi[0] - xmax) <= tol:
                    x = xmax
                else:
                    raise SceneError(f"{role}.{group}: '{f.part}.{f.side}' is not an end face of the beam "
                                     f"(x = {xmin:g} or {xmax:g} m), the only supports the beam model has")
                vertex = int(np.argmin(np.abs(mesh.p[0] - x)))
                node = int(basis.nodal_dofs[0, vertex])
                fixed |= {6 * node + a for c in components for a in dofs[c]}
    return np.array(sorted(fixed), dtype=int)
