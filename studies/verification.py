"""Verification table: the 3-D solid model against analytic theory, case by case.

Prints, for each case, the analytic value, the FE value, their difference, the DOFs and the
solve time, at the mesh of the tests (``--quick``) and at finer meshes (default): cantilever vs
Timoshenko and Euler-Bernoulli, diaphragm-supported plates vs Kirchhoff, Mindlin and the exact
3-D (Rayleigh-Lamb) frequency, the observed convergence order, the k31 PZT bar's fr, fa and
k_eff, and invariance under a rotation of the whole model; then the seed 002 / 003 hand
formulas against the seeds' numbers.

    python studies/verification.py --quick     # ~20 s idle, the meshes of tests/models/test_verification.py
    python studies/verification.py             # ~3 minutes, adds one or two refinements per case
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

from modalfe.scene.materials import MATERIALS
from modalfe.solve.api import solve_modes
from tests.oracles import analytic

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests.oracles
from tests.oracles.cases import cantilever_scene, diaphragm_plate_scene, k31_bar_scene

CUBE = {"E": 123e9, "nu": 0.30, "rho": 8250.0}  # modalfe.scene.materials "CuBe" (seed 001)
BRASS = {"E": 105e9, "nu": 0.34, "rho": 8500.0}  # modalfe.scene.materials "brass-seed003" (seed 003)
THIN = (0.040, 0.030, 0.5e-3)
THICK = (0.020, 0.016, 2.0e-3)
CONVERGENCE = (0.012, 0.010, 2.0e-3)
PLATE_MODES = [(1, 1), (2, 1), (1, 2), (2, 2), (3, 1)]
SEED_003_MODE6 = 24221.0  # Hz, seed 003, Euler-Bernoulli theory of the ciliary beam
SEED_002_F1 = 845.0  # Hz, seed 002, eq. (5)
SEED_002_F0 = 49.0  # Hz, seed 002, sec. 4.3


def rotation() -> np.ndarray:
    """Euler z-y-x (37, -23, 61) degrees: a generic rotation."""
    z, y, x = np.radians([37.0, -23.0, 61.0])
    Rz = np.array([[np.cos(z), -np.sin(z), 0], [np.sin(z), np.cos(z), 0], [0, 0, 1]])
    Ry = np.array([[np.cos(y), 0, np.sin(y)], [0, 1, 0], [-np.sin(y), 0, np.cos(y)]])
    Rx = np.array([[1, 0, 0], [0, np.cos(x), -np.sin(x)], [0, np.sin(x), np.cos(x)]])
    return Rz @ Ry @ Rx


def timed_solve(scene, **kwargs):
    start = time.perf_counter()
    modes = solve_modes(scene, error_estimate=False, **kwargs)
    return modes, time.perf_counter() - start


class Table:
    """Rows of case, quantity, analytic [Hz or -], FE, difference, DOFs, time [s]."""

    def __init__(self) -> None:
        self.rows: list[tuple] = []
        self.notes: list[str] = []

    def add(self, case: str, quantity: str, reference: float, fe: float, dofs: int | str,
            seconds: float | None, unit: str = "Hz") -> None:
        self.rows.append((case, quantity, reference, fe, fe / reference - 1, dofs, seconds, unit))

    def print(self) -> None:
        head = f"{'case':<28} {'quantity':<28} {'analytic':>13} {'FE':>13} {'diff':>10} {'DOFs':>8} {'time':>7}"
        print(head)
        print("-" * len(head))
        for case, quantity, ref, fe, diff, dofs, seconds, unit in self.rows:
            fmt = ".2f" if unit == "Hz" else ".5f"
            sec = f"{seconds:6.1f}s" if seconds is not None else "      -"
            # relative differences below 1e-6 (rotation checks) in scientific notation
            shown = f"{100 * diff:>+9.4f}%" if abs(diff) >= 1e-6 else f"{diff:>+9.1e} "
            print(f"{case:<28} {quantity:<28} {ref:>13{fmt}} {fe:>13{fmt}} {shown} {dofs!s:>8} {sec}")
        print()
        for note in self.notes:
            print(note)
        print()


def bending(modes, order: int, near: float):
    found = [m for m in modes if m.label in (f"bending-z {order}", f"bending-y {order}")]
    return min(found, key=lambda m: abs(m.frequency - near))


def axial(modes, near: float):
    return min((m for m in modes if m.label.startswith("axial")), key=lambda m: abs(m.frequency - near))


def cantilever_cases(table: Table, sizes: list[float]) -> None:
    E, nu, rho = BRASS["E"], BRASS["nu"], BRASS["rho"]
    section = {"length": 0.1, "E": E, "rho": rho, "area": 25e-6, "inertia": 5e-3**4 / 12}
    tim = analytic.timoshenko_cantilever(**section, G=E / (2 * (1 + nu)),
                                         kappa=analytic.cowper_shear_coefficient_rectangle(nu), count=6)
    eb = analytic.euler_bernoulli_cantilever(**section, count=6)
    for size in sizes:
        modes, seconds = timed_solve(cantilever_scene(size))
        case = f"cantilever h={size * 1e3:g}mm"
        for n in range(1, 7):
            table.add(case, f"bending {n} vs Timoshenko", tim[n - 1], bending(modes, n, tim[n - 1]).frequency,
                      modes.dofs, seconds if n == 1 else None)
        table.add(case, "bending 1 vs Euler-Bernoulli", eb[0], bending(modes, 1, eb[0]).frequency, modes.dofs, None)
        table.add(case, "bending 6 vs Euler-Bernoulli", eb[5], bending(modes, 6, tim[5]).frequency, modes.dofs, None)
        table.add(case, "bending 6 vs seed 003 (EB)", SEED_003_MODE6, bending(modes, 6, tim[5]).frequency,
                  modes.dofs, None)


def plate_references(dims) -> dict:
    a, b, h = dims
    return {mn: {"Kirchhoff": analytic.kirchhoff_plate_ss(*mn, a=a, b=b, h=h, **CUBE),
                 "Mindlin": analytic.mindlin_plate_ss(*mn, a=a, b=b, h=h, **CUBE),
                 "exact 3-D": analytic.rayleigh_lamb_plate_ss(*mn, a=a, b=b, h=h, **CUBE)}
            for mn in PLATE_MODES}


def plate_solve(dims, max_size: float, size_factor: float = 1.0):
    a, b, h = dims
    refs = plate_references(dims)
    near = 0.5 * (refs[(1, 1)]["exact 3-D"] + refs[(2, 2)]["exact 3-D"])
    return timed_solve(diaphragm_plate_scene(a, b, h, max_size), near=near, count=10, size_factor=size_factor)


def plate_cases(table: Table, name: str, dims, levels: list[tuple[float, float]], theory: str) -> None:
    refs = plate_references(dims)
    for max_size, factor in levels:
        modes, seconds = plate_solve(dims, max_size, factor)
        case = f"{name} {modes.model.mesh.nelements} el"
        for i, (mn, ref) in enumerate(refs.items()):
            fe = modes.labelled(f"({mn[1] - 1},{mn[0] - 1})", near=ref["exact 3-D"]).frequency
            table.add(case, f"{mn} vs {theory}", ref[theory], fe, modes.dofs, seconds if i == 0 else None)
            table.add(case, f"{mn} vs exact 3-D", ref["exact 3-D"], fe, modes.dofs, None)


def convergence_case(factors: list[float]) -> None:
    refs = plate_references(CONVERGENCE)
    print("observed convergence order, diaphragm plate 12 x 10 x 2 mm, uniform refinement")
    print(f"{'size factor':>11} {'DOFs':>8} {'time':>7} {'error (1,1)':>12} {'error (2,1)':>12} "
          f"{'order (1,1)':>11} {'order (2,1)':>11}")
    previous = None
    for factor in factors:
        modes, seconds = plate_solve(CONVERGENCE, 2e-3, factor)
        errors = np.array([modes.labelled(f"({mn[1] - 1},{mn[0] - 1})", near=refs[mn]["exact 3-D"]).frequency
                           / refs[mn]["exact 3-D"] - 1 for mn in [(1, 1), (2, 1)]])
        orders = np.log(previous / errors) / np.log(2) if previous is not None else [math.nan] * 2
        print(f"{factor:>11g} {modes.dofs:>8} {seconds:>6.1f}s {errors[0]:>12.3e} {errors[1]:>12.3e} "
              f"{orders[0]:>11.3f} {orders[1]:>11.3f}")
        previous = errors
    print("theory: O(h^4) for quadratic elements (Strang & Fix 1973)")


def k31_cases(table: Table, sizes: list[float]) -> None:
    mat = MATERIALS["PZT-5A"]
    ref = analytic.k31_bar(length=0.03, c_E=mat.C, e=mat.e, eps_S=mat.eps_S, rho=mat.rho)
    for size in sizes:
        short, t_short = timed_solve(k31_bar_scene(size), circuit="short")
        open_, t_open = timed_solve(k31_bar_scene(size), circuit="open")
        fr, fa = axial(short, ref.fr).frequency, axial(open_, ref.fa).frequency
        case = f"k31 bar PZT-5A h={size * 1e3:g}mm"
        table.add(case, "fr (short) vs 1-D", ref.fr, fr, short.dofs, t_short)
        table.add(case, "fa (open) vs 1-D", ref.fa, fa, open_.dofs, t_open)
        table.add(case, "k_eff vs 1-D", ref.k_eff, analytic.k_eff(fr, fa), "-", None, unit="-")
    s = np.linalg.inv(mat.C)
    nu12, nu13 = -s[0, 1] / s[0, 0], -s[0, 2] / s[0, 0]
    shift = -((math.pi / 0.03) ** 2) * (nu12**2 * 2e-3**2 + nu13**2 * 1e-3**2) / 24
    table.notes.append(f"k31 bar: Rayleigh's lateral-inertia shift of fr {100 * shift:+.4f}% "
                       "(the model error of the 1-D fr; FE vs 1-D above)")


def rotation_cases(table: Table) -> None:
    R = rotation()
    for name, scene, kwargs in [
        ("k31 bar short", k31_bar_scene(1e-3), {"circuit": "short"}),
        ("k31 bar open", k31_bar_scene(1e-3), {"circuit": "open"}),
        ("cantilever", cantilever_scene(2.5e-3), {}),
    ]:
        plain, t_plain = timed_solve(scene, **kwargs)
        rotated, t_rotated = timed_solve(scene, frame=R, **kwargs)
        worst = int(np.argmax(np.abs(rotated.frequencies / plain.frequencies - 1)))
        table.add(f"rotation: {name}", f"worst of {len(plain)} modes", plain.frequencies[worst],
                  rotated.frequencies[worst], plain.dofs, t_plain + t_rotated)


def seed_formula_cases(table: Table) -> None:
    k = analytic.sandwich_plate_wavenumber(0.304)
    f1 = analytic.sandwich_plate_frequency(k=k, E_f=60e9, t_f=0.083e-2, h=0.025, rho=170.0)
    f1_254 = analytic.sandwich_plate_frequency(k=k, E_f=60e9, t_f=0.083e-2, h=0.0254, rho=170.0)
    f0 = analytic.suspension_frequency(E=2.0e6, area=8e-4, height=0.025, mass=2.7)
    eb6 = analytic.euler_bernoulli_cantilever(length=0.1, E=BRASS["E"], rho=BRASS["rho"], area=25e-6,
                                              inertia=5e-3**4 / 12, count=6)[5]
    table.add("seed 002 eq. (5)", "f1, h = 2.5 cm (as stated)", SEED_002_F1, f1, "-", None)
    table.add("seed 002 eq. (5)", "f1, h = 2.54 cm (panel)", SEED_002_F1, f1_254, "-", None)
    table.add("seed 002 sec. 4.3", "f0 lumped suspension", SEED_002_F0, f0, "-", None)
    table.add("seed 003", "EB mode 6, uniform beam", SEED_003_MODE6, eb6, "-", None)
    dz = analytic.suspension_static_deflection(force=1000.0, E=2.0e6, area=8e-4, height=0.025)
    table.notes.append(f"seed 002 sec. 4.3: dz = F h / (E A) = {dz * 1e3:.2f} mm at 1000 N on one mount "
                       f"({dz / 4 * 1e3:.2f} mm shared by four); the seed quotes 4.5 mm")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="only the meshes of the tests (~20 s)")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    table = Table()
    cantilever_cases(table, [2.5e-3] if args.quick else [2.5e-3, 1.25e-3, 0.625e-3])
    plate_cases(table, "thin plate h/a=0.0125", THIN,
                [(THIN[0] / 24, 1.0)] + ([] if args.quick else [(THIN[0] / 48, 1.0)]), "Kirchhoff")
    plate_cases(table, "thick plate h/a=0.1", THICK,
                [(2e-3, 0.5)] + ([] if args.quick else [(2e-3, 0.25)]), "Mindlin")
    k31_cases(table, [1e-3] if args.quick else [1e-3, 0.5e-3])
    rotation_cases(table)
    seed_formula_cases(table)
    table.print()
    convergence_case([1.0, 0.5, 0.25])
    print(f"total {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
