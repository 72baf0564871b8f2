"""modalfe against a peer FE code (NGSolve, quadratic tetrahedra): time to 0.1 % frequency error.

Two cases, the whole device in both codes (no symmetry planes, so both solve the same problem):

- ``plate``: Cu-Be plate 64 x 38 x 3 mm, free-free, the (0,6) bending mode near 36 kHz;
- ``beam``: the ciliary beam (brass cantilever, PZT-5A bimorph sheets, electrodes short-circuited),
  mode ``bending-z 6`` near 21.7 kHz, piezoelectric in both codes (u and phi, e-form).

Each code runs a refinement sweep: modalfe the size factor (structured quadratic hexahedra, layers
through the thickness refined alike; on the beam with ``mesh.clamp_grading`` = 4, geometric element
layers toward the clamp), NGSolve ``maxh`` (order-2 tetrahedra, straight-sided). The
geometry, materials, poling and supports of the peer model are read from the same modalfe scene.
Peer eigen solve: K and M are exported from NGSolve to scipy and solved with modalfe's own
shift-invert path (``modalfe.solve.eigen.eigenpairs``: PARDISO through ``modalfe.solve.linalg.factorize`` and
ARPACK), so the measured difference is the discretization, meshing and assembly, not the eigen
solver. NGSolve assembles inside its ``TaskManager``, as usually run.

Each point runs in its own process with ``--threads`` threads (1 by default, both codes: on a shared
machine threaded MKL and NGSolve were erratic), fresh mesh caches and peak RSS from ``ru_maxrss``,
after an untimed warm-up solve on the coarsest mesh that loads libraries; ``--repeats`` timed
solves, the median run quoted. The codes take turns, coarse to fine. Total time = wall time of the
whole solve (mesh, assembly, factorization, eigen solve, and picking the mode: modalfe's labels,
the peer's nodal-line count), split shown per stage.
Reference frequency per case: Richardson extrapolation f(N) = f_inf + c N^(-q) through modalfe's
three finest levels (cross-check: the same through NGSolve's). Time to 0.1 % is interpolated
log-log between the two sweep points bracketing 0.1 % error.

    python studies/benchmark_peer.py [--quick] [--repeats 3] [--threads 1] [--cases plate beam]
                                     [--out studies/out/benchmark_peer] [--results FILE.json]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from modalfe.geometry.parts import Assembly
    from modalfe.scene import Scene

TARGET = 1e-3  # accuracy target: relative discretization error of the mode's frequency


@dataclass(frozen=True)
class Case:
    """One benchmark problem: the mode (modalfe selector, Hz), its nodal-line signature for the peer
    and the two sweeps (modalfe size factors, NGSolve maxh [m]), full and ``--quick``."""

    selector: str
    near: float
    nodes_along: int  # sign changes of u_z along the long centre line
    check_across: bool  # also require no nodal line along the length (plate (0,n) modes)
    size_factors: tuple[float, ...]
    maxh: tuple[float, ...]
    quick_size_factors: tuple[float, ...]
    quick_maxh: tuple[float, ...]
    clamp_refinement: float | None = None  # peer: maxh / this on the clamp face (modalfe grades it too)


GRADING_LAYERS = 4  # beam case: element layers toward the clamp, sizes h 0.4^k (modalfe.models.mesh.graded_breaks)
# beam case, the peer's refinement at the clamp: local maxh h / 4 on the clamp face (netgen grades away from
# it); of h / 4 and h / 8 tried, h / 4 reached 0.1 % sooner (22k DOFs at h = 2 mm against 32k)
PEER_CLAMP_REFINEMENT = 4.0

CASES = {
    "plate": Case("(0,6)", 36e3, 6, True, (1.5, 1.0, 2 / 3, 4 / 9), (3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3),
                  (2.0, 1.5, 1.0), (6e-3, 4e-3, 3e-3)),
    "beam": Case("bending-z 6", 21.7e3, 5, False, (1.5, 1.0, 2 / 3, 4 / 9, 8 / 27),
                 (4e-3, 3e-3, 2e-3, 1.4e-3, 1e-3), (2.0, 1.5, 1.0), (6e-3, 4e-3, 3e-3), PEER_CLAMP_REFINEMENT),
}


def scene(case: str) -> Scene:
    """The modalfe scene of a case, whole (no symmetry)."""
    from modalfe.scene import load_scene, scene_from_dict

    if case == "beam":
        # graded layers toward the clamp (mesh.clamp_grading): the clamped edge's singularity otherwise
        # holds uniform refinement to order ~1.9 (docs/benchmark_peer.md)
        return load_scene("ciliary_beam", symmetry=(), **{"analysis.near": CASES[case].near,
                                                          "mesh.clamp_grading": GRADING_LAYERS})
    return scene_from_dict({
        "name": "cube_plate_bare",
        "parts": [{"name": "plate", "region": "plate", "material": "CuBe", "origin": [0, 0, 0],
                   "size": [64e-3, 38e-3, 3e-3]}],
        "analysis": {"near": CASES[case].near, "count": 8},
        "kind": "plate",
    })


def layers(size_factor: float) -> int:
    """Elements through the thickness at a size factor: 3 at 1, scaled like the in-plane size."""
    return max(2, round(3 / size_factor))


# ---- modalfe side ------------------------------------------------------------------------------

def modalfe_solve(case: str, size_factor: float) -> dict:
    """One modalfe solve: DOFs, stage times [s] and the case's mode frequency [Hz]."""
    from modalfe.results.modes import select
    from modalfe.solve.levels import solve_level

    sc = scene(case)
    start = time.perf_counter()
    modes = solve_level(sc, sc.analysis, size_factor=size_factor, solver="auto", min_layers=layers(size_factor))
    mode = select(modes, CASES[case].selector, CASES[case].near)
    total = time.perf_counter() - start
    stages = {k: modes.timings[k] for k in ("mesh", "assembly", "factorization", "eigensolve")}
    return {"dofs": modes.dofs, "frequency": mode.frequency, "total": total, **stages}


def _fresh_modalfe_caches(folder: Path) -> None:
    """Forget meshes and models (new cache ``folder``) so that a repeat meshes and assembles again."""
    import modalfe.models.mesh
    from modalfe.models.build import clear_cache

    os.environ["MODALFE_CACHE"] = str(folder)
    modalfe.models.mesh._memory_cache.clear()
    clear_cache()


# ---- peer side (NGSolve) -----------------------------------------------------------------------

def occ_shape(assembly: Assembly, local_maxh: dict[str, float] | None = None):
    """The assembly's boxes as one glued OCC shape; each solid's material name is its part name,
    face groups carry their names (electrodes, clamps); ``local_maxh``: face group -> maxh [m]."""
    from netgen.occ import Box, Glue, Pnt, X, Y, Z

    solids = {}
    for part in assembly.parts:
        box = Box(Pnt(*part.lo), Pnt(*part.hi))
        box.mat(part.name)
        solids[part.name] = box
    for group, faces in assembly.faces.items():
        for face in faces:
            if face.window is not None:
                raise NotImplementedError(f"face group {group}: windowed faces are not built for the peer")
            axis = {"x": X, "y": Y, "z": Z}[face.side[0]]
            faces_of = solids[face.part].faces
            named = faces_of.Min(axis) if face.side.endswith("min") else faces_of.Max(axis)
            named.name = group
            if local_maxh and group in local_maxh:
                named.maxh = local_maxh[group]
    return Glue(list(solids.values()))


def _voigt_strain(u):
    """Engineering strain (xx, yy, zz, yz, xz, xy) of a vector field."""
    from ngsolve import CF, Grad

    G = Grad(u)
    return CF((G[0, 0], G[1, 1], G[2, 2], G[1, 2] + G[2, 1], G[0, 2] + G[2, 0], G[0, 1] + G[1, 0]))


def peer_matrices(sc: Scene, mesh):
    """K, M (scipy CSR, free DOFs only), the space and the free DOF indices, for the scene's
    elastic and piezoelectric parts: electrodes grounded (phi = 0, short circuit), clamps fixed."""
    import scipy.sparse as sp
    from ngsolve import CF, H1, BilinearForm, Compress, Grad, InnerProduct, VectorH1, dx

    assembly = sc.assembly()
    if any(c != "xyz" for c in sc.clamps.values()):
        raise NotImplementedError("peer model: only fully clamped face groups")
    mats = {p.name: sc.material(p.material) for p in assembly.parts}
    mats = {name: (m.poled(p.poling) if m.is_piezoelectric else m)
            for (name, m), p in zip(mats.items(), assembly.parts)}
    piezo = [name for name, m in mats.items() if m.is_piezoelectric]
    C = mesh.MaterialCF({name: CF(tuple(m.C.ravel()), dims=(6, 6)) for name, m in mats.items()})
    rho = mesh.MaterialCF({name: m.rho for name, m in mats.items()})
    U = VectorH1(mesh, order=2, dirichlet="|".join(sc.clamps))
    if piezo:
        P = Compress(H1(mesh, order=2, definedon="|".join(piezo), dirichlet="|".join(sc.electrodes)))
        fes = U * P
        (u, phi), (v, psi) = fes.TnT()
        on = mesh.Materials("|".join(piezo))
        e = mesh.MaterialCF({name: CF(tuple(mats[name].e.ravel()), dims=(3, 6)) for name in piezo})
        eps = mesh.MaterialCF({name: CF(tuple(mats[name].eps_S.ravel()), dims=(3, 3)) for name in piezo})
        # e-form, E = -grad phi: T = c^E S + e^T grad phi, D = e S - eps^S grad phi
        k = BilinearForm(fes, symmetric=True)
        k += InnerProduct(C * _voigt_strain(u), _voigt_strain(v)) * dx
        k += (InnerProduct(e.trans * Grad(phi), _voigt_strain(v)) + InnerProduct(e * _voigt_strain(u), Grad(psi))
              - InnerProduct(eps * Grad(phi), Grad(psi))) * dx(definedon=on)
        m = BilinearForm(fes, symmetric=True)
        m += rho * InnerProduct(u, v) * dx
    else:
        fes = U
        u, v = fes.TnT()
        k = BilinearForm(InnerProduct(C * _voigt_strain(u), _voigt_strain(v)) * dx, symmetric=True)
        m = BilinearForm(rho * InnerProduct(u, v) * dx, symmetric=True)
    k.Assemble()
    m.Assemble()
    free = np.flatnonzero(np.array(fes.FreeDofs(), dtype=bool))

    def free_block(form):
        A = sp.csr_matrix(form.mat.CSR())  # NGSolve exports the whole matrix, also for symmetric forms
        return A[free][:, free]

    K, M = free_block(k), free_block(m)
    if piezo:  # potentials in scaled units, sqrt(mean K_uu / mean K_phiphi): PARDISO sees a balanced matrix
        d = np.abs(K.diagonal())
        is_phi = free >= U.ndof
        D = sp.diags(np.where(is_phi, np.sqrt(d[~is_phi].mean() / d[is_phi].mean()), 1.0))
        K, M = (D @ K @ D).tocsr(), (D @ M @ D).tocsr()
    return K, M, fes, free


def peer_pick(case: str, sc: Scene, mesh, fes, free: np.ndarray, lam: np.ndarray, X: np.ndarray) -> float:
    """Frequency [Hz] of the case's mode among the peer's eigenpairs, found by its nodal lines:
    u_z dominant on the long centre line with ``nodes_along`` sign changes (and, for a plate (0,n)
    mode, no sign change across the width); the one nearest the case's frequency."""
    from ngsolve import GridFunction, VectorH1

    c = CASES[case]
    coordinates = np.array(mesh.ngmesh.Coordinates())
    lo, hi = coordinates.min(0), coordinates.max(0)
    mid = (lo + hi) / 2
    main = sc.assembly().main_part
    mid[2] = (main.lo[2] + main.hi[2]) / 2
    xs = np.linspace(lo[0], hi[0], 161)[1:-1]
    gf = GridFunction(fes)
    disp = gf if isinstance(fes, VectorH1) else gf.components[0]  # (u, phi) on a piezo device

    def line(y: float) -> np.ndarray:
        return np.array(disp(mesh(xs, np.full_like(xs, y), np.full_like(xs, mid[2]))))

    width = hi[1] - lo[1]
    found = []
    for i, value in enumerate(lam):
        vec = np.zeros(fes.ndof)
        vec[free] = X[:, i]
        gf.vec.FV().NumPy()[:] = vec
        centre = line(mid[1])
        if np.abs(centre[:, 2]).max() < 2 * np.abs(centre[:, :2]).max():
            continue  # not a bending mode about y
        if _sign_changes(centre[:, 2]) != c.nodes_along:
            continue
        if c.check_across and any(np.dot(centre[:, 2], line(y)[:, 2]) <= 0 for y in (lo[1] + 0.1 * width,
                                                                                     hi[1] - 0.1 * width)):
            continue
        found.append(float(np.sqrt(max(value, 0.0)) / (2 * np.pi)))
    if not found:
        raise RuntimeError(f"peer: no {c.selector} mode among {len(lam)} near {c.near:g} Hz")
    return min(found, key=lambda f: abs(f - c.near))


def _sign_changes(values: np.ndarray) -> int:
    """Sign changes along a sampled line, ignoring values below 1 % of the peak (the clamped end)."""
    big = values[np.abs(values) > 0.01 * np.abs(values).max()]
    return int(np.count_nonzero(np.diff(np.sign(big))))


def peer_solve(case: str, maxh: float) -> dict:
    """One NGSolve solve at ``maxh`` [m]: DOFs, stage times [s] and the mode frequency [Hz]."""
    from netgen.occ import OCCGeometry
    from ngsolve import Mesh, SetNumThreads, TaskManager

    from modalfe.solve.eigen import eigenpairs

    sc = scene(case)
    SetNumThreads(int(os.environ.get("OMP_NUM_THREADS", "1")))
    start = time.perf_counter()
    with TaskManager():
        refine = CASES[case].clamp_refinement
        local = {g: maxh / refine for g in sc.clamps} if refine else None
        mesh = Mesh(OCCGeometry(occ_shape(sc.assembly(), local)).GenerateMesh(maxh=maxh))
        t_mesh = time.perf_counter() - start
        K, M, fes, free = peer_matrices(sc, mesh)
        t_assembly = time.perf_counter() - start - t_mesh
    solution = eigenpairs(K, M, sc.analysis)
    lam, X = solution.values, solution.vectors
    t_fact, t_eig = solution.factorization_seconds, solution.eigensolve_seconds
    frequency = peer_pick(case, sc, mesh, fes, free, lam, X)
    return {"dofs": K.shape[0], "frequency": frequency, "total": time.perf_counter() - start, "mesh": t_mesh,
            "assembly": t_assembly, "factorization": t_fact, "eigensolve": t_eig}


# ---- one sweep point in its own process --------------------------------------------------------

def point(code: str, case: str, level: float, warm: float | None, repeats: int) -> dict:
    """Median of ``repeats`` timed solves after one untimed warm-up solve at ``warm`` (None: none);
    peak RSS [MB]."""
    solve = modalfe_solve if code == "modalfe" else peer_solve
    runs = []
    with tempfile.TemporaryDirectory(prefix="modalfe-bench-") as root:
        for i in range(repeats + 1):
            if code == "modalfe":
                _fresh_modalfe_caches(Path(root) / str(i))
            if i:
                runs.append(solve(case, level))
            elif warm is not None:
                solve(case, warm)
    out = dict(sorted(runs, key=lambda r: r["total"])[len(runs) // 2])  # the median run, with its split
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def run_point(code: str, case: str, level: float, warm: float | None, repeats: int, threads: int) -> dict:
    """``point`` in a fresh interpreter with ``threads`` threads (MKL, OpenMP, NGSolve); its JSON result."""
    spec = json.dumps({"code": code, "case": case, "level": level, "warm": warm, "repeats": repeats})
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), MKL_NUM_THREADS=str(threads))
    done = subprocess.run([sys.executable, __file__, "--point", spec], capture_output=True, text=True, check=False,
                          env=env)
    if done.returncode != 0:
        raise RuntimeError(f"{code} {case} at {level:g} failed:\n{done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


# ---- analysis ----------------------------------------------------------------------------------

def richardson(points: list[dict]) -> tuple[float, float]:
    """(f_inf [Hz], observed order p in h ~ N^(-1/3)) from the three finest points, by fitting
    f = f_inf + c N^(-q) exactly (q = p / 3; the meshes need not be refined by a constant ratio).
    Outside the asymptotic range (no such fit with 0.05 < q < 5): the finest frequency, order NaN."""
    from scipy.optimize import brentq

    (n1, f1), (n2, f2), (n3, f3) = [(p["dofs"], p["frequency"]) for p in points[-3:]]
    if (f1 - f2) * (f2 - f3) <= 0:
        return f3, math.nan
    target = (f1 - f2) / (f2 - f3)

    def mismatch(q: float) -> float:
        return (n1**-q - n2**-q) / (n2**-q - n3**-q) - target

    try:
        q = brentq(mismatch, 0.05, 5.0)
    except ValueError:
        return f3, math.nan
    c = (f2 - f3) / (n2**-q - n3**-q)
    return f3 - c * n3**-q, 3 * q


def time_to_target(points: list[dict]) -> tuple[float, float, bool]:
    """(seconds, DOFs) at the target error, interpolated log-log between the bracketing points (the
    first point, coarse to fine, at or below the target, and the one before it); ``exact`` False
    when the coarsest point already meets it (its time is an upper bound) or none does (NaN)."""
    for i, p in enumerate(points):
        if p["error"] <= TARGET:
            if i == 0:
                return p["total"], p["dofs"], False
            a = points[i - 1]
            low = max(p["error"], 1e-12)  # a point on the reference itself
            s = (math.log(TARGET) - math.log(a["error"])) / (math.log(low) - math.log(a["error"]))
            return (math.exp(math.log(a["total"]) + s * (math.log(p["total"]) - math.log(a["total"]))),
                    math.exp(math.log(a["dofs"]) + s * (math.log(p["dofs"]) - math.log(a["dofs"]))), True)
    return math.nan, math.nan, False


def plot(results: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(results), figsize=(5.5 * len(results), 4.2), squeeze=False)
    for ax, (case, sweeps) in zip(axes[0], results.items()):
        for code, style in (("modalfe", "o-"), ("NGSolve", "s--")):
            pts = sweeps[code]
            ax.loglog([p["total"] for p in pts], [max(p["error"], 1e-7) for p in pts], style, label=code)
        ax.axhline(TARGET, color="grey", lw=0.8, ls=":")
        ax.set(xlabel="wall time per solve [s] (median)", ylabel="relative frequency error",
               title=f"{case}: {CASES[case].selector}")
        ax.legend()
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def report(case: str, sweeps: dict) -> dict:
    """Print the case's tables and ratios; return the figures."""
    ref_m, order_m = richardson(sweeps["modalfe"])
    ref_p, order_p = richardson(sweeps["NGSolve"])
    print(f"\n== {case}: {CASES[case].selector} near {CASES[case].near:g} Hz, whole device, no symmetry")
    for what, ref, order in (("reference (Richardson, modalfe 3 finest)", ref_m, order_m),
                             ("cross-check (Richardson, NGSolve 3 finest)", ref_p, order_p)):
        how = f"observed order {order:.2f}" if order == order else "not in the asymptotic range: the finest point"
        print(f"{what}: {ref:.2f} Hz, {how}")
    print(f"cross-check - reference: {100 * (ref_p / ref_m - 1):+.4f} %")
    head = (f"{'code':8} {'level':>7} {'DOFs':>8} {'f [Hz]':>10} {'error %':>8} {'mesh':>6} {'assem':>6} "
            f"{'factor':>6} {'eigen':>6} {'other':>6} {'total s':>7} {'RSS MB':>7}")
    print(head)
    found = {}
    for code, pts in sweeps.items():
        for p in pts:
            p["error"] = abs(p["frequency"] / ref_m - 1)
            other = p["total"] - sum(p[k] for k in ("mesh", "assembly", "factorization", "eigensolve"))
            print(f"{code:8} {p['level']:>7.4g} {p['dofs']:>8} {p['frequency']:>10.2f} {100 * p['error']:>8.4f} "
                  f"{p['mesh']:>6.2f} {p['assembly']:>6.2f} {p['factorization']:>6.2f} {p['eigensolve']:>6.2f} "
                  f"{other:>6.2f} {p['total']:>7.2f} {p['peak_rss_mb']:>7.0f}")
        found[code] = time_to_target(pts)
    for code, (t, n, exact) in found.items():
        how = "interpolated log-log" if exact else ("coarsest point, an upper bound" if t == t else "not reached")
        print(f"time to {100 * TARGET:g} %: {code:8} {t:7.2f} s at ~{n:,.0f} DOFs ({how})")
    ratio = found["modalfe"][0] / found["NGSolve"][0]
    if order_m != order_m:  # the errors above are against modalfe's finest point, which favours modalfe
        print("modalfe's sweep is not in the asymptotic range: no reference, ratio undetermined")
        ratio = math.nan
    print(f"ratio modalfe / NGSolve time to {100 * TARGET:g} %: {ratio:.3f}  (NGSolve / modalfe {1 / ratio:.2f}x)")
    # how much the figures hang on the reference: the same against the NGSolve extrapolation
    other = {code: time_to_target([dict(p, error=abs(p["frequency"] / ref_p - 1)) for p in pts])[0]
             for code, pts in sweeps.items()}
    print(f"  against the NGSolve reference instead: modalfe {other['modalfe']:.2f} s, "
          f"NGSolve {other['NGSolve']:.2f} s, ratio {other['modalfe'] / other['NGSolve']:.3f}")
    return {"reference": ref_m, "peer_reference": ref_p, "ratio": ratio, "time_to_target": found,
            "ratio_peer_reference": other["modalfe"] / other["NGSolve"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="three coarse levels per code, no warm-up solve: a smoke test")
    parser.add_argument("--repeats", type=int, default=3, help="timed solves per point (median quoted)")
    parser.add_argument("--threads", type=int, default=1,
                        help="threads per solve, both codes (1 by default: steadier timings on a shared machine)")
    parser.add_argument("--cases", nargs="+", choices=sorted(CASES), default=sorted(CASES, reverse=True))
    parser.add_argument("--out", default="studies/out/benchmark_peer", help="folder for the PNG and JSON")
    parser.add_argument("--results", help="re-analyse a saved benchmark_peer.json (no solves)")
    parser.add_argument("--point", help=argparse.SUPPRESS)  # internal: one sweep point, JSON spec
    args = parser.parse_args()
    if args.point:
        spec = json.loads(args.point)
        print(json.dumps(point(spec["code"], spec["case"], spec["level"], spec["warm"], spec["repeats"])))
        return
    if args.results:
        saved = json.loads(Path(args.results).read_text())
        results = {case: {code: saved[case][code] for code in ("modalfe", "NGSolve")} for case in saved}
        for case, sweeps in results.items():
            sweeps["summary"] = report(case, sweeps)
        plot(results, Path(args.out) / "benchmark_peer.png")
        return
    results = {}
    for case in args.cases:
        c = CASES[case]
        levels = {"modalfe": c.quick_size_factors if args.quick else c.size_factors,
                  "NGSolve": c.quick_maxh if args.quick else c.maxh}
        sweeps = {code: [] for code in levels}
        # the codes take turns, coarse to fine, so that a change in the machine's load hits both alike
        for i in range(max(map(len, levels.values()))):
            for code, values in levels.items():
                if i >= len(values):
                    continue
                p = run_point(code, case, values[i], None if args.quick else values[0], args.repeats, args.threads)
                sweeps[code].append({"level": values[i], **p})
                print(f"{case} {code} {values[i]:.4g}: {p['dofs']} DOFs, {p['frequency']:.2f} Hz, "
                      f"{p['total']:.2f} s", flush=True)
        if args.quick:
            print("\n(--quick: coarse meshes only, the reference is not converged; a smoke test, not a result)")
        results[case] = {**sweeps, "summary": report(case, sweeps)}
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "benchmark_peer.json").write_text(json.dumps(results, indent=1, default=float))
    plot(results, out / "benchmark_peer.png")
    print(f"\nwrote {out / 'benchmark_peer.png'} and {out / 'benchmark_peer.json'}")


if __name__ == "__main__":
    main()
