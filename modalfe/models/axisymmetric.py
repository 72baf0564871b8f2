"""Axisymmetric model of a body of revolution on its meridian (r, z) plane, circumferential harmonics n = 0..N:
the ``axisymmetric`` rung of the fidelity ladder, on scikit-fem Lagrange quadrilaterals of order 2-4.

Unknowns per node and harmonic (the "symmetric" Fourier set, Zienkiewicz, Taylor & Zhu, The Finite Element
Method: Its Basis and Fundamentals, 7th ed. 2013, sec. 9.5 "Axisymmetric solids with non-symmetric load"):

    u_r = U_r(r, z) cos n theta,   u_theta = U_theta(r, z) sin n theta,   u_z = U_z(r, z) cos n theta,
    phi = Phi(r, z) cos n theta.

Each n >= 1 mode stands for a degenerate pair of the 3-D body (its twin is the set turned by pi / 2n), which the
model solves once. For n = 0 the sine set has u_theta = 0; the torsional motion u_theta = U_theta(r, z) (the other
Fourier set at n = 0) decouples from (U_r, U_z, Phi) and is kept in the same system, so the n = 0 block gives the
radial, thickness and flexural (0, c) modes and the torsional ones (labels ``T1``...) together.

Strains (Voigt order r, theta, z, theta-z, r-z, r-theta: xx, yy, zz, yz, xz, xy of the local frame) and the
potential gradient G = -E, as amplitudes of cos n theta (rr, tt, zz, rz, G_r, G_z) or sin n theta (tz, rt, G_t):

    S_rr = U_r,r            S_tt = (U_r + n U_t) / r           S_zz = U_z,z
    S_tz = U_t,z - n U_z / r    S_rz = U_r,z + U_z,r      S_rt = U_t,r - (n U_r + U_t) / r
    G_r = Phi,r             G_t = -n Phi / r                   G_z = Phi,z

e-form piezoelectricity as the 3-D model (Allik & Hughes, Int. J. Numer. Meth. Eng. 2 (1970) 151-157), T = c^E S -
e^T E, D = e S + eps^S E, so the harmonic's energy is c_n int [S; G]^T [[c^E, e^T], [e, -eps^S]] [S; G] r dr dz
with c_n = int cos^2 n theta dtheta = pi (n >= 1), 2 pi (n = 0; the torsional set's too). The material must not
couple the cosine and sine amplitudes, which holds for any material transversely isotropic about the axis (checked)
and for ceramics poled along the axis or radially (Kagawa & Yamabuchi, IEEE Trans. Sonics Ultrason. 23 (1976)
379-385, for the n = 0 piezoelectric form). The mass is c_n int rho (U_r^2 + U_t^2 + U_z^2) r dr dz, so modal
masses are the whole body's (of one member of a pair). Integrals at Gauss points (r > 0).

Regularity on the axis r = 0 (the revolved field single-valued with finite strain energy: S_tt, S_rt, S_tz and G_t
bounded as r -> 0), standard for Fourier-series axisymmetric elements (e.g. Bathe, Finite Element Procedures, 2nd
ed. 2014, sec. 5.3.6; derived here from the strain table above):

    n = 0: U_r = U_t = 0;   n = 1: U_r + U_t = 0, U_z = 0, Phi = 0;   n >= 2: U_r = U_t = U_z = Phi = 0.

With these, every 1 / r term is a polynomial on the elements next to the axis (the Lagrange functions of nodes off
the axis vanish on it), so Gauss quadrature integrates it exactly.

Electrodes are equipotential faces, as in 3-D, uniform round the circumference: n = 0 only. Short circuit: every
electrode at 0 V; open circuit: each driven electrode's n = 0 potential one floating unknown (n >= 1: zero).
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError
from modalfe.geometry.shapes import AXES, Cylinder, Ring
from modalfe.models.constraints import Constraints
from modalfe.models.meridian_forms import (
    circumference,
    coupled_tensor,
    local_material,
    region_mass,
    region_stiffness,
    segment_dofs,
)
from modalfe.models.revolved import REVOLVED_ANGLES, Revolved
from modalfe.models.solid import PiezoUnknowns

ORDERS = (2, 3, 4)  # Lagrange quadrilateral orders offered (scikit-fem ElementQuadP)
_ON_SURFACE = 1e-9  # element sizes by which a probed point may lie outside the mesh's bounds (round-off)
# harmonics assembled where ``mesh.harmonics`` is None and none are given: the first try of the solve's rule
# (``modalfe.solve.axisymmetric.solve_axisymmetric`` raises them until the top one holds no mode of the answer)
FIRST_HARMONICS = 4


@dataclass(frozen=True)
class Region:
    """One part's rectangle r0..r1, z0..z1 [m] of the meridian plane, with its material in the local (r, theta, z)
    frame (``PiezoMaterial`` poled along its 3-axis when ``poled``)."""

    part: str
    r0: float
    r1: float
    z0: float
    z1: float
    material: object
    poled: bool


@dataclass(frozen=True)
class MeridianSection:
    """A body of revolution's meridian section: ``regions`` (one per part), the ``axis`` (3,) and the point
    ``origin`` (3,) [m] on it where z = 0, the unit ``radial`` direction (3,) that theta = 0 points along, and the
    element size [m] from the scene's mesh settings."""

    regions: tuple[Region, ...]
    axis: np.ndarray
    origin: np.ndarray
    radial: np.ndarray
    element_size: float

    def breaks(self, which: int) -> np.ndarray:
        """Sorted distinct r (``which`` = 0) or z (1) coordinates [m] of the regions' edges."""
        values = [b for reg in self.regions for b in ((reg.r0, reg.r1) if which == 0 else (reg.z0, reg.z1))]
        span = max(values) - min(values)
        return np.unique(np.round(np.array(values) / span, 12)) * span

    def region_at(self, r: float, z: float) -> int | None:
        """Index of the region containing (r, z) [m], None outside every part."""
        for i, reg in enumerate(self.regions):
            if reg.r0 <= r <= reg.r1 and reg.z0 <= z <= reg.z1:
                return i
        return None


def round_parts(scene) -> bool:
    """Whether every part of ``scene`` is a cylinder or a ring: a candidate body of revolution, which
    ``meridian_section`` accepts or refuses naming the field at fault."""
    return all(isinstance(part, (Cylinder, Ring)) for part in scene.assembly().parts)


def meridian_section(scene, size_factor: float = 1.0) -> MeridianSection:
    """The meridian section of ``scene`` when every part is a cylinder or ring on one common axis, with the element
    size of the solid's settings (``modalfe.models.mesh.element_sizes``: elements per wavelength at
    ``scene.max_frequency``, clipped to ``mesh.min_size``..``mesh.max_size``; the smallest part's) x ``size_factor``.
    SceneError naming the field where the scene is no body of revolution the model can take."""
    from modalfe.models.mesh import element_sizes

    for name in ("clamps", "edges", "guides", "springs", "masses"):
        if getattr(scene, name):
            raise SceneError(f"{name}: not supported by the axisymmetric model yet (free bodies only)")
    if scene.mirror_axes:
        raise SceneError("symmetry: mirror planes do not apply to the axisymmetric model (it solves harmonics)")
    assembly = scene.assembly()
    first = assembly.parts[0]
    for part in assembly.parts:
        if not isinstance(part, (Cylinder, Ring)):
            raise SceneError(f"parts.{part.name}.shape: the axisymmetric model takes cylinders and rings only")
        if part.axis != first.axis:
            raise SceneError(f"parts.{part.name}.axis: '{part.axis}' is not the common axis '{first.axis}'")
        k = AXES.index(part.axis)
        if not np.allclose(np.delete(part.centre, k), np.delete(first.centre, k), rtol=0, atol=1e-12):
            raise SceneError(f"parts.{part.name}.centre: off the common axis through {tuple(first.centre)}")
    for group, faces in assembly.faces.items():
        if any(f.window is not None for f in faces):
            raise SceneError(f"faces.{group}: face windows break the axial symmetry")
    k = AXES.index(first.axis)
    axis, radial = np.eye(3)[k], np.eye(3)[(k + 1) % 3]
    origin = np.array(first.centre, dtype=float)
    origin[k] = 0.0
    frame = np.array([radial, np.cross(axis, radial), axis])  # rows: local r (theta = 0), theta, z in xyz
    regions = []
    for part in assembly.parts:
        r0, r1 = (0.0, part.radius) if isinstance(part, Cylinder) else (part.inner, part.outer)
        z0 = float(part.centre[k])
        regions.append(Region(part.name, r0, r1, z0, z0 + part.height,
                              local_material(scene, part, frame), bool(part.poling)))
    size = min(element_sizes(scene).values()) * size_factor
    return MeridianSection(tuple(regions), axis, origin, radial, size)


def meridian_mesh(section: MeridianSection):
    """(MeshQuad of the parts' rectangles on a tensor grid conforming to every part edge, each interval cut into
    elements no longer than the section's element size, region index per element)."""
    from skfem import MeshQuad

    lines = []
    for which in (0, 1):
        b = section.breaks(which)
        cuts = [np.linspace(a, c, max(1, math.ceil((c - a) / section.element_size - 1e-9)) + 1)[:-1]
                for a, c in itertools.pairwise(b)]
        lines.append(np.concatenate([*cuts, b[-1:]]))
    mesh = MeshQuad.init_tensor(*lines)
    centres = mesh.p[:, mesh.t].mean(axis=1)
    region = np.array([section.region_at(r, z) for r, z in centres.T], dtype=object)
    outside = np.flatnonzero(region == None)  # noqa: E711 (object array)
    if len(outside):
        mesh = mesh.remove_elements(outside)
        region = np.delete(region, outside)
    return mesh, region.astype(int)


@dataclass(frozen=True, eq=False)
class AxisymmetricModel(PiezoUnknowns, Revolved):
    """Assembled harmonics n in ``harmonics`` of one meridian mesh, as one block-diagonal system (full DOF set, no
    constraint applied): u DOFs first (harmonic-major, then 3 per node: U_r, U_t, U_z), then the potentials
    (harmonic-major, one per scalar DOF of a poled part). ``electrodes``: face group -> indices into the phi unknowns
    of one block of the DOFs that are values on the face (equal on an equipotential face: the electrode's potential,
    carried by n = 0 only). ``clamped`` is empty (free bodies only)."""

    scene: object
    section: MeridianSection
    mesh: object
    basis: object
    harmonics: tuple[int, ...]
    K: sp.csr_matrix
    M: sp.csr_matrix
    n_u: int
    phi_nodes: np.ndarray  # scalar DOFs of the basis carrying a potential (poled parts)
    electrodes: dict[str, np.ndarray]
    electrode_higher: np.ndarray  # phi unknowns of higher-order DOFs on electrodes: zero on an equipotential face
    region: np.ndarray  # index into section.regions of each element of the mesh
    timings: dict[str, float] = field(default_factory=dict)
    clamped: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    attached_mass: None = None
    # each mode of a solve lies in one harmonic and stands for its whole degenerate pair: two modes close in frequency
    # are distinct modes, not a pair to turn to its clearest basis (``modalfe.results.labels.unique_labels``)
    pairs_apart = True

    @property
    def n_phi(self) -> int:
        return len(self.harmonics) * len(self.phi_nodes)

    def u_dof(self, h: int, nodes: np.ndarray, component: int) -> np.ndarray:
        """Full DOF indices of displacement ``component`` (0 r, 1 theta, 2 z) at scalar ``nodes`` of block ``h``."""
        return h * 3 * self.basis.N + 3 * np.asarray(nodes) + component

    def phi_dof(self, h: int, which: np.ndarray) -> np.ndarray:
        """Full DOF indices of the potentials ``which`` (indices into ``phi_nodes``) of block ``h``."""
        return self.n_u + h * len(self.phi_nodes) + np.asarray(which)

    def prescribed_potential(self, volts: float) -> np.ndarray:
        """Full DOF vector that is ``volts`` [V] on every driven electrode (its n = 0 potential) and zero elsewhere."""
        if 0 not in self.harmonics:
            raise SceneError("harmonics: a voltage on the electrodes drives n = 0 only, which is not solved")
        x = np.zeros(self.ndofs)
        h = self.harmonics.index(0)
        for group, role in self.scene.electrodes.items():
            if role == "drive" and group in self.electrodes:
                x[self.phi_dof(h, self.electrodes[group])] = volts
        return x

    def nodal_displacement(self, x: np.ndarray) -> np.ndarray:
        """Amplitudes (U_r, U_t, U_z) (3, n_vertices) [m] at the meridian mesh's vertices of the full DOF vector ``x``
        of one mode (its harmonic's block; the others carry none)."""
        vertices = self.basis.nodal_dofs[0]
        return sum(np.asarray(x)[[self.u_dof(h, vertices, c) for c in range(3)]] for h in range(len(self.harmonics)))

    def parts_stiffness(self, names) -> sp.csr_matrix:
        """(n_u, n_u) elastic stiffness K_uu of the parts named in ``names`` alone (c^E only, as the 3-D
        ``modalfe.models.solid.parts_matrices``), by the same assembly as the whole model's, every harmonic: for
        the strain energy U = u^T K u / 2 of those parts."""
        from skfem import Basis

        N = self.basis.N
        u_idx = np.arange(4 * N).reshape(N, 4)[:, :3].ravel()
        blocks = {n: sp.csr_matrix((4 * N, 4 * N)) for n in self.harmonics}
        for i, reg in enumerate(self.section.regions):
            if reg.part not in names:
                continue
            sub = Basis(self.mesh, self.basis.elem, quadrature=self.basis.quadrature,
                        elements=np.flatnonzero(self.region == i))
            D = np.zeros((9, 9))
            D[:6, :6] = reg.material.C
            for n, block in region_stiffness(sub, D, self.harmonics).items():
                blocks[n] = blocks[n] + block
        return sp.block_diag([(circumference(n) * blocks[n]).tocsr()[u_idx][:, u_idx] for n in self.harmonics],
                             format="csr")

    def vertex_field(self, x: np.ndarray, part: str) -> tuple[np.ndarray, np.ndarray]:
        """(points (3, m) [m], displacement (3, m) [m]) of the full DOF vector ``x`` at the vertices of ``part``'s
        elements, revolved at ``REVOLVED_ANGLES`` angles (those on the axis once)."""
        i = [reg.part for reg in self.section.regions].index(part)
        points, probes = self._revolved_vertices(np.unique(self.mesh.t[:, self.region == i]), axis_once=True)
        return points, (probes @ np.asarray(x)).reshape(3, -1)

    def on_face(self, group: str, points: np.ndarray, tol: float) -> np.ndarray:
        """Whether each of ``points`` (n, 3) [m] of the revolved mesh (``revolved_mesh``: its walls are chords, up to
        r (1 - cos(pi / sectors)) inside the round ones) lies on face group ``group``, within ``tol`` [m]."""
        d = np.asarray(points, dtype=float).reshape(-1, 3) - self.section.origin
        z = d @ self.section.axis
        r = np.linalg.norm(d - np.outer(z, self.section.axis), axis=1)
        chord = 1 - math.cos(math.pi / REVOLVED_ANGLES)
        regions = {reg.part: reg for reg in self.section.regions}
        on = np.zeros(len(r), dtype=bool)
        for face in self.scene.assembly().faces[group]:
            reg = regions[face.part]
            wall = face.side in ("outer", "inner")
            slack = tol + chord * (reg.r1 if wall else 0.0)
            on |= _face_segment(reg, face.side, slack)(np.array([r, z]))
        return on

    def face_integrals(self, group: str) -> list[tuple[str, np.ndarray, float]]:
        """Per face of the group ``group``: (its side, g (basis.N,) with g_i = int v_i r ds over its meridian segment,
        its area [m^2] = 2 pi int r ds), a face's area element being r dtheta ds (``_face_segment``)."""
        from skfem import FacetBasis, Functional, LinearForm

        regions = {reg.part: reg for reg in self.section.regions}
        tol = 1e-9 * self.section.element_size
        out = []
        for face in self.scene.assembly().faces[group]:
            facets = self.mesh.facets_satisfying(_face_segment(regions[face.part], face.side, tol))
            fb = FacetBasis(self.mesh, self.basis.elem, facets=facets, intorder=self.basis.elem.maxdeg + 2)
            out.append((face.side, LinearForm(lambda v, w: w.x[0] * v).assemble(fb),
                        2 * np.pi * Functional(lambda w: w.x[0]).assemble(fb)))
        return out

    def face_load(self, load) -> np.ndarray:
        """u DOF load (n_u,) of a ``force`` (total over the face group, uniform traction t = F / A) or a normal
        ``pressure`` on a face group (traction -P n, n the outward normal: the axis on a top or bottom face, the radial
        direction on a wall), as given, projected on the harmonics by its circumferential Fourier components: the
        pressure and a force's axial part are uniform round the circumference, n = 0, f_z = 2 pi t_z int v r ds
        (``face_integrals``); a force's part t_1 along the radial direction theta = 0 loads n = 1 (t_r = t_1 cos
        theta, t_theta = -t_1 sin theta: f_r = pi t_1 int v r ds, f_theta = -pi t_1 int v r ds). SceneError naming
        the load where it has a part the model does not carry (``load_refusal``) or its harmonic is not solved."""
        why = load_refusal(self.scene, load)
        if why:
            raise SceneError(why)
        value = np.asarray(load.value, dtype=float)
        parts = {0: float(value @ self.section.axis)} if load.kind == "force" else {0: 1.0}
        if load.kind == "force" and abs(value @ self.section.radial) > 0:
            parts[1] = float(value @ self.section.radial)
        for n, size in parts.items():
            if size and n not in self.harmonics:
                raise SceneError(f"harmonics: the {load.describe()} drives n = {n}, which is not solved")
        nodes = np.arange(self.basis.N)
        faces = self.face_integrals(load.group)
        area = sum(a for _, _, a in faces)
        f = np.zeros(self.n_u)
        for side, g, _ in faces:
            if load.kind == "pressure":
                component, outward = _FACE_NORMALS[side]
                f[self.u_dof(self.harmonics.index(0), nodes, component)] += 2 * np.pi * -load.value[0] * outward * g
                continue
            if parts[0]:
                f[self.u_dof(self.harmonics.index(0), nodes, 2)] += 2 * np.pi * parts[0] / area * g
            if parts.get(1):
                h = self.harmonics.index(1)
                f[self.u_dof(h, nodes, 0)] += np.pi * parts[1] / area * g
                f[self.u_dof(h, nodes, 1)] -= np.pi * parts[1] / area * g
        return f

    def face_mean(self, group: str) -> sp.csr_matrix:
        """(3, ndofs) area mean of the revolved displacement (x, y, z) [m] over the face group ``group``: over the
        circumference n = 0 keeps its axial motion (2 pi U_z), n = 1 its motion along theta = 0 (pi (U_r - U_t), the
        module docstring's cos / sin set); the other harmonics and the twin direction average to zero."""
        faces = self.face_integrals(group)
        g = sum(gi for _, gi, _ in faces)
        area = sum(a for _, _, a in faces)
        nodes = np.arange(self.basis.N)
        rows = np.zeros((3, self.ndofs))
        if 0 in self.harmonics:
            rows[:, self.u_dof(self.harmonics.index(0), nodes, 2)] = np.outer(self.section.axis, 2 * np.pi * g)
        if 1 in self.harmonics:
            h = self.harmonics.index(1)
            rows[:, self.u_dof(h, nodes, 0)] = np.outer(self.section.radial, np.pi * g)
            rows[:, self.u_dof(h, nodes, 1)] = np.outer(self.section.radial, -np.pi * g)
        return sp.csr_matrix(rows / area)

    def rigid_translations(self) -> np.ndarray:
        """(3, ndofs) unit rigid translations along the local radial (theta = 0), its twin direction and the axis:
        the axis's is n = 0's U_z = 1; the radial one n = 1's U_r = 1, U_t = -1 (u = cos theta e_r - sin theta e_t);
        the model solves one set of each n >= 1 pair, so the twin direction's row is the radial one's, which the
        pair's other member (turned by pi / 2) projects on alike. Zero where the harmonic is not solved."""
        ones = self.basis.project(lambda x: np.ones_like(x[0]))  # the constant in the scalar basis (exact)
        nodes = np.arange(self.basis.N)
        r = np.zeros((3, self.ndofs))
        if 1 in self.harmonics:
            h = self.harmonics.index(1)
            r[0, self.u_dof(h, nodes, 0)], r[0, self.u_dof(h, nodes, 1)] = ones, -ones
            r[1] = r[0]
        if 0 in self.harmonics:
            r[2, self.u_dof(self.harmonics.index(0), nodes, 2)] = ones
        return r

    def harmonic_of(self, x: np.ndarray) -> int:
        """The harmonic n whose block carries most of the full DOF vector ``x`` (one harmonic per mode)."""
        u = np.asarray(x)[: self.n_u].reshape(len(self.harmonics), -1)
        return self.harmonics[int(np.argmax(np.sum(u**2, axis=1)))]

    def constraints(self, circuit: str) -> Constraints:
        """x_full = T x_free for a ``short`` or ``open`` circuit: the axis regularity conditions of each harmonic
        (module docstring; n = 1: one unknown U_r = -U_t per axis node), every electrode's potential zero, except
        in an open circuit each driven electrode's n = 0 potential, one floating unknown (last columns).
        Potentials scaled by ``potential_scale`` as in 3-D."""
        if circuit not in ("short", "open"):
            raise SceneError(f"circuit: must be 'short' or 'open', got '{circuit}'")
        N = self.basis.N
        on_axis = np.concatenate(segment_dofs(self.basis, lambda x: np.abs(x[0]) <= 1e-12 * self.section.element_size))
        phi_on_axis = np.flatnonzero(np.isin(self.phi_nodes, on_axis))
        on_electrode = np.unique(np.concatenate([self.electrode_higher, *self.electrodes.values()]))
        scale = self.potential_scale()
        rows, cols, vals, k = [], [], [], 0

        def column(dofs, values) -> None:
            """One unknown setting ``dofs`` to ``values`` times it."""
            nonlocal k
            rows.append(np.asarray(dofs, dtype=int))
            vals.append(np.asarray(values, dtype=float))
            cols.append(np.full(len(dofs), k))
            k += 1

        def each(dofs, value: float) -> None:
            """One unknown per DOF of ``dofs``, setting it to ``value`` times it."""
            nonlocal k
            rows.append(np.asarray(dofs, dtype=int))
            vals.append(np.full(len(dofs), value))
            cols.append(k + np.arange(len(dofs)))
            k += len(dofs)

        for h, n in enumerate(self.harmonics):
            fixed = {0: (0, 1), 1: (0, 1, 2)}.get(n, (0, 1, 2))
            for c in range(3):
                nodes = np.arange(N) if c not in fixed else np.setdiff1d(np.arange(N), on_axis)
                each(self.u_dof(h, nodes, c), 1.0)
            if n == 1:  # U_r + U_t = 0 on the axis
                for node in on_axis:
                    column([self.u_dof(h, node, 0), self.u_dof(h, node, 1)], [1.0, -1.0])
        for h, n in enumerate(self.harmonics):
            fixed = np.union1d(on_electrode, self._gauged(h, circuit) if n == 0 else phi_on_axis)
            each(self.phi_dof(h, np.setdiff1d(np.arange(len(self.phi_nodes)), fixed)), scale)
        floating = []
        if circuit == "open" and 0 in self.harmonics:
            h = self.harmonics.index(0)
            for group, role in self.scene.electrodes.items():
                if role == "drive" and group in self.electrodes:
                    idx = self.phi_dof(h, self.electrodes[group])
                    column(list(idx), [scale] * len(idx))
                    floating.append(group)
        T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(self.ndofs, k))
        return Constraints(T, scale, tuple(floating))

    def _gauged(self, h: int, circuit: str) -> np.ndarray:
        """Potential nodes of harmonic ``h`` (n = 0) held at zero to fix the constant: one in each region of potential
        unknowns no grounded electrode reaches (an unelectroded part: else a singular matrix, "no regular shift"), as
        the solid's ``Model.constraints``; other harmonics have no constant (their potential varies round the axis)."""
        from scipy.sparse.csgraph import connected_components

        held = [idx for group, idx in self.electrodes.items()
                if not (circuit == "open" and self.scene.electrodes.get(group) == "drive")]
        dofs = self.phi_dof(h, np.arange(len(self.phi_nodes)))
        _, region = connected_components(self.K[dofs][:, dofs], directed=False)
        anchored = region[np.concatenate([*held, np.zeros(0, dtype=int)]).astype(int)]
        return np.unique(region, return_index=True)[1][~np.isin(np.unique(region), anchored)]

    def _cylindrical(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(r, theta, z) of ``points`` (n, 3) [m] about the axis, (r, z) within ``_ON_SURFACE`` element sizes off the
        mesh's bounds put on them (round-off); SceneError for a point in no part, as the solid (a ring's hole)."""
        self.scene.assembly().holders(np.asarray(points, dtype=float).reshape(-1, 3).T)
        d = np.asarray(points, dtype=float).reshape(-1, 3) - self.section.origin
        z = d @ self.section.axis
        e2 = np.cross(self.section.axis, self.section.radial)
        x, y = d @ self.section.radial, d @ e2
        r = np.hypot(x, y)
        (r0, z0), (r1, z1) = self.mesh.p.min(axis=1), self.mesh.p.max(axis=1)
        slack = _ON_SURFACE * self.section.element_size
        return _snapped(r, r0, r1, slack), np.arctan2(y, x), _snapped(z, z0, z1, slack)

    def displacement_probes(self, points: np.ndarray) -> sp.csr_matrix:
        """(3 n, ndofs) matrix giving (ux, uy, uz) [m] at ``points`` (n, 3) [m] of the revolved body from a full DOF
        vector, rows component-major: the harmonics summed, u = u_r e_r + u_t e_t + u_z e_z (module docstring)."""
        r, theta, z = self._cylindrical(points)
        return self._revolved(sp.csr_matrix(self.basis.probes(np.array([r, z]))), theta)

    def _revolved(self, P: sp.csr_matrix, theta: np.ndarray) -> sp.csr_matrix:
        """(3 n, ndofs) displacement probes from the meridian probes ``P`` (n, basis.N) at angles ``theta`` (n,)."""
        e1, e3 = self.section.radial, self.section.axis
        e2 = np.cross(e3, e1)
        e_r = np.outer(np.cos(theta), e1) + np.outer(np.sin(theta), e2)  # (n, 3)
        e_t = -np.outer(np.sin(theta), e1) + np.outer(np.cos(theta), e2)
        blocks = []
        for i in range(3):
            row = []
            for n in self.harmonics:
                c, s = np.cos(n * theta), (np.sin(n * theta) if n else np.ones_like(theta))  # n = 0: torsion
                parts = [sp.diags(c * e_r[:, i]) @ P, sp.diags(s * e_t[:, i]) @ P, sp.diags(c * e3[i]) @ P]
                row.append(sp.hstack(parts).tocsr()[:, _interleave(P.shape[1])])
            blocks.append(sp.hstack([*row, sp.csr_matrix((P.shape[0], self.n_phi))]))
        return sp.vstack(blocks, format="csr")

    def potential_probes(self, points: np.ndarray) -> sp.csr_matrix:
        """(n, ndofs) matrix giving the potential [V] at ``points`` (n, 3) [m] (zero outside the poled parts)."""
        r, theta, z = self._cylindrical(points)
        return self._potential_revolved(sp.csr_matrix(self.basis.probes(np.array([r, z]))), theta)

    def _potential_revolved(self, P: sp.csr_matrix, theta: np.ndarray) -> sp.csr_matrix:
        """(n, ndofs) potential probes from the meridian probes ``P`` (n, basis.N) of n points at angles ``theta``
        (n,): the harmonics' cos n theta Phi summed."""
        P = sp.csc_matrix(P)[:, self.phi_nodes]
        row = [sp.diags(np.cos(n * theta)) @ P for n in self.harmonics]
        return sp.hstack([sp.csr_matrix((P.shape[0], self.n_u)), *row], format="csr")

# a face's (displacement component (0 r, 2 z), outward normal's sign along it) in the meridian plane
_FACE_NORMALS = {"top": (2, 1.0), "bottom": (2, -1.0), "outer": (0, 1.0), "inner": (0, -1.0)}


def load_refusal(scene, load) -> str | None:
    """Why the axisymmetric model cannot take ``load`` (``modalfe.scene.loads.Load``), naming the field; None where
    it can: a voltage, a pressure on a face group, a force in the plane of the axis and the radial direction
    theta = 0 (``meridian_section``'s: the axis's next one in x, y, z). A force's part along the third direction loads
    the other member of each n = 1 pair, which the model does not solve (it solves the pair once), and a base
    acceleration needs supports, which the model has not."""
    if load.kind == "voltage" or load.kind == "pressure":
        return None
    if load.kind == "force":
        k = AXES.index(scene.assembly().parts[0].axis)
        across = (k + 2) % 3  # the axis, the radial direction theta = 0, and this one: a right-handed frame
        value = np.asarray(load.value, dtype=float)
        if abs(value[across]) <= 1e-12 * np.linalg.norm(value):
            return None
        plane = "".join(sorted((AXES[k], AXES[(k + 1) % 3])))
        return (f"drive.load: the force's {AXES[across]} part ({load.describe()}) loads the other member of the n = 1 "
                f"pairs, which the axisymmetric model solves once (the {plane} plane's); give the force in the "
                f"{plane} plane (turn the device) or --fidelity solid")
    return f"drive.load: a {load.kind} needs supports, which the axisymmetric model has not (free bodies only)"


def _face_segment(reg: Region, side: str, tol: float):
    """Predicate on facet midpoints (2, m) [m] of the meridian mesh: on the ``side`` of region ``reg`` (its top or
    bottom: a segment of constant z; its outer or inner wall: one of constant r)."""
    if side in ("top", "bottom"):
        at = reg.z1 if side == "top" else reg.z0
        return lambda x: (np.abs(x[1] - at) <= tol) & (x[0] >= reg.r0 - tol) & (x[0] <= reg.r1 + tol)
    at = reg.r1 if side == "outer" else reg.r0
    return lambda x: (np.abs(x[0] - at) <= tol) & (x[1] >= reg.z0 - tol) & (x[1] <= reg.z1 + tol)


def _snapped(v: np.ndarray, lo: float, hi: float, slack: float) -> np.ndarray:
    """``v`` with values within ``slack`` below ``lo`` (above ``hi``) set to ``lo`` (``hi``)."""
    v = np.where((v < lo) & (v >= lo - slack), lo, v)
    return np.where((v > hi) & (v <= hi + slack), hi, v)


def _interleave(N: int) -> np.ndarray:
    """Column order taking [r nodes, theta nodes, z nodes] to the model's 3 per node (r, theta, z)."""
    return (np.arange(3)[None, :] * N + np.arange(N)[:, None]).ravel()


def assemble_axisymmetric(scene, *, harmonics: tuple[int, ...] | None = None, order: int | None = None,
                          size_factor: float = 1.0) -> AxisymmetricModel:
    """Assemble the harmonics ``harmonics`` (default 0..``mesh.harmonics``, else 0..``FIRST_HARMONICS``) of
    ``scene``'s meridian section (``meridian_section``) on quadrilaterals of ``order`` (default ``mesh.order``; 2-4),
    element size x ``size_factor``: K = c_n sum_ab kron(int r d_a(v) d_b(u), B_a^T D B_b) with d = (value / r, d/dr,
    d/dz) (module docstring; ``region_stiffness``), M = c_n rho int r u v (``region_mass``) on each component."""
    from skfem import Basis, ElementQuad2, ElementQuadP

    order = scene.mesh.order if order is None else order
    if order not in ORDERS:
        raise SceneError(f"mesh.order: the axisymmetric model takes orders {ORDERS}, got {order}")
    if harmonics is None:
        harmonics = range((FIRST_HARMONICS if scene.mesh.harmonics is None else scene.mesh.harmonics) + 1)
    harmonics = tuple(sorted(int(n) for n in harmonics))
    if not harmonics or harmonics[0] < 0 or len(set(harmonics)) != len(harmonics):
        raise SceneError(f"harmonics: distinct whole numbers >= 0, got {harmonics}")
    t0 = time.perf_counter()
    section = meridian_section(scene, size_factor)
    mesh, region = meridian_mesh(section)
    element = ElementQuad2() if order == 2 else ElementQuadP(order)  # nodal 9-node quad; hierarchical above
    basis = Basis(mesh, element, intorder=2 * order + 2)
    t_mesh = time.perf_counter() - t0
    N = basis.N
    K_blocks = {n: [] for n in harmonics}
    M_terms = []
    poled_elements = []
    for i, reg in enumerate(section.regions):
        elements = np.flatnonzero(region == i)
        if reg.poled:
            poled_elements.append(elements)
        sub = Basis(mesh, element, intorder=2 * order + 2, elements=elements)
        for n, block in region_stiffness(sub, coupled_tensor(reg.material), harmonics).items():
            K_blocks[n].append(block)
        M_terms.append(reg.material.rho * region_mass(sub))
    phi_nodes = (np.unique(basis.element_dofs[:, np.concatenate(poled_elements)]) if poled_elements
                 else np.zeros(0, dtype=int))
    u_idx = np.arange(4 * N).reshape(N, 4)[:, :3].ravel()  # (U_r, U_t, U_z) of each node in 4-per-node
    phi_idx = 4 * phi_nodes + 3
    K_u, K_up, K_p, M_u = [], [], [], []
    M_scalar = sum(M_terms)
    for n in harmonics:
        c_n = circumference(n)
        K4 = (c_n * sum(K_blocks[n])).tocsr()
        K_u.append(K4[u_idx][:, u_idx])
        K_up.append(K4[u_idx][:, phi_idx])
        K_p.append(K4[phi_idx][:, phi_idx])
        M_u.append(sp.kron(c_n * M_scalar, sp.eye(3), format="csr"))
    K = sp.bmat([[sp.block_diag(K_u), sp.block_diag(K_up)], [sp.block_diag(K_up).T, sp.block_diag(K_p)]],
                format="csr")
    n_u = 3 * N * len(harmonics)
    M = sp.block_diag([sp.block_diag(M_u), sp.csr_matrix((len(harmonics) * len(phi_nodes),) * 2)], format="csr")
    electrodes, higher = {}, [np.zeros(0, dtype=int)]
    for group, (values, edges) in _electrode_dofs(scene, section, basis).items():
        electrodes[group] = np.flatnonzero(np.isin(phi_nodes, values))
        if len(electrodes[group]) == 0:
            raise SceneError(f"electrodes.{group}: the face group touches no poled part")
        higher.append(np.flatnonzero(np.isin(phi_nodes, edges)))
    timings = {"mesh": t_mesh, "assembly": time.perf_counter() - t0 - t_mesh}
    return AxisymmetricModel(scene, section, mesh, basis, harmonics, K, M, n_u, phi_nodes, electrodes,
                             np.unique(np.concatenate(higher)), region, timings)


def _electrode_dofs(scene, section: MeridianSection, basis) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Electrode face group -> (value DOFs, higher-order DOFs) of ``basis`` on its faces (``segment_dofs``; a
    part's top or bottom: a segment of constant z, its outer or inner wall: one of constant r)."""
    regions = {reg.part: reg for reg in section.regions}
    tol = 1e-9 * section.element_size
    out = {}
    for group in scene.electrodes:
        found = []
        for face in scene.assembly().faces[group]:
            found.append(segment_dofs(basis, _face_segment(regions[face.part], face.side, tol)))
        out[group] = tuple(np.unique(np.concatenate([f[i] for f in found])) for i in (0, 1))
    return out
