"""SuperLU against PARDISO on the shift-invert matrices of the solid models (issue 6, item 4).

For each device and size factor the solid model is assembled and constrained as ``solve_level`` does
(``modalfe.models.build.build_model``, ``model.constraints(circuit)``), then, with each direct solver,
``modalfe.solve.eigen.eigenpairs`` runs one full eigen solve: factorization of A - sigma B (timed on its own)
and the ARPACK shift-invert iterations. Medians over ``--repeats`` (solvers alternate within a repeat),
the SuperLU / PARDISO time ratio per size, the power-law exponent of each solver's time against DOFs, and
the largest relative difference between the two solvers' frequencies. Layers through the thickness scale
with the size factor as in ``benchmark_fidelity.py``. CHOLMOD (scikit-sparse) and MUMPS are tried by
import and listed as not installed when that fails.

    python studies/benchmark_solvers.py [--quick] [--repeats 3] [--devices cube_plate ciliary_beam] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import importlib
import statistics
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from benchmark_fidelity import level_scene, positive_factor, power_law_exponent

DEVICES = ("cube_plate", "ciliary_beam")
SIZE_FACTORS = (2.25, 1.5, 1.0, 0.75)
QUICK_FACTORS = (2.25, 1.5)
OTHERS = {"cholmod": "sksparse.cholmod", "mumps": "mumps"}  # solvers modalfe does not use, by module


@dataclass(frozen=True)
class Timing:
    """Medians over repeats for one matrix and solver [s], and the frequencies found [Hz]."""

    device: str
    size_factor: float
    dofs: int
    nnz: int
    solver: str
    factorization: float
    eigensolve: float
    frequencies: np.ndarray

    @property
    def total(self) -> float:
        return self.factorization + self.eigensolve


def shift_invert_problem(device: str, size_factor: float):
    """(A, B, analysis) of the device's constrained solid model at ``size_factor``."""
    from modalfe.models.build import build_model

    scene = level_scene(device, size_factor)
    model, _ = build_model(scene, size_factor=size_factor)
    T = model.constraints(scene.analysis.circuit).T
    return (T.T @ model.K @ T).tocsr(), (T.T @ model.M @ T).tocsr(), scene.analysis


def time_solvers(device: str, size_factor: float, solvers: list[str], repeats: int) -> list[Timing]:
    """Each solver's median factorization and eigen-solve seconds on one matrix pair."""
    from modalfe.solve.eigen import eigenpairs

    A, B, analysis = shift_invert_problem(device, size_factor)
    runs = {name: [] for name in solvers}
    for _ in range(repeats):
        for name in solvers:
            solution = eigenpairs(A, B, analysis, name)
            lam, used = solution.values, solution.solver
            t_fact, t_eig = solution.factorization_seconds, solution.eigensolve_seconds
            if used != name:
                raise RuntimeError(f"asked for {name}, eigenpairs used {used}")
            runs[name].append((t_fact, t_eig, np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)))
    return [Timing(device, size_factor, A.shape[0], A.nnz, name, statistics.median(r[0] for r in rs),
                   statistics.median(r[1] for r in rs), rs[0][2]) for name, rs in runs.items()]


def frequency_difference(a: Timing, b: Timing) -> float:
    """Largest relative difference between two solvers' frequencies of the same problem (non-rigid modes)."""
    if len(a.frequencies) != len(b.frequencies):
        return float("inf")
    top = max(a.frequencies.max(), b.frequencies.max())
    keep = a.frequencies > 1e-6 * top
    return float(np.max(np.abs(b.frequencies[keep] / a.frequencies[keep] - 1), initial=0.0))


def not_installed() -> list[str]:
    """The other sparse direct solvers whose Python package does not import here."""
    missing = []
    for name, module in OTHERS.items():
        try:
            importlib.import_module(module)
        except ImportError:
            missing.append(name)
    return missing


def conclusion(rows: list[tuple[Timing, Timing]]) -> str:
    """What the measured ratios say about the default (PARDISO when MKL loads, else SuperLU)."""
    worst = max(frequency_difference(s, p) for s, p in rows)
    ratio = {(s.device, s.size_factor, s.dofs): s.total / p.total for s, p in rows}
    nearest = min((f for _, f, _ in ratio), key=lambda f: abs(np.log(f)))
    default = [k for k in ratio if k[1] == nearest]
    largest = max(ratio, key=lambda k: k[2])

    def listed(keys) -> str:
        return ", ".join(f"{d} x{f:g} ({n} DOFs) {ratio[(d, f, n)]:.2f}" for d, f, n in keys) or "none"

    wins = [k for k in ratio if ratio[k] > 1]
    verdict = "is supported" if all(ratio[k] > 1 for k in [*default, largest]) else "is not supported"
    return (f"PARDISO faster at {len(wins)} of {len(ratio)} sizes; SuperLU / PARDISO time at the size factor "
            f"nearest the default: {listed(default)}; at the largest: {listed([largest])}; SuperLU as fast or "
            f"faster at: {listed(k for k in ratio if k not in wins)}; frequencies agree to {worst:.1e} relative. "
            f"The default (PARDISO when MKL loads, SuperLU fallback) {verdict} by these numbers.")


def write_csv(rows: list[tuple[Timing, Timing]], path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as fh:
        out = csv.writer(fh)
        out.writerow(["device", "size_factor", "dofs", "nnz", "solver", "factorization_s", "eigensolve_s", "total_s",
                      "max_rel_frequency_difference"])
        for pair in rows:
            for t in pair:
                out.writerow([t.device, t.size_factor, t.dofs, t.nnz, t.solver, f"{t.factorization:.4g}",
                              f"{t.eigensolve:.4g}", f"{t.total:.4g}", f"{frequency_difference(*pair):.2e}"])


@dataclass(frozen=True)
class Comparison:
    """(SuperLU, PARDISO) timings per matrix, exponents per solver and stage, the printed conclusion."""

    rows: list[tuple[Timing, Timing]]
    exponents: dict[str, dict[str, float]]
    conclusion: str


def run(devices, factors, repeats: int, out: Path) -> Comparison | None:
    """Time both solvers on every matrix; None when PARDISO is not available here."""
    from modalfe.solve.linalg import available_solvers

    if "pardiso" not in available_solvers():
        return None
    rows = []
    for device in devices:
        for factor in factors:
            superlu, pardiso = time_solvers(device, factor, ["superlu", "pardiso"], repeats)
            rows.append((superlu, pardiso))
            print(f"  {device:<13} x{factor:<5g} {superlu.dofs:>7d} DOFs  superlu {superlu.total:7.2f} s  "
                  f"pardiso {pardiso.total:7.2f} s")
    exponents = {name: {stage: power_law_exponent([pair[i].dofs for pair in rows],
                                                  [getattr(pair[i], stage) for pair in rows])
                        for stage in ("factorization", "eigensolve", "total")}
                 for i, name in enumerate(("superlu", "pardiso"))}
    write_csv(rows, out / "benchmark_solvers.csv")
    return Comparison(rows, exponents, conclusion(rows))


def format_comparison(result: Comparison) -> str:
    lines = [f"{'device':<13} {'size':>5} {'DOFs':>7} {'nnz':>9} {'SuperLU fact':>12} {'eig':>7} "
             f"{'PARDISO fact':>12} {'eig':>7} {'ratio':>6} {'max df/f':>9}"]
    for s, p in result.rows:
        lines.append(f"{s.device:<13} {s.size_factor:>5g} {s.dofs:>7d} {s.nnz:>9d} {s.factorization:>12.3f} "
                     f"{s.eigensolve:>7.3f} {p.factorization:>12.3f} {p.eigensolve:>7.3f} {s.total / p.total:>6.2f} "
                     f"{frequency_difference(s, p):>9.1e}")
    lines.append("ratio = SuperLU / PARDISO time of factorization plus eigen solve (medians)")
    for name, fit in result.exponents.items():
        lines.append(f"exponent vs DOFs, {name:<8} " + "  ".join(f"{k} {v:.2f}" for k, v in fit.items()))
    lines.append(result.conclusion)
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> Comparison | None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="ciliary_beam only, two coarse sizes, 1 repeat")
    parser.add_argument("--repeats", type=int, help="eigen solves per solver and size (default 3, 1 with --quick)")
    parser.add_argument("--devices", nargs="+", choices=DEVICES, help="default: both")
    parser.add_argument("--factors", nargs="+", type=positive_factor, help=f"size factors (default {SIZE_FACTORS})")
    parser.add_argument("--out", default="studies/out/benchmark_solvers", help="folder for the CSV")
    args = parser.parse_args(argv)
    repeats = args.repeats if args.repeats is not None else 1 if args.quick else 3
    if repeats < 1:
        parser.error(f"--repeats must be at least 1, got {repeats}")
    devices = args.devices or (("ciliary_beam",) if args.quick else DEVICES)
    factors = args.factors or (QUICK_FACTORS if args.quick else SIZE_FACTORS)
    for name in not_installed():
        print(f"{name}: not installed")
    print(f"solver benchmark: {', '.join(devices)} at size factors {', '.join(f'{f:g}' for f in factors)}; "
          f"medians of {repeats}")
    result = run(devices, factors, repeats, Path(args.out))
    if result is None:
        print("pardiso: not available (MKL did not load): nothing to compare, SuperLU is the only solver")
        return None
    print(format_comparison(result))
    print(f"wrote {Path(args.out) / 'benchmark_solvers.csv'}")
    return result


if __name__ == "__main__":
    main()
