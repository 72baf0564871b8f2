"""Losses of a piezoelectric device's modes and of its electrodes: mechanical viscous (modal zeta, Q = 1 / 2 zeta,
Rayleigh alpha + beta omega_r^2 = 2 zeta_r omega_r) or hysteretic (loss factor eta, and per material eta_r =
sum_m U_m,r / U_r / Qm_m, the modal strain-energy method, Johnson & Kienholz, AIAA J. 20 (1982) 1284); dielectric:
eps^S (1 - i tan delta). Resolved from the options given, else the scene's drive and the material table
(``resolve_losses``), with each one's source; used by the admittance (``modalfe.response.admittance``)."""

from __future__ import annotations

import math
import weakref
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

import modalfe.caches as caches
from modalfe.errors import SceneError, SolverError

if TYPE_CHECKING:
    from modalfe.response.forced import Damping
    from modalfe.results.modes import Mode


@dataclass(frozen=True)
class Losses:
    """Mechanical loss ``mechanical`` (``Q=..``, ``zeta=..``, ``eta=..``, ``rayleigh=A,B`` or ``material``: each
    material's Qm, the ``fallback`` where the table has none) and dielectric ``tan_delta``, each with its source;
    ``per_mode``: label -> spec overriding the mechanical loss of that mode (modal superposition only)."""

    mechanical: str
    mechanical_source: str
    tan_delta: float
    tan_delta_source: str
    fallback: str = ""
    fallback_source: str = ""
    per_mode: Mapping[str, str] = field(default_factory=dict)

    def describe(self) -> list[str]:
        lines = [f"mechanical: {self.mechanical} ({self.mechanical_source})"]
        if self.mechanical == "material":
            lines[0] = f"mechanical: per material, modal strain-energy weighted 1 / Qm ({self.mechanical_source})"
            lines.append(f"materials without Qm and springs: {self.fallback} ({self.fallback_source})")
        lines += [f"mode {label}: {spec} (set by the user)" for label, spec in self.per_mode.items()]
        lines.append(f"dielectric: tan delta = {self.tan_delta:g} on the clamped capacitance ({self.tan_delta_source})")
        return lines


def loss_spec(field_name: str, text: str) -> tuple[str, tuple[float, ...]]:
    """(kind, numbers) of a mechanical loss spec: zeta, Q, eta, rayleigh or material."""
    from modalfe.response.forced import Damping
    from modalfe.scene.scene import check_underdamped

    text = str(text).strip()
    if text == "material":
        return "material", ()
    key, _, value = text.partition("=")
    if key not in ("Q", "zeta", "eta", "rayleigh"):
        raise SceneError(f"{field_name}: expected Q=Q, zeta=Z, eta=ETA, rayleigh=ALPHA,BETA or material, "
                         f"got '{text}'")
    if key == "eta":
        try:
            eta = float(value)
        except ValueError:
            raise SceneError(f"{field_name}: expected eta=LOSS_FACTOR, got '{text}'") from None
        if not (math.isfinite(eta) and eta >= 0):
            raise SceneError(f"{field_name}: eta must be finite and >= 0, got {value}")
        check_underdamped(field_name, eta / 2)
        return "eta", (eta,)
    try:
        d = Damping.parse(text)
    except SceneError as exc:  # its own message (a number out of range, an overdamped ratio), after the flag's name
        raise SceneError(f"{field_name}: {exc}") from None
    if d.zeta is not None:
        return "zeta", (d.zeta,)
    if d.Q is not None:
        return "zeta", (1.0 / (2.0 * d.Q),)
    return "rayleigh", (d.alpha, d.beta)


def resolve_losses(scene, *, damping: str | None = None, tan_delta: float | None = None,
                   per_mode: Mapping[str, str] | None = None) -> Losses:
    """The losses of ``scene``: ``damping`` (default: the scene's ``drive.damping``, ``material`` unless the scene
    says otherwise; ``drive.damping_fallback`` where a material has no Qm), ``tan_delta`` (default: the material
    table's value of the scene's piezoelectric materials, 0 when it has none)."""
    drive = scene.drive
    mechanical, source = (drive.damping, drive.damping_source) if damping is None else (str(damping),
                                                                                        "set by the user")
    loss_spec("--damping", mechanical)
    if mechanical == "material":
        source = _material_loss_sources(scene, "Qm") or "no material of the scene has a sourced Qm"
    for label, spec in (per_mode or {}).items():
        if loss_spec(f"--mode-damping {label}", spec)[0] == "material":
            raise SceneError(f"--mode-damping {label}: 'material' applies to all modes; give Q, zeta or eta")
    if tan_delta is not None:
        if not (math.isfinite(tan_delta) and 0 <= tan_delta < 1):
            raise SceneError(f"--tan-delta: must lie in [0, 1), got {tan_delta:g}")
        td, td_source = float(tan_delta), "set by the user"
    else:
        values = _piezo_tan_deltas(scene)
        if not values:
            td, td_source = 0.0, "no dielectric loss: the scene's piezoelectric materials have no sourced tan delta"
        else:
            td = max(values.values())
            td_source = _material_loss_sources(scene, "tan_delta")
            if len(set(values.values())) > 1:
                td_source += f"; materials differ ({values}), the largest is applied to the whole capacitance"
    return Losses(mechanical, source, td, td_source, drive.damping_fallback, drive.damping_fallback_source,
                  dict(per_mode or {}))


def mode_damping(mode: Mode, losses: Losses) -> tuple[Damping, str]:
    """(``modalfe.response.forced.Damping``, its source) of one mode for a one-mode model: the losses' own spec,
    or for ``material`` the viscous equivalent at resonance, zeta_r = eta_r / 2 (Q = 1 / eta_r), of the modal
    strain-energy loss factor eta_r = sum_m U_m,r / U_r / Qm_m + (the rest) x the fallback's
    (Johnson & Kienholz, AIAA J. 20 (1982) 1284). A model without per-material stiffness (not the 3-D solid)
    takes the fallback, and says so."""
    from modalfe.response.forced import Damping

    kind, v = loss_spec("--damping", losses.mechanical)
    if kind == "eta":
        return Damping(zeta=v[0] / 2), f"{losses.mechanical_source}; the loss factor's viscous equivalent at resonance"
    if kind != "material":
        return Damping.parse(losses.mechanical), losses.mechanical_source
    if not _per_part(mode.model):
        return Damping.parse(losses.fallback), (f"{losses.fallback_source}; this model (not the 3-D solid or the "
                                                "axisymmetric one) has no per-material strain energy for the "
                                                "materials' Qm")
    if not qm_table(mode.model):
        return Damping.parse(losses.fallback), (f"{losses.fallback_source}; no material of the scene has a "
                                                "sourced Qm")
    c, h, text = modal_losses([mode], mode.model, losses)
    zeta = float(c[0] / (2 * mode.omega) + h[0] / (2 * mode.omega**2))
    return Damping(Q=1 / (2 * zeta)), (f"{text[0]}: {losses.mechanical_source}; the rest at {losses.fallback} "
                                       f"({losses.fallback_source})")


def _piezo_tan_deltas(scene) -> dict[str, float]:
    from modalfe.scene.materials import material_loss

    out = {}
    for part in scene.assembly().parts:
        name = scene.material(part.material).name
        loss = material_loss(name)
        if part.poling and loss is not None and loss.tan_delta is not None:
            out[name] = loss.tan_delta
    return out


def _material_loss_sources(scene, what: str) -> str:
    from modalfe.scene.materials import material_loss

    parts = {}
    for part in scene.assembly().parts:
        name = scene.material(part.material).name
        loss = material_loss(name)
        if loss is not None and getattr(loss, what) is not None:
            parts[name] = f"{name} {what} {getattr(loss, what):g}: {loss.source}"
    return "; ".join(parts.values())


# per-material stiffness of each live model, by the materials asked: ``forced`` and ``admittance`` read the modal
# strain energy of every mode on every estimate level, and each assembly of a quartic model's ceramics cost as much
# as a solve's Lanczos run (dropped with the model, or by ``modalfe.caches.clear``)
_MATERIAL_STIFFNESS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
caches.register("per-material stiffness", _MATERIAL_STIFFNESS.clear)


def material_stiffness(model, names) -> dict[str, sp.csr_matrix]:
    """(n_u, n_u) elastic stiffness K_uu of the parts made of each material in ``names`` (solid model), for the
    modal strain energy U_m = u^T K_m u / 2; assembled once per model and set of names."""
    if not _per_part(model):
        raise SolverError("material losses: need the 3-D solid model or the axisymmetric one")
    kept = _MATERIAL_STIFFNESS.setdefault(model, {})
    key = frozenset(names)
    if key not in kept:
        kept[key] = _assembled_material_stiffness(model, key)
    return kept[key]


def _per_part(model) -> bool:
    """Whether ``model`` assembles its parts' stiffness alone: the 3-D solid, the axisymmetric model."""
    from modalfe.models.axisymmetric import AxisymmetricModel

    return hasattr(model, "u_basis") or isinstance(model, AxisymmetricModel)


def _assembled_material_stiffness(model, names: frozenset) -> dict[str, sp.csr_matrix]:
    from modalfe.models.axisymmetric import AxisymmetricModel
    from modalfe.models.solid import parts_matrices

    scene = model.scene
    made_of: dict[str, set[str]] = {}
    for part in scene.assembly().parts:
        made_of.setdefault(scene.material(part.material).name, set()).add(part.name)
    assembled = model.parts_stiffness if isinstance(model, AxisymmetricModel) else \
        (lambda parts: parts_matrices(model, parts)[0])
    return {name: assembled(made_of[name]) for name in names if name in made_of}


def qm_table(model) -> dict[str, float]:
    """Material name -> Qm for the scene's materials with a sourced Qm."""
    from modalfe.scene.materials import material_loss

    out = {}
    for part in model.scene.assembly().parts:
        name = model.scene.material(part.material).name
        loss = material_loss(name)
        if loss is not None and loss.Qm is not None:
            out[name] = loss.Qm
    return out


def fallback_eta(spec: str, omega: np.ndarray) -> np.ndarray:
    """Loss factor equivalent at resonance (eta = 2 zeta = 1 / Q) of a spec, per angular frequency."""
    kind, v = loss_spec("drive.damping", spec)
    if kind == "eta":
        return np.full_like(omega, v[0])
    if kind == "zeta":
        return np.full_like(omega, 2 * v[0])
    if kind == "rayleigh":
        return v[0] / omega + v[1] * omega
    raise SceneError("drive.damping: 'material' cannot be its own fallback")


def modal_losses(modes_list, model, losses: Losses) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """(c_r, h_r, descriptions): d_r = omega_r^2 - omega^2 + i (c_r omega + h_r), viscous c_r = 2 zeta_r
    omega_r, hysteretic h_r = eta_r omega_r^2, per mode."""
    from modalfe.scene.scene import check_underdamped

    omega = np.array([m.omega for m in modes_list])
    c, h = np.zeros(len(omega)), np.zeros(len(omega))
    text = [""] * len(omega)
    kind, v = loss_spec("--damping", losses.mechanical)
    if kind != "material":
        c[:], h[:] = _viscous_hysteretic(kind, v, omega)
    else:
        qm = qm_table(model)
        stiff = material_stiffness(model, set(qm))
        n_u = model.n_u
        eta = np.zeros(len(omega))
        covered = np.zeros(len(omega))
        if modes_list:  # every mode in one sparse product per matrix (a product per mode read K once per mode)
            X = np.column_stack([m.shape for m in modes_list])
            X[n_u:] = 0.0  # u^T K_uu u as x^T K x: slicing K_uu out of the quartic Cu-Be plate's K took 0.9 s
            U = X[:n_u]
            total = np.einsum("ij,ij->j", X, model.K @ X)
            for name, K_m in stiff.items():
                frac = np.einsum("ij,ij->j", U, K_m @ U) / total
                eta += frac / qm[name]
                covered += frac
        eta += (1 - covered) * fallback_eta(losses.fallback, omega)
        h[:] = eta * omega**2
        text = [f"eta {e:.3g} ({100 * f:.0f} % of the strain energy in materials with Qm)"
                for e, f in zip(eta, covered)]
    for i, m in enumerate(modes_list):
        if m.label in losses.per_mode:
            k2, v2 = loss_spec(f"--mode-damping {m.label}", losses.per_mode[m.label])
            c[i], h[i] = _viscous_hysteretic(k2, v2, omega[i])
            text[i] = f"{losses.per_mode[m.label]} (per mode)"
        if not text[i]:
            text[i] = f"zeta {c[i] / (2 * omega[i]):.3g}" if c[i] else f"eta {h[i] / omega[i] ** 2:.3g}"
        field_name = f"--mode-damping {m.label}" if m.label in losses.per_mode else "--damping"
        check_underdamped(field_name, c[i] / (2 * omega[i]) + h[i] / (2 * omega[i] ** 2),
                          f" at mode {m.label} ({m.frequency:.6g} Hz)")
    unknown = set(losses.per_mode) - {m.label for m in modes_list}
    if unknown:
        raise SceneError(f"--mode-damping: no mode labelled {sorted(unknown)} among "
                         f"{[m.label for m in modes_list]}")
    return c, h, text


def _viscous_hysteretic(kind: str, v: tuple[float, ...], omega) -> tuple:
    """(c, h) of d = omega_r^2 - omega^2 + i (c omega + h) at ``omega`` = omega_r for a zeta, rayleigh or eta spec."""
    zero = 0 * omega
    if kind == "zeta":
        return 2 * v[0] * omega, zero
    if kind == "rayleigh":
        return v[0] + v[1] * omega**2, zero
    return zero, v[0] * omega**2
