"""The mode table: per mode its frequency, label, error estimate, effective modal masses and participation
factors in x, y and z, fr / fa and k_eff, and the modal force per volt of the driven electrodes.

For a mass-normalised mode phi_r (phi^T M phi = 1) and the rigid translation r_d (unit displacement along d on
every displacement unknown, clamped ones included): participation factor Gamma_r,d = phi_r^T M r_d [kg^0.5],
effective modal mass m_r,d = Gamma_r,d^2 [kg], whose sum over all modes of an unsupported or spring-supported
body is the total mass r_d^T M r_d (Chopra, Dynamics of Structures, 4th ed. 2012, sec. 13.2.5; Craig & Kurdila
2006, sec. 11.5). Modal force per volt theta_r = phi_r . f_1V [N/(V kg^0.5)]; referred to the point of largest
displacement (modal mass 1 / max|phi|^2 there) it is the force factor N_r = theta_r / max|phi_u| [N/V], as in
``modalfe forced``. k_eff = sqrt(1 - fr^2 / fa^2) (IEEE Std 176-1987, eq. 100). A half or quarter model's masses
and fractions are those of the solved part.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from modalfe.errors import SolverError
from modalfe.response.loads import rigid_translations
from modalfe.results.coupling import k_eff
from modalfe.results.labels import RIGID_FRACTION

CSV_COLUMNS = (
    "index", "label", "frequency_Hz", "error_estimate_rel", "meff_x_kg", "meff_y_kg", "meff_z_kg",
    "cum_fraction_x", "cum_fraction_y", "cum_fraction_z", "gamma_x_sqrtkg", "gamma_y_sqrtkg", "gamma_z_sqrtkg",
    "fa_Hz", "k_eff", "theta_N_per_V_sqrtkg", "force_factor_N_per_V",
    "meff_error_rel", "fa_error_rel", "k_eff_error_rel", "force_factor_error_rel",
)
UNCOUPLED = 1e-3  # k_eff below this: a mode the electrodes do not drive, its k_eff and force factor given no error
SIGNIFICANT_MASS = 1e-3  # effective masses below this fraction of the total are not given an error (noise-level)


@dataclass(frozen=True)
class ModeTable:
    """Rows (one dict per mode, keys ``CSV_COLUMNS``), total_mass [kg] per direction (the solved part),
    scene, dofs, notes."""

    scene: str
    rows: tuple[dict, ...]
    total_mass: dict[str, float]
    dofs: int
    notes: tuple[str, ...] = ()

    def to_json(self) -> dict:
        return {"scene": self.scene, "dofs": self.dofs, "total_mass_kg": self.total_mass, "notes": list(self.notes),
                "modes": [{k: _clean(v) for k, v in r.items()} for r in self.rows]}

    def write_csv(self, path) -> None:
        import csv

        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(CSV_COLUMNS)
            for r in self.rows:
                w.writerow(["" if _clean(r[c]) is None else (f"{r[c]:.10g}" if isinstance(r[c], float) else r[c])
                            for c in CSV_COLUMNS])

    def format(self) -> str:
        lines = [f"{self.scene}: {len(self.rows)} modes, {self.dofs} DOFs; total mass x/y/z "
                 + " / ".join(f"{1e3 * self.total_mass[d]:.4g}" for d in "xyz") + " g"]
        lines += [f"note: {n}" for n in self.notes]
        lines.append(f"{'#':>3} {'f [Hz]':>11} {'label':<13} {'err':>7} {'meff x/y/z [g]':>26} "
                     f"{'cum % x/y/z':>17} {'fa [Hz]':>11} {'k_eff':>6} {'N [N/V]':>9}  "
                     f"{'err meff/fa/k_eff/N':>25}")
        for r in self.rows:
            err = "n/a" if _clean(r["error_estimate_rel"]) is None else f"{100 * r['error_estimate_rel']:.2f}%"
            meff = " ".join(f"{1e3 * r[f'meff_{d}_kg']:8.3g}" for d in "xyz")
            cum = " ".join(f"{100 * r[f'cum_fraction_{d}']:5.1f}" for d in "xyz")
            fa = "-" if r["fa_Hz"] is None else f"{r['fa_Hz']:.1f}"
            k = "-" if r["k_eff"] is None else f"{r['k_eff']:.3f}"
            n = "-" if r["force_factor_N_per_V"] is None else f"{r['force_factor_N_per_V']:.3g}"
            errors = "/".join(_percent(r[c]) for c in CSV_COLUMNS[-4:])
            lines.append(f"{r['index']:>3} {r['frequency_Hz']:>11.1f} {r['label']:<13} {err:>7} {meff:>26} "
                         f"{cum:>17} {fa:>11} {k:>6} {n:>9}  {errors:>25}")
        return "\n".join(lines)


def _percent(error) -> str:
    if error is None:
        return "-"
    return "?" if math.isnan(error) else "inf" if math.isinf(error) else f"{100 * error:.2g}%"


def _clean(v):
    return None if isinstance(v, float) and not math.isfinite(v) else v


def effective_masses(modes) -> tuple[np.ndarray, np.ndarray]:
    """(Gamma (n_modes, 3) [kg^0.5], total mass (3,) [kg]) of mass-normalised ``modes`` of one model."""
    model = modes.model
    R = rigid_translations(model)
    MR = (model.M @ R.T)  # (ndofs, 3)
    Phi = np.column_stack([m.shape for m in modes]) if len(modes) else np.zeros((model.ndofs, 0))
    return Phi.T @ MR, np.einsum("ij,ji->i", R, MR)


def mode_table(scene, *, near: float | None = None, count: int | None = None,
               band: tuple[float, float] | None = None, **resolution) -> ModeTable:
    """The mode table of ``scene`` (3-D solid, or the axisymmetric model where auto answers with it or it is asked:
    its n >= 1 modes stand for pairs, meff_y the twin's): ``count`` modes nearest ``near`` [Hz] or every mode in
    ``band`` (default: the scene's analysis), the answer ``modes`` gives for that question at ``resolution``
    (``solve_modes``' tol, fidelity, error_estimate). fa and k_eff of each mode from the open circuit of its model,
    its partner by shape, as ``forced``, ``admittance`` and the API give them (``modalfe.response.forced.open_circuit``,
    one path). Each number of a row that depends on the
    discretization has its stated error from the frequencies' estimate levels (``derived_errors``)."""
    from modalfe.response.forced import open_circuit
    from modalfe.solve.api import REVOLVED, derived_errors, solid_modes

    short = solid_modes(scene, needs="the mode table", near=near, count=count, band=band, takes=REVOLVED,
                        **resolution)
    if band is None and near is None:
        band = scene.analysis.band
    model = short.model
    driven = "drive" in scene.electrodes.values() and model.n_phi > 0
    notes = [f"resolved: {short.resolution}"]
    if scene.symmetry:
        notes.append(f"solved on the part of the device on one side of its {'/'.join(scene.symmetry)} mid-plane(s): "
                     f"masses and fractions refer to the solved part, and the modes listed are the symmetric ones "
                     f"(the whole device's symmetric modes have no effective mass along "
                     f"{'/'.join(scene.symmetry)}; the solved part's value is listed)")
    if scene.antisymmetry:
        notes.append(f"solved on the part of the device on one side of its {'/'.join(scene.antisymmetry)} "
                     f"mid-plane(s), the modes antisymmetric about them: masses and fractions refer to the solved part "
                     f"(the whole device's modes antisymmetric about a plane have no effective mass along the plane's "
                     f"own directions; the solved part's value is listed)")
    notes.append("effective mass m = (phi^T M r_d)^2 for mass-normalised phi (Chopra 2012, sec. 13.2.5); "
                 "cumulative fractions of the total mass over the modes listed, in frequency order")
    if driven:
        notes.append("fa: the open-circuit mode of the same shape on the same model (largest mass-weighted MAC); "
                     "k_eff = sqrt(1 - fr^2/fa^2), IEEE Std 176-1987")
        load = model.voltage_load(1.0)
    else:
        notes.append("no driven electrode: no fa, k_eff or force factor")
    notes.append(f"err meff/fa/k_eff/N: stated errors from the frequency's estimate levels (meff: the largest over the "
                 f"directions holding {SIGNIFICANT_MASS:.1%} of the mass or more; none for the k_eff and N of a mode "
                 f"with k_eff < {UNCOUPLED:g}); ? not estimated, - not applicable")
    gamma, total = effective_masses(short)
    meff = gamma**2
    cum = np.cumsum(meff, axis=0) / np.where(total > 0, total, np.inf)
    def fa_of(m) -> float | None:
        """fa of ``m`` (of the answer or of an estimate level), or None where no open mode has its shape."""
        try:
            return open_circuit(m, among=short if m.model is model else short.estimate.level_holding(m)).fa
        except SolverError:
            return None

    translated: dict[int, np.ndarray] = {}  # (M R^T)^T of each model met (the answer and its estimate levels)
    highest = max((m.frequency**2 for m in short), default=0.0)

    def rigid(m) -> bool:
        """A free body's rigid-body mode (``RIGID_FRACTION``, as the labels name it): no fa or k_eff (both ~0 Hz, their
        ratio the solver's noise: a free bimorph's sway read k_eff 0.721)."""
        return m.frequency**2 < RIGID_FRACTION * highest

    def numbers(m) -> dict[str, float]:
        """The numbers of a row that depend on the discretization: effective masses, fa, k_eff, force factor."""
        shape = m.shape
        if id(m.model) not in translated:
            translated[id(m.model)] = (m.model.M @ rigid_translations(m.model).T).T
        g = translated[id(m.model)] @ shape
        out = {f"meff_{d}": float(g[k] ** 2) for k, d in enumerate("xyz")
               if g[k] ** 2 >= SIGNIFICANT_MASS * total[k]}
        if driven and not rigid(m):
            fa = fa_of(m)
            if fa is None:
                return out
            out.update(fa=fa, k_eff=k_eff(m.frequency, fa))
            theta = float(shape @ m.model.voltage_load(1.0))
            umax = float(np.max(np.abs(m.model.nodal_displacement(shape))))
            if umax > 0:
                out["force_factor"] = abs(theta) / umax
            if out["k_eff"] < UNCOUPLED:  # noise relative to nothing
                del out["k_eff"], out["force_factor"]
        return out

    rows = []
    for i, m in enumerate(short):
        fa = ke = theta = force = None
        fine = numbers(m)  # the row's fa and the numbers its errors are of, computed once
        if driven:
            fa = fine.get("fa")
            ke = k_eff(m.frequency, fa) if fa is not None else None
            theta = float(m.shape @ load)
            umax = float(np.max(np.abs(model.nodal_displacement(m.shape))))
            force = theta / umax if umax > 0 else None
        errors = derived_errors(short, m, numbers, fine, eigenvalues=("fa",)) if not rigid(m) else {}
        meff_errors = [e for name, (e, _) in errors.items() if name.startswith("meff_")]
        rows.append({
            "index": m.index, "label": m.label, "frequency_Hz": m.frequency, "error_estimate_rel": m.error_estimate,
            **{f"meff_{d}_kg": float(meff[i, k]) for k, d in enumerate("xyz")},
            **{f"cum_fraction_{d}": float(cum[i, k]) for k, d in enumerate("xyz")},
            **{f"gamma_{d}_sqrtkg": float(gamma[i, k]) for k, d in enumerate("xyz")},
            "fa_Hz": fa, "k_eff": ke, "theta_N_per_V_sqrtkg": theta, "force_factor_N_per_V": force,
            "meff_error_rel": max(meff_errors) if meff_errors else None,
            **{f"{name}_error_rel": errors[name][0] if name in errors else None
               for name in ("fa", "k_eff", "force_factor")},
        })
    return ModeTable(scene.name, tuple(rows), {d: float(total[k]) for k, d in enumerate("xyz")}, short.dofs,
                     tuple(notes))
