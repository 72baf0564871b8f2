"""What the reduced-dimension models (``modalfe.models.beam``, ``modalfe.models.plate``) share: the electrode and
circuit handling of their laminated piezo layers, the element size from the flexural wavenumber, the surface
sampling that labels their modes. Their matrices have the 3-D model's block form
[[K_uu, K_uphi], [K_uphi^T, -K_phiphi]] with one potential unknown per electrode face group, so every later
stage treats them alike.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from modalfe.errors import SceneError
from modalfe.models.solid import PiezoUnknowns


@dataclass(frozen=True, eq=False)
class LayeredModel(PiezoUnknowns):
    """An assembled reduced model (full DOF set, no constraint applied): K, M with u DOFs first then one
    potential per electrode, ``electrodes`` (group -> index array into the phi unknowns), ``clamped`` (u DOF
    indices fixed to zero), ``basis`` the scalar scikit-fem basis of every field. Subclasses give
    ``displacement_probes(points)`` and ``surface_points()``; the circuit handling is the 3-D model's (every
    potential is an electrode's)."""

    scene: object
    mesh: object
    basis: object
    K: sp.csr_matrix
    M: sp.csr_matrix
    n_u: int
    electrodes: dict[str, np.ndarray]
    clamped: np.ndarray
    timings: dict[str, float] = field(default_factory=dict)
    attached_mass: sp.csr_matrix | None = None  # (n_u, n_u): the scene's masses alone, included in M
    guided: tuple[np.ndarray, ...] = ()  # groups of u DOFs sharing one unknown (guided faces; the plate model)

    @property
    def n_phi(self) -> int:
        return len(self.electrodes)

    def potential_probes(self, points: np.ndarray) -> sp.csr_matrix:
        """Not available: a reduced model carries one potential per electrode, no field in the layers."""
        raise SceneError(f"points: the {self.scene.kind} model has no potential field (one unknown per electrode); "
                         "use the solid fidelity")

    @functools.cached_property
    def _surface(self) -> tuple[np.ndarray, sp.csr_matrix]:
        points = self.surface_points()
        return points.T, self.displacement_probes(points)

    def label_field(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(points (3, m) [m], displacement (3, m) [m]) of the full DOF vector ``x`` at ``surface_points``."""
        points, probes = self._surface
        return points, (probes @ np.asarray(x)).reshape(3, -1)


def flexural_wavenumber(w2: float, EI: float, kGA: float, rhoA: float, rhoI: float) -> float:
    """Propagating root k [rad/m] of the shear-deformable (Timoshenko beam, Mindlin plate) flexural dispersion

        EI kGA k^4 - w^2 (rhoA EI + rhoI kGA) k^2 + rhoA w^2 (rhoI w^2 - kGA) = 0

    at w^2 = ``w2`` [rad^2/s^2]: bending stiffness EI, shear stiffness kGA, inertia rhoA and rotary inertia rhoI
    per unit length (beam) or per unit area (plate: D, A_s, I0, I2)."""
    a, b, c = EI * kGA, w2 * (rhoA * EI + rhoI * kGA), rhoA * w2 * (rhoI * w2 - kGA)
    return math.sqrt((b + math.sqrt(b * b - 4 * a * c)) / (2 * a))


def element_size(sections, scene, wavenumber, size_factor: float = 1.0) -> float:
    """Element size [m]: the shortest wavelength at ``scene.max_frequency`` over the ``sections``
    (``wavenumber(section, frequency)`` [rad/m]), divided by ``scene.mesh.elements_per_wavelength``, at most
    ``scene.mesh.max_size``, times ``size_factor``."""
    k = max(wavenumber(s, scene.max_frequency) for s in sections)
    return min(2 * np.pi / k / scene.mesh.elements_per_wavelength, scene.mesh.max_size) * size_factor


def electrode_layers(scene, assembly) -> tuple[dict[str, int], list[tuple]]:
    """(group -> phi index, [(part, top group, bottom group)]) for the poled parts of ``assembly``.

    The reduced models know one kind of electrode: whole z faces of a part poled along z, the field
    uniform through its thickness. Anything else raises SceneError naming the group or part."""
    groups = list(scene.electrodes)
    on_face = {}
    for g in groups:
        for f in assembly.faces[g]:
            if f.window is not None:
                raise SceneError(f"electrodes.{g}: face windows are not supported by the {scene.kind} model")
            on_face[(f.part, f.side)] = g
    layers, used = [], set()
    for part in assembly.parts:
        if not part.poling:
            continue
        top, bottom = on_face.get((part.name, "zmax")), on_face.get((part.name, "zmin"))
        if top is None or bottom is None:
            raise SceneError(f"part '{part.name}': the {scene.kind} model needs electrode groups on both z faces "
                             f"of a poled part")
        layers.append((part, top, bottom))
        used |= {top, bottom}
    unused = [g for g in groups if g not in used]
    if unused:
        raise SceneError(f"electrodes.{unused[0]}: the face group is not a z face of a poled piezo part "
                         f"(the only electrodes the {scene.kind} model supports)")
    return {g: i for i, g in enumerate(groups)}, layers


def capacitance_matrix(n_phi: int, capacitors: list[tuple[int, int, float]]) -> np.ndarray:
    """K_phiphi (n_phi, n_phi) of layers between electrode unknowns (i, j) with capacitance C [F] each:
    C [[1, -1], [-1, 1]] on (i, j), summed."""
    K = np.zeros((n_phi, n_phi))
    for i, j, C in capacitors:
        K[[i, j, i, j], [i, j, j, i]] += [C, C, -C, -C]
    return K


def thin_layer_constants(material, in_plane: list[int]) -> tuple[np.ndarray, np.ndarray, float]:
    """(stiffness Q, coupling e*, permittivity eps*) of a thin layer with field E3 only and the stresses
    outside ``in_plane`` (Voigt indices) zero: from the d-form, eps_in = s_in sig_in + d_in^T E3 and
    D3 = d_in . sig_in + eps33^T E3, so Q = s_in^-1, e* = Q d_in, eps* = eps33^T - d_in Q d_in (IEEE Std
    176-1987 relations via ``modalfe.scene.materials.piezo_compliance_form``). For ``in_plane`` = [0] this is the
    beam's uniaxial stress, for [0, 1, 5] the plate's plane stress; e* = 0, eps* = 0 for a passive layer."""
    from modalfe.scene.materials import piezo_compliance_form

    s = np.linalg.inv(material.C)
    Q = np.linalg.inv(s[np.ix_(in_plane, in_plane)])
    if not material.is_piezoelectric:
        return Q, np.zeros(len(in_plane)), 0.0
    _, d, eps_T = piezo_compliance_form(material.C, material.e, material.eps_S)
    d_in = d[2, in_plane]
    return Q, Q @ d_in, float(eps_T[2, 2] - d_in @ Q @ d_in)
