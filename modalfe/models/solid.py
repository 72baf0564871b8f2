"""Assemble a scene on its mesh: stiffness, mass, piezoelectric coupling, supports and electrodes.

Linear piezoelectricity in e-form (Allik & Hughes 1970), unknowns u (displacement) and phi
(electric potential, on piezo parts only):

    [ K_uu      K_uphi   ] [u  ]   [F ]        K_uu   = int B^T c^E B
    [ K_uphi^T  -K_phiphi] [phi] = [-Q]        K_uphi = int B^T e^T grad N
                                               K_phiphi = int grad N^T eps^S grad N

The mass matrix acts on u only. Axis-aligned box elements (the structured hexahedra) are summed from
integrals on the reference cube scaled per element (``modalfe.models.box_assembly``); the other hexahedra
(curved swept ones, rotated frames, distorted elements) from reference shape functions evaluated once and per-element
Jacobians (``modalfe.models.mapped_assembly``); tetrahedra and radially poled parts in batches of elements and
quadrature points from scikit-fem bases, then scattered.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError
from modalfe.models import box_assembly, mapped_assembly
from modalfe.models.box_assembly import scatter
from modalfe.models.constraints import Constraints, bordered, shared_unknowns
from modalfe.models.part_material import material_of, radially_poled
from modalfe.models.probing import probing
from modalfe.models.symmetry import fold, solved_elements, unfold

log = logging.getLogger(__name__)

_CHUNK = 1500  # elements per batch: bounds the memory of the batched element matrices


class PiezoUnknowns:
    """Circuit handling shared by the 3-D model and the reduced ones: needs ``scene``, ``K``, ``n_u``,
    ``n_phi``, ``electrodes`` (face group -> indices into the phi unknowns), ``clamped`` and ``guided`` (groups of u
    DOFs that share one unknown: a guided face's component, ``Scene.guides``; none on the reduced models)."""

    guided: tuple[np.ndarray, ...] = ()

    @property
    def n_u_free(self) -> int:
        """Free displacement unknowns: the u DOFs neither clamped nor guided, plus one per guided group."""
        return self.n_u - len(self.clamped) - sum(len(g) for g in self.guided) + len(self.guided)

    @property
    def copies(self) -> int:
        """Copies of the solved part in the whole device: 2 per mirror plane of a symmetric (antisymmetric) model
        (its modes are the symmetric (antisymmetric) ones), so charges, capacitances and modal masses of the whole
        device are ``copies`` times the solved part's."""
        return 2 ** len(self.scene.mirror_axes)

    @property
    def ndofs(self) -> int:
        return self.n_u + self.n_phi

    def attached_share(self, shapes: np.ndarray) -> np.ndarray:
        """Share of each mode's kinetic energy carried by the scene's attached masses (``shapes`` (n, k) full DOF
        vectors): x_u^T M_attached x_u / x^T M x, zero without masses (``attached_mass``, on the u DOFs)."""
        shapes = np.asarray(shapes).reshape(self.ndofs, -1)
        if self.attached_mass is None:
            return np.zeros(shapes.shape[1])
        u = shapes[: self.n_u]
        total = np.einsum("ik,ik->k", shapes, self.M @ shapes)
        return np.einsum("ik,ik->k", u, self.attached_mass @ u) / np.where(total > 0, total, 1.0)

    def constraints(self, circuit: str) -> Constraints:
        """``_constraints(circuit)``, made once per model and circuit (17 asks an admittance, 0.02 s each)."""
        kept = self.__dict__.setdefault("_kept_constraints", {})
        return kept[circuit] if circuit in kept else kept.setdefault(circuit, self._constraints(circuit))

    def _constraints(self, circuit: str) -> Constraints:
        """The map from free unknowns to the full DOF vector for a ``short`` or ``open`` circuit.

        Short: every electrode at 0 V. Open: each driven electrode floats as one shared unknown. The free
        displacements come first (``n_u_free`` columns: single DOFs, then one column per guided group).
        Potentials are scaled so that the coupled matrix stays well conditioned. A piezo region that no fixed
        electrode touches (poled, without electrodes) has its potential fixed at one node: only its gradient
        enters, and left free the potential's constant made the matrix singular.
        """
        from scipy.sparse.csgraph import connected_components

        if circuit not in ("short", "open"):
            raise SceneError(f"circuit: must be 'short' or 'open', got '{circuit}'")
        roles = self.scene.electrodes
        free_u = np.setdiff1d(np.arange(self.n_u), np.concatenate([self.clamped, *self.guided]))
        on_electrode = np.zeros(self.n_phi, dtype=bool)
        fixed = np.zeros(self.n_phi, dtype=bool)
        for group in self.electrodes:
            on_electrode[self.electrodes[group]] = True
            if not (circuit == "open" and roles.get(group) == "drive"):
                fixed[self.electrodes[group]] = True
        count, region = connected_components(self.K[self.n_u:, self.n_u:], directed=False)
        anchored = np.zeros(count, dtype=bool)
        anchored[region[fixed]] = True
        gauged = [np.flatnonzero((region == r) & ~on_electrode)[:1] for r in np.flatnonzero(~anchored)]
        on_electrode[np.concatenate([*gauged, np.zeros(0, dtype=int)]).astype(int)] = True
        interior = np.flatnonzero(~on_electrode)
        scale = self.potential_scale()
        cols = [sp.csr_matrix((np.ones(len(free_u)), (free_u, np.arange(len(free_u)))),
                              shape=(self.ndofs, len(free_u)))]
        for group in self.guided:  # one shared unknown: the multi-point constraint u_i = u_group
            cols.append(sp.csr_matrix((np.ones(len(group)), (group, np.zeros(len(group), dtype=int))),
                                      shape=(self.ndofs, 1)))
        if len(interior):
            cols.append(sp.csr_matrix((np.full(len(interior), scale), (self.n_u + interior, np.arange(len(interior)))),
                                      shape=(self.ndofs, len(interior))))
        floating = []
        if circuit == "open":
            for group, role in roles.items():
                if role == "drive" and group in self.electrodes:
                    idx = self.n_u + self.electrodes[group]
                    cols.append(sp.csr_matrix((np.full(len(idx), scale), (idx, np.zeros(len(idx), dtype=int))),
                                              shape=(self.ndofs, 1)))
                    floating.append(group)
        T = sp.hstack(cols, format="csr")
        return Constraints(T, scale, tuple(floating))

    def prescribed_potential(self, volts: float) -> np.ndarray:
        """Full DOF vector that is ``volts`` [V] on every driven electrode and zero elsewhere: with the
        short-circuit constraints (driven electrodes eliminated) x = T x_free + x_volts."""
        x = np.zeros(self.ndofs)
        for group, role in self.scene.electrodes.items():
            if role == "drive" and group in self.electrodes:
                x[self.n_u + self.electrodes[group]] = volts
        return x

    def voltage_load(self, volts: float = 1.0) -> np.ndarray:
        """Full DOF load f = -K x_V of ``volts`` [V] on the driven electrodes, the others grounded: the right-hand
        side of the short-circuit problem whose solution x gives the full response T x + x_V, and whose
        projection phi_r . f on a mass-normalised mode is its modal force per ``volts``."""
        if "drive" not in self.scene.electrodes.values():
            raise SceneError("electrodes: the scene has no driven electrode to apply a voltage to")
        x = self.prescribed_potential(volts)
        driven = np.flatnonzero(x)  # K x from K's few driven rows (K symmetric): K @ x read all of K, 13 ms a call on
        return -(self.K[driven].T @ x[driven])  # the Cu-Be plate's quartic model, 28 calls in an admittance

    def mechanical_stiffness(self) -> sp.csr_matrix:
        """K with the piezoelectric coupling and permittivity blocks removed: the elastic stiffness (ndofs, ndofs)
        that stiffness-proportional damping and loss factors act on."""
        return sp.block_diag([self.K[: self.n_u, : self.n_u], sp.csr_matrix((self.n_phi, self.n_phi))],
                             format="csr")

    def rayleigh_damping(self, alpha: float, beta: float) -> sp.csr_matrix:
        """C = alpha M + beta K_mech [N s/m] (Rayleigh damping on the elastic unknowns)."""
        return (alpha * self.M + beta * self.mechanical_stiffness()).tocsr()

    def potential_scale(self) -> float:
        """Scale of the potential unknowns: sqrt(mean diag K_uu / mean diag K_phiphi)."""
        if self.n_phi == 0:
            return 1.0
        d = self.K.diagonal()
        return float(np.sqrt(np.mean(np.abs(d[: self.n_u])) / np.mean(np.abs(d[self.n_u :]))))


@dataclass(frozen=True, eq=False)
class Model(PiezoUnknowns):
    """Assembled matrices of one scene on one mesh (full DOF set, no constraint applied).

    K, M : (n, n) with n = n_u + n_phi; u DOFs first (skfem vector numbering), then phi
    phi_dofs : skfem scalar DOF index of each phi unknown
    electrodes : electrode face group -> indices into the phi unknowns
    clamped : u DOF indices fixed to zero (clamps, edge supports)
    guided : groups of u DOF indices, each sharing one unknown (guided faces)
    """

    scene: object
    mesh: object
    u_basis: object
    K: sp.csr_matrix
    M: sp.csr_matrix
    n_u: int
    phi_dofs: np.ndarray
    electrodes: dict[str, np.ndarray]
    clamped: np.ndarray
    timings: dict[str, float] = field(default_factory=dict)
    frame: np.ndarray | None = None
    attached_mass: sp.csr_matrix | None = None  # (n_u, n_u): the scene's masses alone, included in M
    guided: tuple[np.ndarray, ...] = ()

    @property
    def n_phi(self) -> int:
        return len(self.phi_dofs)

    def nodal_displacement(self, x: np.ndarray) -> np.ndarray:
        """Displacement (3, n_vertices) at the mesh vertices from a full DOF vector."""
        return np.asarray(x[: self.n_u])[self.u_basis.nodal_dofs]

    def vertex_field(self, x: np.ndarray, part: str) -> tuple[np.ndarray, np.ndarray]:
        """(points (3, m) [m], displacement (3, m) [m]) of the full DOF vector ``x`` at the mesh vertices of
        ``part``'s elements."""
        mesh = self.mesh.mesh
        vertices = np.unique(mesh.t[:, self.mesh.parts[part]])
        return mesh.p[:, vertices], self.nodal_displacement(x)[:, vertices]

    def displacement_probes(self, points: np.ndarray) -> sp.csr_matrix:
        """(3 n, ndofs) matrix giving (ux, uy, uz) [m] at ``points`` (n, 3) [m] of the whole device from a full
        DOF vector, rows component-major (all ux, then uy, then uz); a symmetric model reads mirror images."""
        p, flip = fold(self.scene, np.asarray(points, dtype=float).reshape(-1, 3).T)
        P = sp.diags(flip.ravel()) @ self._displacement_probing.probes(self._inside(p))
        return sp.hstack([P, sp.csr_matrix((P.shape[0], self.n_phi))], format="csr")

    def element_probes(self, cells: np.ndarray, corners: np.ndarray, weights: np.ndarray) -> sp.csr_matrix:
        """``displacement_probes`` at points given in elements of the whole device: ``whole_device_mesh``'s cells
        ``cells`` (n,), each point the combination ``weights`` (n, m) of the cell's vertices at positions ``corners``
        (n, m) of its VTK list, taken in reference coordinates: read in that element by its own map (a curved
        element's point on its curved face, where the vertices' chord may cross a ring's hole), no point search."""
        elements, vertex, sign = solved_elements(self, cells, corners)
        reference = self.u_basis.mesh.refdom.p  # (3, vertices of the reference cell)
        local = np.einsum("nm,dnm->dn", weights, reference[:, vertex])
        P = sp.diags(sign.ravel()) @ self._displacement_probing.at(elements, local)
        return sp.hstack([P, sp.csr_matrix((P.shape[0], self.n_phi))], format="csr")

    def potential_probes(self, points: np.ndarray) -> sp.csr_matrix:
        """(n, ndofs) matrix giving the electric potential [V] at ``points`` (n, 3) [m] from a full DOF vector
        (zero outside the poled parts, which carry no potential unknowns)."""
        p, _ = fold(self.scene, np.asarray(points, dtype=float).reshape(-1, 3).T)
        P = self._potential_probing.probes(self._inside(p)).tocsc()[:, self.phi_dofs]
        return sp.hstack([sp.csr_matrix((P.shape[0], self.n_u)), P], format="csr")

    @cached_property
    def _displacement_probing(self):
        """The vector basis that locates probe points (``modalfe.models.probing.probing``), built once per model: a
        whole-mesh basis."""
        return probing(self.u_basis)

    @cached_property
    def _potential_probing(self):
        """The scalar basis for potential probes, built once per model (one quadrature point: probes need the
        element and its DOF numbering only)."""
        from skfem import Basis

        return probing(Basis(self.u_basis.mesh, element_for(self.scene.mesh), intorder=1))

    def _inside(self, p: np.ndarray) -> np.ndarray:
        """Points (3, n) moved by 1e-9 of the device's size toward the centre of a part that holds them, so that
        points on faces, edges and corners (a foot's sole) fall inside an element; SceneError for a point in no part
        (``Assembly.holders``)."""
        assembly = self.scene.assembly()
        holder = assembly.holders(p).argmax(axis=1)
        centres = np.array([0.5 * (np.asarray(q.lo, dtype=float) + np.asarray(q.hi, dtype=float))
                            for q in assembly.parts])
        return p + assembly.tolerance * (centres[holder].T - p)

    def label_field(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Coordinates (3, n) and displacements (3, n) of the whole device at the vertices of its main parts
        (those at least 1 % as stiff as the stiffest, so rubber mounts and honeycomb cores do not vote), in the
        device's own axes: what ``modalfe.results.labels.label`` reads a mode's shape from."""
        scene, dm = self.scene, self.mesh
        assembly = scene.assembly()
        stiffness = {p.name: scene.material(p.material).C[0, 0] for p in assembly.parts}
        top = max(stiffness.values())
        keep = [p.name for p in assembly.parts if stiffness[p.name] >= 0.01 * top]
        vertices = np.unique(dm.mesh.t[:, np.concatenate([dm.parts[n] for n in keep])])
        points, u = dm.mesh.p[:, vertices], self.nodal_displacement(x)[:, vertices]
        if self.frame is not None:  # a rotated device is labelled in its own axes
            points, u = self.frame.T @ points, self.frame.T @ u
        return unfold(scene, points, u)

    def shifted_matrix(self, frequency: float, *, scale: float | None = None) -> sp.csr_matrix:
        """K - omega^2 M on the short-circuit free unknowns, the potentials scaled by ``scale``
        (default: ``potential_scale()``; 1.0 leaves them in volts), for conditioning checks."""
        A = self.constraints("short").project(self.K - (2 * np.pi * frequency) ** 2 * self.M)
        n_u_free = self.n_u_free
        ratio = (self.potential_scale() if scale is None else scale) / self.potential_scale()
        rescale = sp.diags(np.r_[np.ones(n_u_free), np.full(A.shape[0] - n_u_free, ratio)])
        return (rescale @ A @ rescale).tocsr()


def element_for(settings):
    """The scikit-fem scalar element of ``settings`` (a ``MeshSettings``: kind, order, family): hexahedra are
    serendipity (Hex1, the 20-node S2, the 32-node S3 of ``modalfe.models.hex_elements``) or Lagrange on
    Gauss-Lobatto nodes (``ElementHexGLL``), tetrahedra P1 or P2."""
    from skfem import ElementHex1, ElementHexS2, ElementTetP1, ElementTetP2

    from modalfe.models.hex_elements import ElementHexGLL, ElementHexS3

    kind, order = settings.element, settings.order
    if kind == "tet":
        return {1: ElementTetP1, 2: ElementTetP2}[order]()
    if order == 1:
        return ElementHex1()
    if settings.serendipity:
        return ElementHexS2() if order == 2 else ElementHexS3()
    return ElementHexGLL(order)


def assemble(scene, device_mesh, *, frame: np.ndarray | None = None) -> Model:
    """Assemble K and M of ``scene`` on ``device_mesh`` (a ``modalfe.models.mesh.DeviceMesh``).

    ``frame`` (3, 3) rotates the whole device, mesh and material tensors alike (a check of
    frame invariance); face springs are axis-aligned and refuse a frame.
    """
    from skfem import Basis, ElementVector

    start = time.perf_counter()
    assembly = scene.assembly()
    mesh = device_mesh.mesh
    if frame is not None:
        if scene.springs:
            raise SceneError("frame: face springs are axis-aligned and cannot be rotated")
        held = [*scene.clamps.values(), *scene.symmetry_clamps.values(), *scene.guides.values(),
                *(edge["fix"] for edge in scene.edges.values())]
        if any(len(set(c)) < 3 for c in held):
            raise SceneError("frame: supports holding some components only (clamps, edges, guides, symmetry planes) "
                             "are axis-aligned and cannot be rotated")
        frame = np.asarray(frame, dtype=float)
        mesh = type(mesh)(frame @ mesh.p, mesh.t)
        device_mesh = replace(device_mesh, mesh=mesh)
    scalar = element_for(scene.mesh)
    intorder = 2 * scene.mesh.order
    u_basis = Basis(mesh, ElementVector(scalar), intorder=1)  # DOF numbering and probes only: one point
    chunk_size = _chunk_size(u_basis, intorder)
    n_u = u_basis.N
    scalar_dofs = u_basis.element_dofs[::3] // 3  # scikit-fem numbers vector DOFs 3 s + c
    Kuu, Muu, piezo_parts = _elastic(scene, device_mesh, u_basis, assembly.parts, frame)
    if scene.springs:
        Kuu = Kuu + _face_springs(scene, device_mesh, u_basis, scalar, intorder)
    attached = _face_masses(scene, device_mesh, u_basis, scalar, intorder) if scene.masses else None
    if attached is not None:
        Muu = Muu + attached
    phi_dofs, Kup, Kpp = _piezo_blocks(mesh, scalar, intorder, scalar_dofs, piezo_parts, n_u, chunk_size)
    n_phi = len(phi_dofs)
    if n_phi:  # canonical blocks give a canonical K, whose projection then needs no sort
        # (``modalfe.solve.linalg.upper_triangle``: 0.47 s on the Cu-Be plate)
        Kuu.sum_duplicates()
        Kup = Kup.tocsr()
        Kup.sum_duplicates()
        bottom = sp.hstack([Kup.T.tocsr(), -Kpp], format="csr")
        bottom.sum_duplicates()
        K = bordered(Kuu, Kup, bottom)  # Kuu's entries copied once, explicit zeros kept (B's pattern lies in A's)
        M = bordered(Muu, sp.csr_matrix((n_u, n_phi)), sp.csr_matrix((n_phi, n_u + n_phi)))
    else:
        K, M = Kuu, Muu
    electrodes = _electrode_dofs(scene, device_mesh, mesh, scalar, phi_dofs)
    clamped, guided = _supported_dofs(scene, device_mesh, u_basis)
    return Model(scene, device_mesh, u_basis, K, M, n_u, phi_dofs, electrodes, clamped,
                 {"assembly": time.perf_counter() - start}, frame, attached, guided)


def _chunk_size(u_basis, intorder: int) -> int:
    """Elements per batch: batches hold (3 nloc) x nq basis values per element; keep the serendipity's 60 x 27
    memory per batch."""
    from skfem.quadrature import get_quadrature

    return max(1, _CHUNK * 60 * 27 // (u_basis.Nbfun * len(get_quadrature(u_basis.mesh.refdom, intorder)[1])))


def _elastic(scene, device_mesh, u_basis, parts, frame) -> tuple[sp.csr_matrix, sp.csr_matrix, list]:
    """(K_uu, M_uu, piezo parts) over ``parts`` of the scene: axis-aligned box elements by
    ``box_assembly`` (closed form), the others on hexahedra by ``mapped_assembly`` (but radially poled parts) and else
    by quadrature on scikit-fem bases; the piezo parts as (material, tensors, boxes, elements by quadrature, elements
    by ``mapped_assembly``) for ``_piezo_blocks``."""
    from skfem import Basis, ElementVector

    mesh = u_basis.mesh
    scalar = element_for(scene.mesh)
    intorder = 2 * scene.mesh.order
    chunk_size = _chunk_size(u_basis, intorder)
    n_u = u_basis.N
    scalar_dofs = u_basis.element_dofs[::3] // 3
    K_blocks, M_blocks = [], []
    boxes, mapped, piezo_parts = [], [], []
    for part in parts:
        mat, tensors = material_of(scene, part, frame)
        found, rest = box_assembly.find_boxes(mesh, scalar, scalar_dofs, device_mesh.parts[part.name])
        boxes.append((found, mat))
        by_map = rest if mapped_assembly.applies(mesh) and not radially_poled(part) else rest[:0]
        if part.poling:
            piezo_parts.append((mat, tensors, found, rest[len(by_map):], by_map))
        mapped.append((by_map, mat))
        for chunk in _chunks(rest[len(by_map):], chunk_size):
            b = Basis(mesh, ElementVector(scalar), intorder=intorder, elements=chunk)
            Bv, V = _strain_and_value(b)
            C = tensors(b)[0]
            K_blocks.append(scatter(b.element_dofs, b.element_dofs, _contract(Bv, C, Bv, b.dx), n_u, n_u))
            M_blocks.append(scatter(b.element_dofs, b.element_dofs, mat.rho * _contract(V, None, V, b.dx), n_u, n_u))
    Kuu, Muu = box_assembly.assemble_elastic(scalar, intorder, boxes, n_u // 3,
                                             mapped=_mapped(mesh, scalar, intorder, scalar_dofs, mapped))
    return sum(K_blocks, Kuu).tocsr(), sum(M_blocks, Muu).tocsr(), piezo_parts


def _mapped(mesh, scalar, intorder: int, scalar_dofs: np.ndarray, parts: list) -> mapped_assembly.Elements | None:
    """The ``parts``' elements ((elements, material) pairs) left to ``mapped_assembly``, None if there are none."""
    if not any(len(elements) for elements, _ in parts):
        return None
    dofs = mapped_assembly.canonical_dofs(mesh, scalar, scalar_dofs)
    return mapped_assembly.Elements(mesh, scalar, intorder, dofs, parts)


def parts_matrices(model, names: set[str] | frozenset[str]) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """(n_u, n_u) elastic stiffness K_uu and mass M_uu of ``model``'s parts named in ``names`` alone (its frame and
    mesh), by the same assembly as the whole model's; for the strain and kinetic energies of those parts."""
    parts = [part for part in model.scene.assembly().parts if part.name in names]
    return _elastic(model.scene, model.mesh, model.u_basis, parts, model.frame)[:2]


def _supported_dofs(scene, device_mesh, u_basis) -> tuple[np.ndarray, tuple[np.ndarray, ...]]:
    """(clamped, guided) u DOFs of the scene's supports: clamps fix the components they name on their faces, edge
    supports on the nodes two face groups share (the line's vertices and its elements' edge nodes), both at zero;
    guides make each component they name one unknown over the face (``guided``: groups of DOFs, merged where guided
    faces share nodes; a group that holds a clamped DOF is clamped whole, its uniform value being zero)."""
    fixed = [np.array([], dtype=int)]
    for group, components in {**scene.clamps, **scene.symmetry_clamps}.items():
        fixed += _component_dofs(u_basis, device_mesh.faces[group], components)
    for name, edge in scene.edges.items():
        a, b = edge["faces"]
        line = [np.intersect1d(x, y) for x, y in zip(_component_dofs(u_basis, device_mesh.faces[a], edge["fix"]),
                                                      _component_dofs(u_basis, device_mesh.faces[b], edge["fix"]))]
        if len(line[0]) < 2:
            raise SceneError(f"edges.{name}.faces: '{a}' and '{b}' share {len(line[0])} mesh node(s): they do not "
                             f"meet along a line")
        fixed += line
    clamped = np.unique(np.concatenate(fixed)).astype(int)
    guided = [dofs for group, components in scene.guides.items()
              for dofs in _component_dofs(u_basis, device_mesh.faces[group], components)]
    return shared_unknowns(u_basis.N, guided, clamped)


def _component_dofs(u_basis, facets: np.ndarray, components: str) -> list[np.ndarray]:
    """u DOFs on ``facets``, one array per component letter of ``components`` (sorted)."""
    dofs = u_basis.get_dofs(facets)
    return [np.sort(dofs.all(f"u^{'xyz'.index(c) + 1}")) for c in components]


def _chunks(elements: np.ndarray, size: int) -> list[np.ndarray]:
    """``elements`` in batches of at most ``size``."""
    return [elements[i:i + size] for i in range(0, len(elements), size)]


def _strain_and_value(b):
    """Voigt strain (nloc, 6, nel, nq) and value (nloc, 3, nel, nq) of each vector basis function."""
    G = np.array([f[0].grad for f in b.basis])
    V = np.array([np.asarray(f[0]) for f in b.basis])
    Bv = np.stack([G[:, 0, 0], G[:, 1, 1], G[:, 2, 2], G[:, 1, 2] + G[:, 2, 1],
                   G[:, 0, 2] + G[:, 2, 0], G[:, 0, 1] + G[:, 1, 0]], axis=1)
    return Bv, V


def _contract(A, C, B, dx):
    """Element matrices sum_q A_i^T C B_j dx -> (nel, nA, nB); A (nA, a, nel, nq), B (nB, b, nel, nq), C (a, b) or
    one per point (nel, nq, a, b)."""
    nA, _, nel, _ = A.shape
    nB = B.shape[0]
    if C is None:
        CB = B
    elif C.ndim == 4:
        CB = np.einsum("eqab,jbeq->jaeq", C, B, optimize=True)
    else:
        CB = np.einsum("ab,jbeq->jaeq", C, B, optimize=True)
    left = (A * dx).transpose(2, 0, 1, 3).reshape(nel, nA, -1)
    right = CB.transpose(2, 0, 1, 3).reshape(nel, nB, -1)
    return left @ right.transpose(0, 2, 1)


def _piezo_blocks(mesh, scalar, intorder, scalar_dofs, piezo_parts, n_u, chunk_size):
    """K_uphi and K_phiphi over the piezo parts ((material, tensors, boxes, elements by quadrature, elements by
    ``mapped_assembly``) each, see ``material_of`` and ``_elastic``; a radially poled part has no box elements), on
    the potential unknowns they use."""
    from skfem import Basis, ElementVector

    if not piezo_parts:
        return np.array([], dtype=int), None, None
    used = np.unique(np.concatenate([found.dofs.ravel() for _, _, found, _, _ in piezo_parts]
                                    + [scalar_dofs[:, np.r_[rest, by_map]].ravel()
                                       for _, _, _, rest, by_map in piezo_parts]))
    index = np.full(n_u // 3, -1)
    index[used] = np.arange(len(used))
    n_phi = len(used)
    mapped = _mapped(mesh, scalar, intorder, scalar_dofs, [(by_map, mat) for mat, _, _, _, by_map in piezo_parts])
    Kup, Kpp = box_assembly.assemble_piezo(scalar, intorder, [(found, mat) for mat, _, found, _, _ in piezo_parts],
                                           index, n_phi, n_u, mapped=mapped)
    for _, tensors, _, rest, _ in piezo_parts:
        for chunk in _chunks(rest, chunk_size):
            ub = Basis(mesh, ElementVector(scalar), intorder=intorder, elements=chunk)
            pb = Basis(mesh, scalar, intorder=intorder, elements=chunk)
            Bv, _ = _strain_and_value(ub)
            Gp = np.array([f[0].grad for f in pb.basis])  # (nloc, 3, nel, nq)
            phi_rows = index[pb.element_dofs]
            _, e, eps = tensors(ub)
            Kup = Kup + scatter(ub.element_dofs, phi_rows, _contract(Bv, np.swapaxes(e, -1, -2), Gp, ub.dx),
                                 n_u, n_phi)
            Kpp = Kpp + scatter(phi_rows, phi_rows, _contract(Gp, eps, Gp, pb.dx), n_phi, n_phi)
    return used, Kup.tocsr(), Kpp.tocsr()


def _electrode_dofs(scene, device_mesh, mesh, scalar, phi_dofs) -> dict[str, np.ndarray]:
    """Indices into the phi unknowns of every electrode named by the scene."""
    from skfem import Basis

    if not scene.electrodes:
        return {}
    if len(phi_dofs) == 0:
        raise SceneError("electrodes: the scene names electrodes but has no poled piezo part")
    index = {d: i for i, d in enumerate(phi_dofs)}
    probe = Basis(mesh, scalar, intorder=1, elements=np.arange(1))
    out = {}
    for group in scene.electrodes:
        if group not in device_mesh.faces:
            continue  # the mirror image of a face kept by the symmetric model
        dofs = probe.get_dofs(device_mesh.faces[group]).all()
        idx = np.array([index[d] for d in dofs if d in index], dtype=int)
        if len(idx) == 0:
            raise SceneError(f"electrodes.{group}: the face group does not touch a piezo part")
        out[group] = idx
    return out


def _face_operator(device_mesh, group, scalar, intorder, diag):
    """int_face diag(d) u . v ds over one face group, with ``diag`` per unit area: the scalar face mass
    int_face u v ds once, then kron(., diag(d)) onto the interleaved displacement unknowns (3 s + c, as
    ``box_assembly`` numbers them), instead of the vector form's 9x as many basis-function pairs."""
    from skfem import BilinearForm

    from modalfe.models.facets import facet_basis

    fb = facet_basis(device_mesh.mesh, scalar, device_mesh.faces[group], intorder=intorder)

    @BilinearForm
    def face_mass(u, v, _):
        return u * v

    return sp.kron(face_mass.assemble(fb), sp.diags(np.asarray(diag, dtype=float)), format="csr")


def face_area(device_mesh, group: str) -> float:
    """Area [m^2] of a face group."""
    from skfem import ElementHex1, ElementTetP1, Functional

    from modalfe.models.facets import facet_basis

    fb = facet_basis(device_mesh.mesh, ElementHex1() if device_mesh.element == "hex" else ElementTetP1(),
                     device_mesh.faces[group])
    return float(Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(fb))


def _face_springs(scene, device_mesh, u_basis, scalar, intorder):
    """Springs to ground: the scene gives totals for the whole face (whole device), spread
    uniformly per unit area, so a symmetric half model carries its share."""
    out = sp.csr_matrix((u_basis.N, u_basis.N))
    full = scene.full_assembly()
    for group, k in scene.springs.items():
        if group not in device_mesh.faces:
            continue  # the mirror image of a face kept by the symmetric model
        out = out + _face_operator(device_mesh, group, scalar, intorder, np.asarray(k) / full.face_area(group))
    return out


def _face_masses(scene, device_mesh, u_basis, scalar, intorder):
    """Attached masses (translational inertia), spread uniformly over the face like the springs."""
    out = sp.csr_matrix((u_basis.N, u_basis.N))
    full = scene.full_assembly()
    for group, m in scene.masses.items():
        if group not in device_mesh.faces:
            continue  # the mirror image of a face kept by the symmetric model
        out = out + _face_operator(device_mesh, group, scalar, intorder, np.full(3, m / full.face_area(group)))
    return out
