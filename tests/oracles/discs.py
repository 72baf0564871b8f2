"""Closed-form references for discs and rings: Kirchhoff bending modes of clamped and free circular plates, the
radial (planar) modes of a free disc, and the in-plane modes of a thin circular ring.

Sources: A. W. Leissa, "Vibration of Plates", NASA SP-160 (1969), ch. 2 (circular plates: eqs. 2.4-2.16, the
clamped and free frequency parameters lambda^2 = omega a^2 sqrt(rho h / D) of Tables 2.1 and 2.5); R. Holland and
E. P. EerNisse, "Variational evaluation of admittances of multielectroded three-dimensional piezoelectric
structures" / M. Onoe, "Contour vibrations of isotropic circular plates", J. Acoust. Soc. Am. 28 (1956) 1158
(the free disc's radial modes: x J0(x) = (1 - nu) J1(x), x = k a); R. Hoppe, "Vibrationen eines Ringes in seiner
Ebene", J. reine angew. Math. 73 (1871) 158, as given by Blevins, "Formulas for Natural Frequency and Mode Shape"
(1979), Table 9-1 (thin ring: in-plane inextensional modes and the breathing mode); piezoelectric discs and rings:
IEEE Std 176-1987 (planar mode of a thin disc, Meitzler et al. 1961) and Berlincourt, Curran & Jaffe 1964 (thin
radially poled ring), with the pickers of those modes from a solve by shape.

Disc modes are ``(n, s)``: n nodal diameters, s nodal circles (the boundary not counted), as in Leissa. Radii are
dimensionless (rho = r / a) in the shape functions; frequencies in Hz.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import scipy.optimize as so
import scipy.special as ss
from scipy.special import ive, jv, jvp

from modalfe.results.modes import Modes
from modalfe.scene.materials import material
from tests.oracles.analytic import _bracketed_roots
from tests.oracles.cases import EXAMPLES

# the free 20 x 1 mm PZT-5A disc's scene file, by its absolute path (the tests and studies run from any folder)
PZT5A_DISC = str(EXAMPLES / "pzt5a_disc.toml")
# the 3-D solid's 20 x 1 mm PZT-5A disc (examples/pzt5a_disc.toml; docs/studies.md "Curved parts", "Mesh error
# of the disc"): R1 short circuit 99,365 Hz stated to 0.001 % (P2, 17,940 DOFs; two layers 99,364.8 Hz), open 117,317 Hz
SOLID_FR, SOLID_FR_ERROR, SOLID_FA = 99_365.0, 1e-5, 117_317.0

_GRID = np.arange(0.5, 40.0, 0.01)  # lambda = k a scanned for sign changes: roots are > 0.5 apart


def _iv_scaled(n: int, x: float) -> tuple[float, float]:
    """(I_n(x), I_n'(x)) times exp(-x): the modified Bessel function without its overflow."""
    return float(ive(n, x)), float(0.5 * (ive(n - 1, x) + ive(n + 1, x)))


def clamped_disc_roots(n: int, count: int) -> np.ndarray:
    """The first ``count`` roots lambda = k a (s = 0, 1, ... nodal circles) of the clamped circular plate with
    ``n`` nodal diameters: J_n(l) I_n'(l) - I_n(l) J_n'(l) = 0 (Leissa 1969, eq. 2.8; Table 2.1 gives l^2)."""

    def f(x: float) -> float:
        i, di = _iv_scaled(n, x)
        return float(jv(n, x) * di - i * jvp(n, x))

    return np.array(_bracketed_roots(f, _GRID)[:count])


def _free_edge(n: int, x: float, nu: float) -> tuple[float, float, float, float]:
    """(M_J, M_I, V_J, V_I): edge moment and Kirchhoff shear of w = J_n(k r) cos(n theta) and of I_n (scaled by
    exp(-x)) at r = a, x = k a, up to a common factor (Leissa 1969, eqs. 2.12-2.13)."""
    j, dj = float(jv(n, x)), float(jvp(n, x))
    i, di = _iv_scaled(n, x)
    m_j = -(x * x * j) - (1 - nu) * (x * dj - n * n * j)
    m_i = x * x * i - (1 - nu) * (x * di - n * n * i)
    v_j = -(x**3 * dj) - (1 - nu) * n * n * (x * dj - j)
    v_i = x**3 * di - (1 - nu) * n * n * (x * di - i)
    return m_j, m_i, v_j, v_i


def free_disc_roots(n: int, count: int, nu: float) -> np.ndarray:
    """The first ``count`` non-zero roots lambda = k a of the free circular plate with ``n`` nodal diameters and
    Poisson ratio ``nu``: zero edge moment and Kirchhoff shear, M_J V_I - M_I V_J = 0 (Leissa 1969, eq. 2.14;
    Table 2.5 for nu = 0.33). For n = 0 and 1 the first root has one nodal circle (s = 0 is a rigid motion)."""

    def f(x: float) -> float:
        m_j, m_i, v_j, v_i = _free_edge(n, x, nu)
        return m_j * v_i - m_i * v_j

    return np.array(_bracketed_roots(f, _GRID)[:count])


def clamped_disc_shape(n: int, lam: float) -> Callable[[np.ndarray], np.ndarray]:
    """Radial profile W(rho) of the clamped plate's mode: J_n(l rho) - J_n(l) / I_n(l) I_n(l rho)
    (Leissa 1969, eq. 2.7), rho = r / a in [0, 1]; w = W(rho) cos(n theta)."""
    ratio = float(jv(n, lam) / ive(n, lam))
    return lambda rho: jv(n, lam * rho) - ratio * ive(n, lam * rho) * np.exp(lam * rho - lam)


def free_disc_shape(n: int, lam: float, nu: float) -> Callable[[np.ndarray], np.ndarray]:
    """Radial profile W(rho) of the free plate's mode: J_n(l rho) + C I_n(l rho) with C from zero edge moment
    (Leissa 1969, eq. 2.12), rho = r / a in [0, 1]; w = W(rho) cos(n theta)."""
    m_j, m_i, _, _ = _free_edge(n, lam, nu)
    c = -m_j / m_i  # in units of the scaled I_n
    return lambda rho: jv(n, lam * rho) + c * ive(n, lam * rho) * np.exp(lam * rho - lam)


def kirchhoff_disc_frequency(lam: float, *, radius: float, h: float, E: float, nu: float, rho: float) -> float:
    """f = l^2 / (2 pi a^2) sqrt(D / (rho h)) [Hz], D = E h^3 / (12 (1 - nu^2)) (Leissa 1969, eq. 2.6)."""
    D = E * h**3 / (12 * (1 - nu**2))
    return lam**2 / (2 * math.pi * radius**2) * math.sqrt(D / (rho * h))


def disc_radial_roots(nu: float, count: int) -> np.ndarray:
    """The first ``count`` roots x = k a of x J0(x) - (1 - nu) J1(x) = 0: the free thin disc's axisymmetric radial
    (planar) modes u_r = J1(k r) (Onoe 1956; x = 2.049 for nu = 0.3)."""
    return np.array(_bracketed_roots(lambda x: float(x * jv(0, x) - (1 - nu) * jv(1, x)), _GRID)[:count])


def ring_inplane_frequency(n: int, *, radius: float, E: float, rho: float, area: float, inertia: float) -> float:
    """f_n = 1 / (2 pi) sqrt(E I / (rho A R^4)) n (n^2 - 1) / sqrt(n^2 + 1) [Hz], n >= 2: in-plane inextensional
    bending of a thin circular ring of mean radius R (Hoppe 1871; Blevins 1979, Table 9-1); I is the second
    moment of the cross-section about the axis normal to the ring's plane."""
    if n < 2:
        raise ValueError(f"n must be >= 2 (n = 0, 1 are the breathing mode and a rigid motion), got {n}")
    return n * (n * n - 1) / math.sqrt(n * n + 1) * math.sqrt(E * inertia / (rho * area * radius**4)) / (2 * math.pi)


def compliances(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """s^E, d, eps^T, rho of a library material from its e-form constants: s = c^-1, d = e s, eps^T = eps^S + d e^T."""
    mat = material(name)
    s = np.linalg.inv(mat.C)
    d = mat.e @ s
    return s, d, mat.eps_S + d @ mat.e.T, mat.rho


def thin_disc(name: str, radius: float) -> tuple[float, float]:
    """(fr, fa) [Hz] of a thin disc's planar mode (IEEE Std 176-1987): eta J0(eta) = (1 - sigma) J1(eta),
    sigma = -s12/s11, fr = eta / (2 pi a) / sqrt(rho s11 (1 - sigma^2)); fa from k_p^2 / (1 - k_p^2) =
    ((1 - sigma) J1(eta_a) - eta_a J0(eta_a)) / ((1 + sigma) J1(eta_a)), k_p^2 = 2 d31^2 / (eps33^T (s11 + s12))."""
    s, d, eps_t, rho = compliances(name)
    sigma = -s[0, 1] / s[0, 0]

    def planar(x: float) -> float:
        return (1 - sigma) * ss.j1(x) - x * ss.j0(x)

    eta = so.brentq(planar, 1.5, 2.5)
    kp2 = 2 * d[2, 0] ** 2 / (eps_t[2, 2] * (s[0, 0] + s[0, 1]))
    eta_a = so.brentq(lambda x: planar(x) / ((1 + sigma) * ss.j1(x)) - kp2 / (1 - kp2), eta * 1.0001, 3.5)
    fr = eta / (2 * np.pi * radius) / np.sqrt(rho * s[0, 0] * (1 - sigma**2))
    return fr, fr * eta_a / eta


def thin_ring_breathing(name: str, radius: float) -> float:
    """Breathing mode [Hz] of a thin ring poled along its radius: fr = sqrt(1 / (rho s11^E)) / (2 pi R)."""
    s, _, _, rho = compliances(name)
    return float(np.sqrt(1 / (rho * s[0, 0])) / (2 * np.pi * radius))


def _rim(radius: float, z: float, count: int) -> tuple[np.ndarray, np.ndarray]:
    th = np.linspace(0, 2 * np.pi, count, endpoint=False)
    return th, np.stack([radius * np.cos(th), radius * np.sin(th), np.full_like(th, z)], axis=1)


def axisymmetric(modes: Modes, radius: float, z: float):
    """The mode whose rim at ``radius``, height ``z`` moves most uniformly outward (planar / breathing mode)."""
    th, pts = _rim(radius, z, 24)

    def share(m) -> float:
        u = m.displacement(pts).T
        return abs(np.mean(u[0] * np.cos(th) + u[1] * np.sin(th))) / np.sqrt(np.mean(np.sum(u**2, axis=0)))

    best = max(modes.modes, key=share)
    if share(best) < 0.99:
        raise RuntimeError(f"no axisymmetric mode among {modes.frequencies}")
    return best


def in_plane(modes: Modes, n: int, radius: float, z: float, *, every: bool = False):
    """The lower of the pair of in-plane flexural modes with n waves round the ring (u_z < 10 % of u_r, n the
    strongest Fourier harmonic of u_r on the mid-circle), or with ``every`` all such modes."""
    th, pts = _rim(radius, z, 48)
    found = []
    for m in modes.modes:
        u = m.displacement(pts).T
        ur = u[0] * np.cos(th) + u[1] * np.sin(th)
        if np.abs(u[2]).max() < 0.1 * np.abs(ur).max() and int(np.argmax(np.abs(np.fft.rfft(ur))[:6])) == n:
            found.append(m)
    if every:
        return found
    if not found:
        raise RuntimeError(f"no in-plane n = {n} mode among {modes.frequencies}")
    return min(found, key=lambda m: m.frequency)


def thickness_resonator(name: str, thickness: float) -> tuple[float, float]:
    """(fr, fa) [Hz] of the 1-D thickness-extensional resonator of a plate poled through its ``thickness`` [m] (IEEE
    Std 176-1987): fa = sqrt(c33^D / rho) / 2t, c33^D = c33^E + e33^2 / eps33^S; fr from k_t^2 = (pi fr / 2 fa)
    tan(pi (fa - fr) / 2 fa), k_t^2 = e33^2 / (c33^D eps33^S)."""
    mat = material(name)
    c33D = mat.C[2, 2] + mat.e[2, 2] ** 2 / mat.eps_S[2, 2]
    fa = math.sqrt(c33D / mat.rho) / (2 * thickness)
    kt2 = mat.e[2, 2] ** 2 / (c33D * mat.eps_S[2, 2])
    x = so.brentq(lambda x: x * math.tan(math.pi / 2 - x) - kt2, 1.0, math.pi / 2 - 1e-9)  # x = pi fr / 2 fa
    return 2 * fa * x / math.pi, fa


def laterally_held(model, circuit: str, near: float) -> float:
    """Frequency [Hz] nearest ``near`` of an axisymmetric ``model`` (``modalfe.models.axisymmetric``) with u_r =
    u_theta = 0 everywhere (its constraint map for ``circuit`` without those columns): waves through the thickness
    only, the 1-D resonator of ``thickness_resonator`` for a plate poled through it."""
    import scipy.sparse as sp
    from scipy.sparse.linalg import eigsh

    T = sp.csc_matrix(model.constraints(circuit).T)
    lateral = np.zeros(model.ndofs, dtype=bool)
    for h in range(len(model.harmonics)):
        for c in (0, 1):
            lateral[model.u_dof(h, np.arange(model.basis.N), c)] = True
    keep = [j for j in range(T.shape[1]) if not lateral[T.indices[T.indptr[j]:T.indptr[j + 1]]].any()]
    T = T[:, keep]
    A, B = (T.T @ model.K @ T).tocsc(), (T.T @ model.M @ T).tocsc()
    w2 = eigsh(A, 1, B, sigma=(2 * np.pi * near) ** 2)[0]
    return float(np.sqrt(w2[0]) / (2 * np.pi))


STEEL_RING = {"E": 200e9, "nu": 0.3, "rho": 7850.0, "radius": 0.02, "wall": 0.001, "height": 0.002}


def steel_ring_scene():
    """examples/steel_ring.toml: a free steel ring (``STEEL_RING``: mean radius 20 mm, wall 1 mm, height 2 mm), its
    in-plane modes near 3 kHz."""
    from modalfe.scene.loading import load_scene

    return load_scene(EXAMPLES / "steel_ring.toml")


def radial_ring_scene(near: float):
    """A thin PZT-4 ring (mean radius 10 mm, wall 0.5 mm, height 1 mm) poled radially, electrodes on its walls."""
    from modalfe.scene.loading import scene_from_dict

    return scene_from_dict({
        "units": "mm", "parts": [{"name": "ring", "shape": "ring", "material": "PZT-4", "centre": [0, 0, 0],
                                  "axis": "z", "inner": 9.75, "outer": 10.25, "height": 1, "poling": "radial"}],
        "faces": {"electrode_a": ["ring.outer"], "electrode_b": ["ring.inner"]},
        "electrodes": {"electrode_a": "drive", "electrode_b": "ground"}, "analysis": {"near": near, "count": 6}})
