"""The batched assembly on isoparametric hexahedra (modalfe/models/mapped_assembly.py) against scikit-fem's own forms.

Both use scikit-fem's quadrature and the mesh's own isoparametric map, only evaluated and summed in another order, so
K, M, K_uphi and K_phiphi agree to round-off: sums of O(1e3) products of O(1) terms agree to a few ulps of the
norm, so 1e-12 (relative, Frobenius norm) catches a wrong orientation, Jacobian, transposition or material constant
(each an O(1) error) with a wide margin. The meshes are swept sections: 27-node hexahedra whose nodes a smooth in-plane
map bends (curved edges, straight along the sweep), through layers of uneven thickness.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import scipy.sparse.linalg as sla
from hypothesis import given, settings
from hypothesis import strategies as st
from skfem import Basis, BilinearForm, ElementHex1, ElementHexS2, ElementVector, MeshHex1, MeshHex2, asm

from modalfe.models import box_assembly, mapped_assembly
from modalfe.models.hex_elements import ElementHexGLL

ELEMENTS = {"Hex1": ElementHex1, "S2": ElementHexS2, "GLL2": lambda: ElementHexGLL(2), "GLL3": lambda: ElementHexGLL(3)}


def swept_mesh(nx: int, ny: int, layers: np.ndarray, bend: float, twist: float) -> MeshHex2:
    """A curved 27-node hexahedral mesh of the unit square's section swept through ``layers`` (ascending z): every
    node (corners, mid-sides, centres) moved in plane by a smooth map, so that the elements' sides are curved."""
    straight = MeshHex2.from_mesh(MeshHex1.init_tensor(np.linspace(0, 1, nx + 1), np.linspace(0, 1, ny + 1), layers))
    x, y, z = straight.doflocs
    moved = np.array([x + bend * np.sin(np.pi * y) * x * (1 - x), y + twist * np.sin(2 * np.pi * x) * y * (1 - y), z])
    return MeshHex2(moved, straight.t)


def _material(seed: int) -> SimpleNamespace:
    """A generic anisotropic material: C (6, 6) and eps (3, 3) symmetric positive definite, e (3, 6) full."""
    rng = np.random.default_rng(seed)
    A, B = rng.normal(size=(6, 6)), rng.normal(size=(3, 3))
    return SimpleNamespace(C=A @ A.T + 6 * np.eye(6), rho=1.0 + rng.random(), e=rng.normal(size=(3, 6)),
                           eps_S=B @ B.T + 3 * np.eye(3))


def _voigt(grad):
    """Engineering strain (6, ...) from the displacement gradient grad[i, j] = du_i / dx_j, Voigt order."""
    return np.array([grad[0, 0], grad[1, 1], grad[2, 2], grad[1, 2] + grad[2, 1], grad[0, 2] + grad[2, 0],
                     grad[0, 1] + grad[1, 0]])


def _skfem_matrices(mesh, scalar, intorder: int, mat):
    """K, M, K_uphi (potential on every scalar DOF) and K_phiphi by scikit-fem's forms on its own bases."""
    ub = Basis(mesh, ElementVector(scalar), intorder=intorder)
    pb = Basis(mesh, scalar, intorder=intorder)

    @BilinearForm
    def stiffness(u, v, _):
        return np.einsum("i...,ij,j...->...", _voigt(v.grad), mat.C, _voigt(u.grad))

    @BilinearForm
    def mass(u, v, _):
        return mat.rho * np.einsum("i...,i...->...", u, v)

    @BilinearForm
    def coupling(phi, v, _):  # int B(v)^T e^T grad phi
        return np.einsum("i...,ki,k...->...", _voigt(v.grad), mat.e, phi.grad)

    @BilinearForm
    def permittivity(phi, psi, _):
        return np.einsum("k...,kl,l...->...", psi.grad, mat.eps_S, phi.grad)

    return asm(stiffness, ub), asm(mass, ub), asm(coupling, pb, ub), asm(permittivity, pb), ub


def _relative(A, B) -> float:
    return float(sla.norm(A - B) / sla.norm(B))


def _check(mesh, scalar, intorder: int, mat) -> None:
    K, M, Kup, Kpp, ub = _skfem_matrices(mesh, scalar, intorder, mat)
    n = ub.N // 3
    dofs = mapped_assembly.canonical_dofs(mesh, scalar, ub.element_dofs[::3] // 3)
    elements = np.arange(mesh.nelements)
    halves = [(elements[::2], mat), (elements[1::2], mat)]  # two parts: the batches' offsets into the pattern
    mapped = mapped_assembly.Elements(mesh, scalar, intorder, dofs, halves)  # no box element: the mapped ones alone
    K_map, M_map = box_assembly.assemble_elastic(scalar, intorder, [], n, mapped=mapped)
    Kup_map, Kpp_map = box_assembly.assemble_piezo(scalar, intorder, [], np.arange(n), n, 3 * n, mapped=mapped)
    assert _relative(K_map, K) < 1e-12
    assert _relative(M_map, M) < 1e-12
    assert _relative(Kup_map, Kup) < 1e-12
    assert _relative(Kpp_map, Kpp) < 1e-12


@pytest.mark.parametrize("element", ELEMENTS)
def test_curved_hexahedra_match_scikit_fem(element):
    scalar = ELEMENTS[element]()
    mesh = swept_mesh(2, 1 if element == "GLL3" else 2, np.array([0.0, 0.15, 0.4]), bend=0.3, twist=-0.2)
    _check(mesh, scalar, 2 * max(2, getattr(scalar, "p", 2)), _material(0))


@settings(max_examples=10, deadline=None)  # ~0.5 s an example (scikit-fem's side)
@given(nx=st.integers(1, 3), ny=st.integers(1, 2),
       gaps=st.lists(st.floats(0.05, 1.0), min_size=1, max_size=2),
       bend=st.floats(-0.4, 0.4), twist=st.floats(-0.3, 0.3),
       element=st.sampled_from(["S2", "GLL2"]), seed=st.integers(0, 2**16))
def test_random_swept_sections_match_scikit_fem(nx, ny, gaps, bend, twist, element, seed):
    # bends below 1/2 keep every element's Jacobian positive (x + b sin(pi y) x (1 - x) has d/dx >= 1 - |b|)
    mesh = swept_mesh(nx, ny, np.r_[0.0, np.cumsum(gaps)], bend, twist)
    _check(mesh, ELEMENTS[element](), 4, _material(seed))  # the orientation of order-3 edge nodes: the case above


def test_applies_to_hexahedra_only():
    from skfem import MeshTet

    assert mapped_assembly.applies(swept_mesh(1, 1, np.array([0.0, 1.0]), 0.1, 0.1))
    assert not mapped_assembly.applies(MeshTet())
