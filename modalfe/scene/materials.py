"""Named materials with their sources, as linear elastic or piezoelectric (e-form) tensors.

Voigt order xx, yy, zz, yz, xz, xy; engineering shear strains. Piezoelectric grades are poled along
the local 3-axis (z); ``PiezoMaterial.rotated`` gives any other frame (poling down = 180 deg about x).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from modalfe.errors import SceneError

EPS0 = 8.8541878128e-12  # vacuum permittivity [F/m], CODATA 2018


@dataclass(frozen=True, eq=False)
class ElasticMaterial:
    """Linear elastic solid: ``C`` [Pa] (6, 6) Voigt stiffness, ``rho`` [kg/m^3]."""

    name: str
    C: np.ndarray
    rho: float
    source: str

    def __post_init__(self) -> None:
        _check_tensor(self.name, "C", self.C, (6, 6))
        if not (np.isfinite(self.rho) and self.rho > 0):
            raise SceneError(f"material '{self.name}': rho must be positive, got {self.rho}")

    @property
    def is_piezoelectric(self) -> bool:
        return False

    def rotated(self, R: np.ndarray) -> ElasticMaterial:
        M = bond_matrix(R)
        C = M @ self.C @ M.T
        return ElasticMaterial(self.name, (C + C.T) / 2, self.rho, self.source)

    def wave_speed_shear(self) -> float:
        """Typical shear wave speed sqrt(median(C44, C55, C66) / rho) [m/s] (the median ignores
        the negligible in-plane shear modulus of a honeycomb core)."""
        return float(np.sqrt(np.median(np.diag(self.C)[3:]) / self.rho))


@dataclass(frozen=True, eq=False)
class PiezoMaterial(ElasticMaterial):
    """Linear piezoelectric solid in e-form, poled along local +3.

    C : c^E [Pa] (6, 6); e : [C/m^2] (3, 6); eps_S : [F/m] (3, 3); rho [kg/m^3].
    """

    e: np.ndarray = None
    eps_S: np.ndarray = None

    def __post_init__(self) -> None:
        super().__post_init__()
        e = np.asarray(self.e, dtype=float)
        if e.shape != (3, 6) or not np.all(np.isfinite(e)):
            raise SceneError(f"material '{self.name}': e must be a finite (3, 6) array [C/m^2]")
        _check_tensor(self.name, "eps_S", self.eps_S, (3, 3))

    @property
    def is_piezoelectric(self) -> bool:
        return True

    def rotated(self, R: np.ndarray) -> PiezoMaterial:
        """The same material seen in a frame rotated by ``R`` (3, 3)."""
        C, e, eps = poled_tensors(self, R)
        return PiezoMaterial(self.name, (C + C.T) / 2, self.rho, self.source, e=e, eps_S=(eps + eps.T) / 2)

    def poled(self, sign: int) -> PiezoMaterial:
        """Poled along +z (``sign`` = +1) or -z (-1): a half turn about x for -z."""
        return self if sign > 0 else self.rotated(np.diag([1.0, -1.0, -1.0]))


def _check_tensor(name: str, field: str, A, shape) -> None:
    A = np.asarray(A, dtype=float)
    if A.shape != shape or not np.all(np.isfinite(A)):
        raise SceneError(f"materials.{name}.{field}: must be a finite {shape} array")
    if not np.allclose(A, A.T, rtol=1e-10, atol=1e-12 * np.abs(A).max()):
        raise SceneError(f"materials.{name}.{field}: is not symmetric")
    if np.linalg.eigvalsh(A).min() <= 0:
        raise SceneError(f"materials.{name}.{field}: is not positive definite")


def bond_matrix(R: np.ndarray) -> np.ndarray:
    """Bond stress-transformation matrix (6, 6) of rotation ``R`` in Voigt order (Auld 1973); a stack of
    rotations (..., 3, 3) gives a stack of matrices (..., 6, 6)."""
    R = np.asarray(R, dtype=float)
    pairs = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)]
    M = np.zeros((*R.shape[:-2], 6, 6))
    for I, (i, j) in enumerate(pairs):
        for J, (k, l) in enumerate(pairs):
            M[..., I, J] = R[..., i, k] * R[..., j, l] + (R[..., i, l] * R[..., j, k] if k != l else 0.0)
    return M


def poling_frames(directions: np.ndarray) -> np.ndarray:
    """Rotations R (..., 3, 3) taking the local 3-axis (the poling axis of ``PiezoMaterial``) to the unit
    ``directions`` (..., 3): columns e1, e2 = d x e1, d, with e1 the x (or, near x, the y) axis made normal to d.
    The choice of e1 does not matter for poled ceramics (class 6mm, transversely isotropic about 3)."""
    d = np.asarray(directions, dtype=float)
    helper = np.zeros_like(d)
    near_x = np.abs(d[..., 0]) > 0.9
    helper[..., 0] = ~near_x
    helper[..., 1] = near_x
    e1 = helper - np.sum(helper * d, axis=-1, keepdims=True) * d
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    return np.stack([e1, np.cross(d, e1), d], axis=-1)


def poled_tensors(material: PiezoMaterial, R: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(c^E, e, eps^S) of ``material`` seen through rotations R (..., 3, 3) (as ``PiezoMaterial.rotated``, one per
    point): M c M^T, R e M^T, R eps R^T with M the Bond matrix of R."""
    M = bond_matrix(R)
    C = np.einsum("...ia,ab,...jb->...ij", M, material.C, M)
    e = np.einsum("...ia,ab,...jb->...ij", R, material.e, M)
    eps = np.einsum("...ia,ab,...jb->...ij", R, material.eps_S, R)
    return C, e, eps


def isotropic(name: str, *, E: float, nu: float, rho: float, source: str) -> ElasticMaterial:
    """Isotropic solid from Young's modulus ``E`` [Pa] and Poisson's ratio ``nu``."""
    if not (E > 0):
        raise SceneError(f"material '{name}': E must be positive, got {E}")
    if not (-1.0 < nu < 0.5):
        raise SceneError(f"material '{name}': nu must lie in (-1, 0.5), got {nu}")
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[np.arange(3), np.arange(3)] += 2 * mu
    C[3, 3] = C[4, 4] = C[5, 5] = mu
    return ElasticMaterial(name, C, rho, source)


def orthotropic(
    name: str, *, E: tuple, nu: tuple, G: tuple, rho: float, source: str
) -> ElasticMaterial:
    """Orthotropic solid: E = (E1, E2, E3) [Pa], nu = (nu12, nu13, nu23), G = (G23, G13, G12) [Pa]."""
    E1, E2, E3 = E
    nu12, nu13, nu23 = nu
    S = np.zeros((6, 6))
    S[:3, :3] = [
        [1 / E1, -nu12 / E1, -nu13 / E1],
        [-nu12 / E1, 1 / E2, -nu23 / E2],
        [-nu13 / E1, -nu23 / E2, 1 / E3],
    ]
    S[3, 3], S[4, 4], S[5, 5] = (1 / g for g in G)
    if np.linalg.eigvalsh(S).min() <= 0:
        raise SceneError(f"material '{name}': orthotropic constants are not positive definite")
    return ElasticMaterial(name, np.linalg.inv(S), rho, source)


def transversely_isotropic_piezo(
    name: str, *, c: dict, e: dict, eps_r: dict, rho: float, source: str
) -> PiezoMaterial:
    """6mm piezoceramic from c11, c12, c13, c33, c44 [Pa], e31, e33, e15 [C/m^2], eps11, eps33 (relative)."""
    C = np.zeros((6, 6))
    C[0, 0] = C[1, 1] = c["11"]
    C[0, 1] = C[1, 0] = c["12"]
    C[0, 2] = C[2, 0] = C[1, 2] = C[2, 1] = c["13"]
    C[2, 2] = c["33"]
    C[3, 3] = C[4, 4] = c["44"]
    C[5, 5] = (c["11"] - c["12"]) / 2
    E = np.zeros((3, 6))
    E[2, 0] = E[2, 1] = e["31"]
    E[2, 2] = e["33"]
    E[0, 4] = E[1, 3] = e["15"]
    eps = EPS0 * np.diag([eps_r["11"], eps_r["11"], eps_r["33"]])
    return PiezoMaterial(name, C, rho, source, e=E, eps_S=eps)


def piezo_stiffness_form(s_E: np.ndarray, d: np.ndarray, eps_T: np.ndarray
                         ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(c^E [Pa] (6, 6), e [C/m^2] (3, 6), eps^S [F/m] (3, 3)) from the datasheet d-form tensors.

    c^E = (s^E)^-1, e = d c^E, eps^S = eps^T - d c^E d^T = eps^T - e d^T; IEEE Std 176-1987 (the
    inverse of ``piezo_compliance_form``; exact matrix identities). Voigt order xx, yy, zz, yz, xz, xy.
    """
    c_E = np.linalg.inv(np.asarray(s_E, dtype=float))
    c_E = (c_E + c_E.T) / 2
    e = np.asarray(d, dtype=float) @ c_E
    eps_S = np.asarray(eps_T, dtype=float) - e @ np.asarray(d, dtype=float).T
    return c_E, e, eps_S


def piezo_compliance_form(c_E: np.ndarray, e: np.ndarray, eps_S: np.ndarray
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(s^E [1/Pa] (6, 6), d [C/N] (3, 6), eps^T [F/m] (3, 3)) from the e-form tensors.

    s^E = (c^E)^-1, d = e s^E, eps^T = eps^S + d e^T; IEEE Std 176-1987 (relations between
    the four forms of the piezoelectric constitutive equations; exact matrix identities).
    Voigt order xx, yy, zz, yz, xz, xy.
    """
    s_E = np.linalg.inv(np.asarray(c_E, dtype=float))
    d = np.asarray(e, dtype=float) @ s_E
    eps_T = np.asarray(eps_S, dtype=float) + d @ np.asarray(e, dtype=float).T
    return s_E, d, eps_T


def completed_from_datasheet(
    name: str, *, s11E: float, s33E: float, d31: float, d33: float, d15: float, eps_r: dict, kp: float, rho: float,
    source: str,
) -> PiezoMaterial:
    """A 6mm piezoceramic from a data sheet that lists s11E, s33E [1/Pa], d31, d33, d15 [C/N], the relative
    permittivities ``eps_r`` {"11T", "33T", "11S", "33S"}, the planar coupling ``kp`` and rho [kg/m^3], but not s12E,
    s13E, s44E. Those three follow from the same sheet's kp, eps11S and eps33S by identities of IEEE Std 176-1987
    (nothing fitted to a frequency):

        kp^2 = 2 d31^2 / (eps33T (s11E + s12E));   eps11S = eps11T - d15^2 / s44E;
        eps33S = eps33T - d3 . s_n^-1 . d3,  d3 = (d31, d31, d33),  s_n the normal block of s^E,

    the last a quadratic in s13E, 2 D s13^2 - 4 d31 d33 s13 + 2 d31^2 s33 + d33^2 P - D P s33 = 0 (D = eps33T -
    eps33S, P = s11E + s12E), of whose two roots the one with e31 < 0 is taken (the other gives e31 > 0: no PZT).
    """
    eps = {k: EPS0 * v for k, v in eps_r.items()}
    P = 2 * d31**2 / (kp**2 * eps["33T"])
    s12E = P - s11E
    s44E = d15**2 / (eps["11T"] - eps["11S"])
    D = eps["33T"] - eps["33S"]
    d = np.zeros((3, 6))
    d[2, :2], d[2, 2], d[0, 4], d[1, 3] = d31, d33, d15, d15
    roots = np.roots([2 * D, -4 * d31 * d33, 2 * d31**2 * s33E + d33**2 * P - D * P * s33E])
    for s13E in roots[np.isreal(roots)].real:
        s_E = np.diag([s11E, s11E, s33E, s44E, s44E, 2 * (s11E - s12E)])
        s_E[0, 1] = s_E[1, 0] = s12E
        s_E[0, 2] = s_E[2, 0] = s_E[1, 2] = s_E[2, 1] = s13E
        C, e, eps_S = piezo_stiffness_form(s_E, d, np.diag([eps["11T"], eps["11T"], eps["33T"]]))
        if e[2, 0] < 0:
            return PiezoMaterial(name, (C + C.T) / 2, rho, source, e=e, eps_S=(eps_S + eps_S.T) / 2)
    raise SceneError(f"material '{name}': no real s13E with e31 < 0 reproduces the data sheet's eps33S "
                     "(its figures are inconsistent)")


_CERAMTEC_P4 = (
    "CeramTec, 'Piezoceramic Hard Materials - Material Data', Sonox P4 (Navy type I), stored copy "
    "https://de.scribd.com/document/628850476/Piezoceramic-Hard-Materials (the same values in CeramTec's 'Werkstoffe "
    "fuer Leistungswandler / Materials for power converters', https://expydoc.com/doc/1391026/): eps33T/eps0 1300, "
    "eps33S/eps0 660, eps11T/eps0 1535, eps11S/eps0 885, kp 0.57, d33 310, d31 -130, d15 455 pC/N, s11E 14.9, s33E "
    "18.1 x 1e-12 m^2/N, rho 7650 kg/m^3; s12E, s13E, s44E completed from the same sheet by IEEE Std 176 identities "
    "(completed_from_datasheet). The sheet's own c33D (15.9e10 N/m^2) disagrees with the completed set's (12.4e10); "
    "its kt (0.50), k31 (0.31), k15 (0.65) and c55D (4.8e10) agree. Its frequency constants Np 2210, Nt 2000 Hz m "
    "are compared in studies/frequency_constants.py, not used here"
)


_BERLINCOURT = (
    "Berlincourt, Curran & Jaffe, 'Piezoelectric and piezomagnetic materials', Physical "
    "Acoustics vol. 1A (1964), as tabulated in Sherman & Butler, Transducers and Arrays for "
    "Underwater Sound (2007), Appendix A.5"
)


def _library() -> dict[str, ElasticMaterial]:
    return {
        "CuBe": isotropic(
            "CuBe", E=123e9, nu=0.30, rho=8250.0,
            source="seed 001, materials table (copper-beryllium plate)",
        ),
        "PZT-seed001": isotropic(
            "PZT-seed001", E=72.6e9, nu=0.31, rho=7700.0,
            source="seed 001, materials table (isotropic stand-in, no coupling)",
        ),
        "brass-seed003": isotropic(
            "brass-seed003", E=105e9, nu=0.34, rho=8500.0,
            source="seed 003 (E, rho); nu 0.34 typical of brass, ASM Handbook vol. 2 (1990)",
        ),
        "piezo-seed003-e31": PiezoMaterial(
            "piezo-seed003-e31", isotropic("iso", E=76.5e9, nu=0.31, rho=7500.0, source="").C, 7500.0,
            "seed 003 (E 76.5 GPa, rho 7500, e31 = e32 = 2.0 C/m^2, no other coupling); nu 0.31 as seed 001; "
            "eps_S of PZT-5A (the seed gives none; it only sets the electrical side)",
            e=np.array([[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0], [2.0, 2.0, 0, 0, 0, 0]], dtype=float),
            eps_S=EPS0 * np.diag([916.0, 916.0, 830.0]),
        ),
        "piezo-seed003": isotropic(
            "piezo-seed003", E=76.5e9, nu=0.31, rho=7500.0,
            source="seed 003 (E, rho); nu 0.31 as the seed 001 PZT",
        ),
        "soda-lime-glass": isotropic(
            "soda-lime-glass", E=70e9, nu=0.22, rho=2500.0,
            source="EN 572-1:2012 (E 70 GPa, rho 2500); nu 0.22, Shelby, Introduction to Glass "
            "Science and Technology (2005)",
        ),
        "Al-5052": isotropic(
            "Al-5052", E=70.3e9, nu=0.33, rho=2680.0,
            source="ASM Handbook vol. 2 (1990), aluminium 5052-H38 (honeycomb facing and foil alloy)",
        ),
        "Al-seed002": isotropic(
            "Al-seed002", E=60e9, nu=0.33, rho=2680.0,
            source="seed 002 eq. (5) facing modulus 60 GPa; nu, rho as Al-5052",
        ),
        "honeycomb-5052-1/4-.001": orthotropic(
            "honeycomb-5052-1/4-.001",
            E=(1.0e6, 1.0e6, 517e6), nu=(0.3, 1e-4, 1e-4), G=(152e6, 310e6, 0.4e6), rho=36.8,
            source="Hexcel, HexWeb Honeycomb Attributes and Properties (1999): 5052 1/4-.001, "
            "2.3 pcf; G_L 45 ksi (xz), G_W 22 ksi (yz), E_c 75 ksi; in-plane moduli ~0 (set 1 MPa)",
        ),
        "epoxy": isotropic(
            "epoxy", E=2.8e9, nu=0.35, rho=1200.0,
            source="Ashby, Materials Selection in Mechanical Design, 4th ed. (2011): epoxies "
            "E 2.35-3.08 GPa, rho 1110-1400 kg/m^3, nu 0.34-0.36 (mid-range values)",
        ),
        "SBR": isotropic(
            "SBR", E=2.0e6, nu=0.49, rho=1100.0,
            source="seed 002 (E 2 MPa); nu 0.49 near-incompressible rubber, rho 1100 filled SBR "
            "(Gent, Engineering with Rubber, 3rd ed. 2012)",
        ),
        "PZT-4": transversely_isotropic_piezo(
            "PZT-4", c={"11": 13.9e10, "12": 7.78e10, "13": 7.43e10, "33": 11.5e10, "44": 2.56e10},
            e={"31": -5.2, "33": 15.1, "15": 12.7}, eps_r={"11": 730.0, "33": 635.0},
            rho=7500.0, source=_BERLINCOURT,
        ),
        "PZT-5A": transversely_isotropic_piezo(
            "PZT-5A", c={"11": 12.1e10, "12": 7.54e10, "13": 7.52e10, "33": 11.1e10, "44": 2.11e10},
            e={"31": -5.4, "33": 15.8, "15": 12.3}, eps_r={"11": 916.0, "33": 830.0},
            rho=7750.0, source=_BERLINCOURT,
        ),
        "PZT-5H": transversely_isotropic_piezo(
            "PZT-5H", c={"11": 12.6e10, "12": 7.95e10, "13": 8.41e10, "33": 11.7e10, "44": 2.30e10},
            e={"31": -6.5, "33": 23.3, "15": 17.0}, eps_r={"11": 1700.0, "33": 1470.0},
            rho=7500.0, source=_BERLINCOURT,
        ),
        "Sonox-P4": completed_from_datasheet(
            "Sonox-P4", s11E=14.9e-12, s33E=18.1e-12, d31=-130e-12, d33=310e-12, d15=455e-12,
            eps_r={"11T": 1535.0, "33T": 1300.0, "11S": 885.0, "33S": 660.0}, kp=0.57, rho=7650.0,
            source=_CERAMTEC_P4,
        ),
    }


MATERIALS: dict[str, ElasticMaterial] = _library()


@dataclass(frozen=True)
class StrengthLimits:
    """Optional limits of a material, with their source: ``depolarising_field`` [V/m] (peak AC field that
    starts to depole a ceramic, about its coercive field) and ``tensile_strength`` [Pa]; None: not given."""

    depolarising_field: float | None
    tensile_strength: float | None
    source: str


_TP226 = ("Morgan Electro Ceramics (Berlincourt, Krueger & Near), Technical Publication TP-226, 'Properties "
          "of Morgan Electro Ceramic Ceramics': PZT-4 AC depoling field >= 10 kV/cm at 25 C (taken as 1 kV/mm), "
          "static tensile strength 11,000 psi = 76 MPa (not re-checked against the document in this release: "
          "confirm with your supplier's datasheet; a scene file may set its own limits)")
# only limits with a datasheet behind them; every other material has "no limit in the table"
LIMITS: dict[str, StrengthLimits] = {"PZT-4": StrengthLimits(1.0e6, 76e6, _TP226)}
LIMIT_KEYS = ("depolarising_field", "tensile_strength", "limits_source")


def strength_limits(name: str, scene=None) -> StrengthLimits | None:
    """The limits of a material: a scene file's own (``depolarising_field`` [V/m], ``tensile_strength`` [Pa],
    ``limits_source`` in its ``[materials.NAME]`` table), else the library's (``LIMITS``), else None."""
    spec = scene.materials.get(name) if scene is not None else None
    if spec is not None:
        given = {k: spec[k] for k in LIMIT_KEYS[:2] if k in spec}
        if not given:
            return None
        return StrengthLimits(*(number(f"materials.{name}.{k}", given[k], positive=True) if k in given else None
                                for k in LIMIT_KEYS[:2]), str(spec.get("limits_source", "user scene file")))
    return LIMITS.get(name)


# bounds that catch a value in the wrong unit: a permittivity above 1e-6 F/m is ~1e5 eps0 (the relative
# number was given), an E below 1 kPa is a modulus in GPa or MPa, a density below 10 kg/m^3 one in g/cm^3
EPS_MAX = 1e-6
MODULUS_MIN = 1e3
RHO_RANGE = (10.0, 1e5)
_META = ("name", "source")
_FORMS = {
    "isotropic": ("E", "nu", "rho"),
    "anisotropic": ("C", "rho"),
    "piezo e-form": ("C", "e", "eps_S", "rho"),
    "piezo d-form": ("s_E", "d", "eps_T", "rho"),
}


def material(name_or_spec) -> ElasticMaterial:
    """A named material, or one built from a TOML/dict spec.

    Spec forms (SI units; ``name`` and ``source`` optional): ``{E, nu, rho}`` (isotropic),
    ``{C (6x6), rho}`` (anisotropic), ``{C, e (3x6), eps_S (3x3), rho}`` (piezoelectric e-form) or
    the datasheet d-form ``{s_E (6x6) [1/Pa], d (3x6) [C/N], eps_T (3x3) [F/m], rho}``, converted
    with the IEEE Std 176 relations. Errors name the field: ``materials.NAME.KEY: ...``.
    """
    if isinstance(name_or_spec, ElasticMaterial):
        return name_or_spec
    if isinstance(name_or_spec, str):
        try:
            return MATERIALS[name_or_spec]
        except KeyError:
            raise SceneError(
                f"unknown material '{name_or_spec}'; known: {', '.join(sorted(MATERIALS))}"
            ) from None
    if not isinstance(name_or_spec, Mapping):
        raise SceneError(f"material: must be a name or a table of constants, got {name_or_spec!r}")
    spec = dict(name_or_spec)
    name = str(spec.pop("name", "user material"))
    field = f"materials.{name}"
    for key in LIMIT_KEYS:  # optional strength limits (``strength_limits``), checked here
        if key in spec:
            value = spec.pop(key)
            if key == "limits_source":
                if not isinstance(value, str) or not value:
                    raise SceneError(f"{field}.{key}: must be a non-empty string, got {value!r}")
            else:
                unit = "V/m" if key == "depolarising_field" else "Pa"
                number(f"{field}.{key}", value, unit=unit, positive=True)
    source = spec.pop("source", "user scene file")
    if not isinstance(source, str):
        raise SceneError(f"{field}.source: must be a string, got {source!r}")
    keys = set(spec)
    form = next((f for f, need in _FORMS.items() if keys <= set(need) and keys >= set(need) - {"nu"}), None)
    if form is None:
        known = sorted({k for need in _FORMS.values() for k in need})
        unknown = sorted(keys - set(known))
        if unknown:
            raise SceneError(f"{field}.{unknown[0]}: unknown key; known: {', '.join(known + list(_META))}")
        if "rho" not in keys:
            raise SceneError(f"{field}.rho: missing (density [kg/m^3])")
        forms = "; ".join(f"{f}: {', '.join(need)}" for f, need in _FORMS.items())
        raise SceneError(f"{field}: keys {sorted(keys)} match no form ({forms})")
    rho = number(f"{field}.rho", spec["rho"], unit="kg/m^3", positive=True)
    if not RHO_RANGE[0] <= rho <= RHO_RANGE[1]:
        raise SceneError(f"{field}.rho: {rho:g} kg/m^3 is implausible (expected {RHO_RANGE[0]:g} to "
                         f"{RHO_RANGE[1]:g}; a density in g/cm^3 is 1000x that)")
    if form == "isotropic":
        E = number(f"{field}.E", spec["E"], unit="Pa", positive=True)
        if E < MODULUS_MIN:
            raise SceneError(f"{field}.E: {E:g} Pa is implausibly small; E is in Pa (200 GPa = 200e9)")
        nu = number(f"{field}.nu", spec.get("nu", 0.3))
        if not -1.0 < nu < 0.5:
            raise SceneError(f"{field}.nu: must lie in (-1, 0.5), got {nu:g}")
        return isotropic(name, E=E, nu=nu, rho=rho, source=source)
    if form == "anisotropic":
        return ElasticMaterial(name, _matrix(f"{field}.C", spec["C"], (6, 6)), rho, source)
    if form == "piezo e-form":
        C = _matrix(f"{field}.C", spec["C"], (6, 6))
        e = _matrix(f"{field}.e", spec["e"], (3, 6))
        eps_S = _permittivity(f"{field}.eps_S", spec["eps_S"])
        return PiezoMaterial(name, C, rho, source, e=e, eps_S=eps_S)
    s_E = _matrix(f"{field}.s_E", spec["s_E"], (6, 6))
    d = _matrix(f"{field}.d", spec["d"], (3, 6))
    eps_T = _permittivity(f"{field}.eps_T", spec["eps_T"])
    _check_tensor(name, "s_E", s_E, (6, 6))
    if np.abs(s_E).max() > 1e-3:
        raise SceneError(f"{field}.s_E: compliances are in 1/Pa (~1e-11 for PZT); got entries up to "
                         f"{np.abs(s_E).max():g}")
    C, e, eps_S = piezo_stiffness_form(s_E, d, eps_T)
    if np.linalg.eigvalsh((eps_S + eps_S.T) / 2).min() <= 0:
        raise SceneError(f"{field}.eps_T: eps_S = eps_T - d c_E d^T is not positive definite (d too large "
                         f"for eps_T: check the units, d in C/N ~1e-10, eps_T in F/m ~1e-8)")
    return PiezoMaterial(name, C, rho, source, e=e, eps_S=(eps_S + eps_S.T) / 2)


def number(field: str, value, *, unit: str = "", positive: bool = False) -> float:
    """A finite real number (not a bool, not a string)."""
    from modalfe.scene.values import number as checked

    return checked(field, value, unit=unit, positive=positive)


def _matrix(field: str, value, shape: tuple[int, int]) -> np.ndarray:
    """A finite numeric array of ``shape`` (rows of numbers)."""
    rows = value.tolist() if isinstance(value, np.ndarray) else value
    ok = isinstance(rows, (list, tuple)) and len(rows) == shape[0] and all(
        isinstance(r, (list, tuple)) and len(r) == shape[1] for r in rows)
    if not ok:
        raise SceneError(f"{field}: must be {shape[0]} rows of {shape[1]} numbers")
    for i, r in enumerate(rows):
        for j, x in enumerate(r):
            number(f"{field}[{i}][{j}]", x)
    return np.asarray(rows, dtype=float)


def _permittivity(field: str, value) -> np.ndarray:
    """A (3, 3) permittivity in F/m; refused when it looks relative (entries above EPS_MAX)."""
    eps = _matrix(field, value, (3, 3))
    if np.abs(eps).max() > EPS_MAX:
        raise SceneError(f"{field}: {np.abs(eps).max():g} F/m is ~{np.abs(eps).max() / EPS0:.2g} eps0: give "
                         f"the permittivity in F/m (relative value times eps0 = {EPS0:.6g} F/m)")
    return eps


@dataclass(frozen=True)
class MaterialLoss:
    """Small-signal losses of a material: mechanical quality factor ``Qm`` (loss factor 1 / Qm) and
    dielectric loss tangent ``tan_delta`` (permittivity eps (1 - i tan delta)), either None when not
    sourced, with the ``source`` of the numbers."""

    Qm: float | None
    tan_delta: float | None
    source: str


_LOSS_SOURCE = (
    "Berlincourt, Curran & Jaffe (1964) Navy-type nominal values (low field, room temperature, +-20 %), "
    "as listed for the equivalent grades in manufacturer datasheets, e.g. Morgan Electro Ceramics, "
    "'Piezoelectric Technology Data for Designers' (PZT-4 / PZT-5A / PZT-5H)"
)

# losses by material name; a material absent here has no sourced loss data (metals, glass, the seeds' stand-ins)
LOSSES: dict[str, MaterialLoss] = {
    "PZT-4": MaterialLoss(Qm=500.0, tan_delta=0.004, source=_LOSS_SOURCE),
    "PZT-5A": MaterialLoss(Qm=75.0, tan_delta=0.02, source=_LOSS_SOURCE),
    "PZT-5H": MaterialLoss(Qm=65.0, tan_delta=0.02, source=_LOSS_SOURCE),
    "Sonox-P4": MaterialLoss(Qm=500.0, tan_delta=0.003, source="CeramTec, 'Piezoceramic Hard Materials - Material "
                             "Data', Sonox P4: Qm 500, tan delta 3e-3 (the sheet of the material, _CERAMTEC_P4)"),
}


def material_loss(name: str) -> MaterialLoss | None:
    """The sourced losses of the named material, or None when the table has none."""
    return LOSSES.get(name)
