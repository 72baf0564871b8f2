"""The axisymmetric model's forms on the meridian plane (``modalfe.models.axisymmetric``, whose module docstring
derives them): a material's coupled e-form tensor in the local (r, theta, z) frame and the check that it keeps the
harmonics apart, the strain maps of harmonic n, one region's stiffness blocks per harmonic, the Lagrange DOFs on a
boundary segment, and the Voigt-tensor turns the revolved fields take."""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError
from modalfe.models.box_assembly import scatter

# relative tolerance of the material checks: a tensor unchanged by a turn about the axis, no cos-sin coupling
_ISOTROPY_TOL = 1e-9
COS_ROWS = [0, 1, 2, 4, 6, 8]  # generalised strain rows carried by cos n theta (rr, tt, zz, rz, G_r, G_z)
SIN_ROWS = [3, 5, 7]  # rows carried by sin n theta (tz, rt, G_t)


def local_material(scene, part, frame: np.ndarray):
    """The part's material in the local (r, theta, z) frame: a ceramic poled along +-z (the axis) or +-radial turned
    so its 3-axis points that way, any other material seen from ``frame`` (rows: local axes in xyz); SceneError
    naming the part's poling or material where the result would couple harmonics (not symmetric about the axis)."""
    from modalfe.scene.materials import poling_frames

    mat = scene.material(part.material)
    if part.poling:
        if part.poling.endswith("radial"):
            direction = np.array([1.0, 0.0, 0.0])
        elif part.poling[1] == part.axis:
            direction = np.array([0.0, 0.0, 1.0])
        else:
            raise SceneError(f"parts.{part.name}.poling: '{part.poling}' is across the axis '{part.axis}', "
                             f"not axisymmetric (pole along the axis or radially)")
        local = mat.rotated(poling_frames(direction if part.poling[0] != "-" else -direction))
    else:
        local = mat.rotated(frame)
        if local.is_piezoelectric:  # an unpoled ceramic: its elastic tensor only, as the 3-D model
            from modalfe.scene.materials import ElasticMaterial

            local = ElasticMaterial(local.name, local.C, local.rho, local.source)
    D = coupled_tensor(local)
    couples = np.abs(D[np.ix_(COS_ROWS, SIN_ROWS)]).max() > _ISOTROPY_TOL * np.abs(D).max()
    radial = bool(part.poling) and part.poling.endswith("radial")  # cylindrically orthotropic: no turn invariance
    if couples or not (radial or _turn_invariant(local)):
        raise SceneError(f"parts.{part.name}.material: '{part.material}' is not transversely isotropic about the "
                         f"axis '{part.axis}'; the axisymmetric model needs a body of revolution")
    return local


def _turn_invariant(material) -> bool:
    """Whether ``material``'s tensors are unchanged by a turn about its local z (transverse isotropy about z)."""
    c, s = math.cos(0.3), math.sin(0.3)
    turned = coupled_tensor(material.rotated(np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])))
    D = coupled_tensor(material)
    return bool(np.abs(turned - D).max() <= _ISOTROPY_TOL * np.abs(D).max())


def coupled_tensor(material) -> np.ndarray:
    """[[c^E, e^T], [e, -eps^S]] (9, 9) on (S, G = -E) of a material (zero coupling and permittivity if passive):
    the e-form energy density S^T c^E S + 2 S^T e^T G - G^T eps^S G (Allik & Hughes 1970)."""
    D = np.zeros((9, 9))
    D[:6, :6] = material.C
    if material.is_piezoelectric:
        D[:6, 6:], D[6:, :6], D[6:, 6:] = material.e.T, material.e, -material.eps_S
    return D


def strain_maps(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(B0, Br, Bz), each (9, 4) on q = (U_r, U_t, U_z, Phi): [S; G] = B0 q / r + Br q,r + Bz q,z for harmonic
    ``n`` (the strain table of the module docstring)."""
    B0, Br, Bz = np.zeros((9, 4)), np.zeros((9, 4)), np.zeros((9, 4))
    Br[0, 0] = 1.0  # S_rr = U_r,r
    B0[1, 0], B0[1, 1] = 1.0, n  # S_tt = (U_r + n U_t) / r
    Bz[2, 2] = 1.0  # S_zz = U_z,z
    Bz[3, 1], B0[3, 2] = 1.0, -n  # S_tz = U_t,z - n U_z / r
    Bz[4, 0], Br[4, 2] = 1.0, 1.0  # S_rz = U_r,z + U_z,r
    Br[5, 1], B0[5, 0], B0[5, 1] = 1.0, -n, -1.0  # S_rt = U_t,r - (n U_r + U_t) / r
    Br[6, 3], B0[7, 3], Bz[8, 3] = 1.0, -n, 1.0  # G = (Phi,r, -n Phi / r, Phi,z)
    return B0, Br, Bz


_VOIGT_PAIRS = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))  # Voigt order xx, yy, zz, yz, xz, xy


def tensor_of(voigt: np.ndarray, shear: float) -> np.ndarray:
    """(..., 3, 3) symmetric tensors of Voigt (..., 6) whose shear entries are multiplied by ``shear`` (1/2 for an
    engineering strain, 1 for a stress)."""
    t = np.zeros((*voigt.shape[:-1], 3, 3))
    for v, (i, j) in enumerate(_VOIGT_PAIRS):
        t[..., i, j] = t[..., j, i] = voigt[..., v] * (shear if i != j else 1.0)
    return t


def voigt_of(tensor: np.ndarray, shear: float) -> np.ndarray:
    """Voigt (..., 6) of (..., 3, 3) tensors, shear entries times ``shear`` (2 for an engineering strain)."""
    return np.stack([tensor[..., i, j] * (shear if i != j else 1.0) for i, j in _VOIGT_PAIRS], axis=-1)


def turned(tensor: np.ndarray, R: np.ndarray) -> np.ndarray:
    """R T R^T of the tensors (k, m, 3, 3) with the rotations R (k, 3, 3): local (r, theta, z) to xyz."""
    return np.einsum("kia,kmab,kjb->kmij", R, tensor, R)


def circumference(n: int) -> float:
    """c_n = int cos^2 n theta dtheta over the circumference: 2 pi for n = 0 (its torsional set too), pi above."""
    return 2 * np.pi if n == 0 else np.pi


ELEMENT_CHUNK = 1000  # elements per batch of element matrices: order 4's (1000, 25 x 4, 25 x 4) take 80 MB


def region_stiffness(sub, D: np.ndarray, harmonics) -> dict[int, sp.csr_matrix]:
    """n -> int r [S; G]^T D [S; G] dr dz over the elements of the basis ``sub`` (4 unknowns per node: U_r, U_t, U_z,
    Phi), without c_n: element matrices sum_ab int r d_a(v_i) d_b(u_j) dr dz (B_a^T D B_b), d = (value / r, d/dr,
    d/dz) (module docstring), batched over the elements and scattered once per harmonic on the unknowns that
    some B_a^T D B_b couples (no stored zeros)."""
    values = np.array([f[0].value for f in sub.basis])  # (nb, nel, nq)
    grads = np.array([f[0].grad for f in sub.basis])  # (nb, 2, nel, nq)
    r = np.asarray(sub.global_coordinates())[0]  # (nel, nq) [m]
    d = np.stack((values / r, grads[:, 0], grads[:, 1]))  # (3, nb, nel, nq)
    weight = sub.dx * r
    dofs = sub.element_dofs.T  # (nel, nb)
    nel, nb = dofs.shape
    out = {}
    for n in harmonics:
        B = strain_maps(n)
        C = np.array([[B[a].T @ D @ B[b] for b in range(3)] for a in range(3)])  # (3, 3, 4, 4)
        x, y = np.nonzero(np.any(C != 0, axis=(0, 1)))  # the unknown pairs coupled
        rows, cols, data = [], [], []
        for lo in range(0, nel, ELEMENT_CHUNK):
            at = slice(lo, lo + ELEMENT_CHUNK)
            E = np.einsum("aieq,bjeq->abeij", d[:, :, at] * weight[at], d[:, :, at], optimize=True)
            data.append(np.einsum("abeij,abk->eijk", E, C[:, :, x, y], optimize=True).ravel())
            rows.append((4 * dofs[at, :, None, None] + x).repeat(nb, axis=2).ravel())
            cols.append(np.broadcast_to(4 * dofs[at, None, :, None] + y, (len(dofs[at]), nb, nb, len(x))).ravel())
        out[n] = sp.coo_matrix((np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))),
                               shape=(4 * sub.N, 4 * sub.N)).tocsr()
    return out


def region_mass(sub) -> sp.csr_matrix:
    """(N, N) int r u v dr dz over the elements of the scalar basis ``sub`` (the mass per unit density of each
    displacement component, without c_n): the element matrices batched in one product, scattered on its DOFs."""
    values = np.array([f[0].value for f in sub.basis])  # (nb, nel, nq)
    weight = sub.dx * np.asarray(sub.global_coordinates())[0]  # r dr dz at the quadrature points
    Ke = np.einsum("ieq,jeq->eij", values * weight, values, optimize=True)
    return scatter(sub.element_dofs, sub.element_dofs, Ke, sub.N, sub.N)


def segment_dofs(basis, on_segment) -> tuple[np.ndarray, np.ndarray]:
    """(DOFs that are values, higher-order DOFs) of ``basis`` on the mesh facets whose midpoints (2, m) [m] satisfy
    ``on_segment``: a field is zero there when both are; uniform when the values are equal and the higher-order ones
    zero. The 9-node ``ElementQuad2``'s edge DOFs are midpoint values; ``ElementQuadP``'s are hierarchical."""
    facets = basis.mesh.facets_satisfying(on_segment)
    if not len(facets):
        return np.zeros(0, dtype=int), np.zeros(0, dtype=int)
    dofs = basis.get_dofs(facets)
    nodal, edge = (np.unique(np.concatenate([*d.values(), np.zeros(0, dtype=int)])) for d in (dofs.nodal, dofs.facet))
    from skfem import ElementQuadP

    if isinstance(basis.elem, ElementQuadP):
        return nodal, edge
    return np.union1d(nodal, edge), np.zeros(0, dtype=int)
