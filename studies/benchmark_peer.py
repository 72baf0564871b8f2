"""modalfe against a peer FE code (NGSolve): time and DOFs to 0.1 % and 0.01 % frequency error, per element order.

Four cases, the whole device in both codes (no symmetry planes, so both solve the same problem); two box
devices:

- ``plate``: Cu-Be plate 64 x 38 x 3 mm, free-free, the (0,6) bending mode near 36 kHz;
- ``beam``: the ciliary beam (brass cantilever, PZT-5A bimorph sheets, electrodes short-circuited),
  mode ``bending-z 6`` near 21.5 kHz, piezoelectric in both codes (u and phi, e-form);

and two bodies of revolution (issue 36 item 6), free:

- ``disc``: the 20 x 1 mm PZT-5A disc of examples/pzt5a_disc.toml, its radial mode R1 near 99.4 kHz,
  piezoelectric in both codes, both electrodes grounded (short circuit);
- ``ring``: the steel ring of examples/steel_ring.toml (mean radius 20 mm, wall 1 mm, height 2 mm), the lower of
  its pair of in-plane n = 2 flexural modes near 1.55 kHz.

Sweeps, coarse to fine, each chosen to bracket both accuracies where affordable:

- modalfe, structured hexahedra of ``mesh.order`` 2 (20-node serendipity), 3 and 4 (Gauss-Lobatto
  Lagrange) and, on the plate, 3S (the 32-node cubic serendipity, ``mesh.family = "serendipity"``),
  each a list of (size factor, ``min_layers``): in-plane size and element layers across
  the main part's thin directions are set separately (at orders 3-4 one or two layers resolve
  bending); the beam with ``mesh.clamp_grading`` = 4 (geometric element layers toward the clamp);
- NGSolve, straight tetrahedra, ``VectorH1(order=p)`` (x ``H1(order=p)`` for the potential), p = 2,
  3 and 4, each with its own ``maxh`` list; on the beam a local maxh / 4 on the clamp face (the
  expert's refinement at the singular clamped edges). Geometry, materials, poling and supports are
  read from the same modalfe scene.

On the bodies of revolution, modalfe runs two models: the 3-D solid (swept hexahedra, isoparametric, levels
(size factor, min_layers) as on the boxes) and the axisymmetric model (``modalfe-axi``: Lagrange quadrilaterals of
order 2-4 on the meridian plane, harmonics 0 to the mode's: 0 on the disc, 0-2 on the ring; levels the meridian
grid's size factor); NGSolve meshes the OCC cylinder (or cylinder minus cylinder) and curves its tetrahedra to the
field's order (``mesh.Curve(p)``). modalfe picks the mode by its own label (``R1``, ``n=2``, as ``(0,6)`` on the
plate); NGSolve by its shape: on the box devices by the nodal lines of the centre line (``box_fits``), on the
round ones by the waves round a circle of the rim (``round_fits``: in-plane, radial more than tangential, the
strongest Fourier harmonic of u_r the mode's n).

Same eigen solver both sides: NGSolve's K and M go to scipy and through modalfe's shift-invert path
(``modalfe.solve.eigen.eigenpairs``: PARDISO and ARPACK), so the comparison is discretization,
meshing and assembly. NGSolve assembles inside its ``TaskManager``.

Each point runs in its own process with ``--threads`` threads (1 by default), fresh mesh caches,
one untimed warm-up solve on its sweep's coarsest level, then ``--repeats`` timed solves: the
median run is quoted with its split (mesh, assembly, factorization, eigen solve; "other" is picking
the mode). The sweeps take turns, coarse to fine, so that a change in the machine's load hits all.

Reference per case: Richardson extrapolation f(N) = f_inf + c N^(-q) through modalfe's three finest
order-4 levels (on the round devices the axisymmetric model's: exact for a body of revolution, the 3-D solid's
order 4 too dear to converge there), its uncertainty taken as the extrapolation step |f_inf - f(finest)| (outside the
asymptotic range: the finest point, its uncertainty its last change); cross-check: the same through
NGSolve's three finest order-4 levels. Time and DOFs to each accuracy are
interpolated log-log between the two sweep points bracketing it. Growth with DOFs: per stage and
sweep, the exponent a of time ~ DOFs^a, least squares in log-log over the sweep's points.

    python studies/benchmark_peer.py [--quick] [--repeats 3] [--threads 1] [--cases plate beam disc ring]
                                     [--out studies/out/benchmark_peer] [--results FILE.json]
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from modalfe.geometry.parts import Assembly
    from modalfe.scene import Scene

TARGETS = (1e-3, 1e-4)  # accuracies: relative discretization error of the mode's frequency
STAGES = ("mesh", "assembly", "factorization", "eigensolve")
GOAL = 0.5  # the goal: modalfe's time to 0.1 % at most half the peer's

Sweeps = dict[str, dict[int | str, tuple]]  # code -> element order (3S: cubic serendipity) -> levels, coarse to fine


@dataclass(frozen=True)
class Case:
    """One benchmark problem: the mode (modalfe selector, Hz), its shape signature and the sweeps, full and
    ``--quick``: modalfe levels (size factor, min_layers), modalfe-axi levels size factor, NGSolve levels maxh [m].
    A box device's mode is known by its nodal lines (``nodes_along``, ``check_across``), a body of revolution's by
    the waves of its rim (``harmonic``, ``rim``: ``round_fits``) in every code."""

    selector: str
    near: float
    sweeps: Sweeps
    quick: Sweeps
    nodes_along: int = 0  # box devices: sign changes of u_z along the long centre line
    check_across: bool = False  # box devices: also require no nodal line along the length (plate (0,n) modes)
    clamp_refinement: float | None = None  # peer: maxh / this on the clamp face (modalfe grades it too)
    harmonic: int | None = None  # bodies of revolution: waves of u_r round the rim (0: the radial mode)
    rim: tuple[float, float] = (0.0, 0.0)  # bodies of revolution: radius and height [m] of the sampled circle
    reference: str = "modalfe"  # the code whose highest-order sweep gives the reference

    @property
    def curved(self) -> bool:
        """A body of revolution: curved elements in the peer, the axisymmetric model in modalfe."""
        return self.harmonic is not None


GRADING_LAYERS = 4  # beam case: element layers toward the clamp, sizes h 0.4^k (modalfe.models.mesh.graded_breaks)
# beam case, the peer's refinement at the clamp: local maxh h / 4 on the clamp face (netgen grades away from
# it); at order 2, of h / 4 and h / 8 tried, h / 4 reached 0.1 % sooner (22k DOFs at h = 2 mm against 32k)
PEER_CLAMP_REFINEMENT = 4.0

CASES = {
    "plate": Case(
        "(0,6)", 36e3, nodes_along=6, check_across=True,
        sweeps={"modalfe": {2: ((1.5, 2), (1.0, 3), (2 / 3, 4), (4 / 9, 7)),
                            3: ((3.0, 1), (2.0, 1), (1.5, 1), (1.0, 2), (2 / 3, 2)),
                            "3S": ((2.0, 1), (1.5, 1), (1.25, 1), (1.0, 1), (2 / 3, 2), (0.5, 2)),
                            4: ((3.0, 1), (2.5, 1), (2.0, 1), (1.5, 1), (1.0, 1))},
                "NGSolve": {2: (3e-3, 2e-3, 1.5e-3, 1e-3, 0.75e-3),
                            3: (8e-3, 6e-3, 4e-3, 3e-3, 2e-3),
                            4: (12e-3, 9e-3, 6e-3, 4e-3)}},
        quick={"modalfe": {2: ((2.0, 2), (1.5, 2)), 3: ((3.0, 1), (2.0, 1)), "3S": ((2.0, 1), (1.5, 1)),
                           4: ((3.0, 1), (2.5, 1))},
               "NGSolve": {2: (6e-3, 4e-3), 3: (10e-3, 8e-3), 4: (16e-3, 12e-3)}}),
    "beam": Case(
        "bending-z 6", 21.5e3, nodes_along=5,
        sweeps={"modalfe": {2: ((1.5, 2), (1.0, 3), (2 / 3, 4), (4 / 9, 7), (8 / 27, 10)),
                            3: ((2.0, 1), (1.5, 1), (1.5, 2), (1.0, 2), (2 / 3, 3), (4 / 9, 3)),
                            4: ((3.0, 1), (2.0, 1), (1.5, 2), (1.0, 3), (2 / 3, 4))},
                "NGSolve": {2: (4e-3, 3e-3, 2e-3, 1.4e-3, 1e-3),
                            3: (10e-3, 6e-3, 4e-3, 3e-3, 2e-3),
                            4: (8e-3, 6e-3, 4e-3)}},
        quick={"modalfe": {2: ((2.0, 2), (1.5, 2)), 3: ((2.0, 1), (1.5, 1)), 4: ((3.0, 1), (2.0, 1))},
               "NGSolve": {2: (6e-3, 4e-3), 3: (12e-3, 10e-3)}},
        clamp_refinement=PEER_CLAMP_REFINEMENT),
    # the 20 x 1 mm PZT-5A disc's radial mode R1 (n = 0, in-plane), short circuit; rim sampled at 0.9 R, mid-height
    "disc": Case(
        "R1", 99.4e3,
        sweeps={"modalfe": {2: ((4.0, 1), (3.0, 1), (2.0, 1), (1.5, 1)), 3: ((4.0, 1), (3.0, 1)), 4: ((4.0, 1),)},
                "modalfe-axi": {2: (4.0, 2.0, 1.0, 0.5), 3: (4.0, 2.0, 1.0), 4: (4.0, 2.0, 1.0, 0.5)},
                "NGSolve": {2: (10e-3, 5e-3, 3e-3, 2e-3), 3: (10e-3, 5e-3, 3e-3), 4: (10e-3, 5e-3, 3e-3, 2e-3)}},
        quick={"modalfe": {2: ((4.0, 1), (3.0, 1))}, "modalfe-axi": {2: (4.0, 2.0), 4: (4.0, 2.0)},
               "NGSolve": {4: (10e-3, 5e-3)}},
        harmonic=0, rim=(9e-3, 0.5e-3), reference="modalfe-axi"),
    # the free steel ring's (R 20 mm, wall 1 mm, height 2 mm) lower in-plane n = 2 flexural mode; rim at R, mid-height
    "ring": Case(
        "n=2", 1.55e3,
        sweeps={"modalfe": {2: ((2.0, 1), (1.5, 1), (1.0, 1), (2 / 3, 1)), 3: ((6.0, 1), (4.0, 1), (3.0, 1), (2.0, 1)),
                            4: ((6.0, 1), (4.0, 1), (3.0, 1))},
                "modalfe-axi": {2: (2.0, 1.0, 0.5), 3: (2.0, 1.0, 0.5), 4: (2.0, 1.0, 0.5)},
                "NGSolve": {2: (3e-3, 2e-3, 1.5e-3), 3: (7e-3, 5e-3, 4e-3, 3e-3), 4: (10e-3, 7e-3, 5e-3, 3e-3)}},
        quick={"modalfe": {2: ((2.0, 1), (1.5, 1))}, "modalfe-axi": {2: (2.0, 1.0), 4: (2.0, 1.0)},
               "NGSolve": {4: (10e-3, 5e-3)}},
        harmonic=2, rim=(20e-3, 1e-3), reference="modalfe-axi"),
}
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
ROUND_SCENES = {"disc": "pzt5a_disc.toml", "ring": "steel_ring.toml"}  # the curved cases' scene files


# modes asked of the eigen solve, both codes: the case's mode and its neighbours, enough to pick it by shape (an
# expert asks for the modes needed; 8 cost 39 shift-invert solves against 4's ~20)
MODES_ASKED = 4


def scene(case: str, order: int = 2, family: str = "auto") -> Scene:
    """The modalfe scene of a case, whole (no symmetry), hexahedra of ``order`` and ``family``; a round case's
    axisymmetric model solves harmonics 0 to its mode's (``mesh.harmonics``)."""
    from modalfe.scene import load_scene, scene_from_dict

    if case in ROUND_SCENES:
        sc = load_scene(EXAMPLES / ROUND_SCENES[case], **{"analysis.near": CASES[case].near,
                                                          "analysis.count": MODES_ASKED,
                                                          "mesh.harmonics": CASES[case].harmonic})
    elif case == "beam":
        # graded layers toward the clamp (mesh.clamp_grading): the clamped edge's singularity otherwise
        # holds uniform refinement to order ~1.9 (docs/benchmark_peer.md)
        sc = load_scene("ciliary_beam", symmetry=(), **{"analysis.near": CASES[case].near,
                                                        "analysis.count": MODES_ASKED,
                                                        "mesh.clamp_grading": GRADING_LAYERS})
    else:
        sc = scene_from_dict({
            "name": "cube_plate_bare",
            "parts": [{"name": "plate", "region": "plate", "material": "CuBe", "origin": [0, 0, 0],
                       "size": [64e-3, 38e-3, 3e-3]}],
            "analysis": {"near": CASES[case].near, "count": MODES_ASKED},
            "kind": "plate",
        })
    return dataclasses.replace(sc, mesh=dataclasses.replace(sc.mesh, order=order, family=family))


def describe(code: str, level) -> str:
    """A sweep level for the tables: ``s 0.667 L2`` (modalfe), ``s 0.5`` (modalfe-axi) or ``h 1.5 mm`` (NGSolve)."""
    if code == "modalfe":
        s, layers = level
        return f"s {s:.3g} L{layers}"
    return f"s {level:.3g}" if code == "modalfe-axi" else f"h {1e3 * level:.3g} mm"


# ---- modalfe side ------------------------------------------------------------------------------

def sweep_element(key: int | str) -> tuple[int, str]:
    """(order, ``mesh.family``) of a sweep key: an order, or an order and S (serendipity)."""
    return int(str(key).rstrip("S")), "serendipity" if str(key).endswith("S") else "auto"


def modalfe_solve(case: str, order: int | str, level: tuple[float, int] | float, fidelity: str = "solid") -> dict:
    """One modalfe solve: the 3-D solid at ``level`` = (size factor, min_layers), or the axisymmetric model
    (``modalfe.models.axisymmetric``, harmonics 0 to the mode's) on its meridian grid scaled by ``level``; the mode
    picked by modalfe's own label (``CASES[case].selector``). DOFs, stage times [s] and the mode frequency [Hz]."""
    from modalfe.results.modes import select
    from modalfe.solve.levels import solve_level

    sc = scene(case, *sweep_element(order))
    size_factor, layers = (level, None) if fidelity == "axisymmetric" else level
    start = time.perf_counter()
    modes = solve_level(sc, sc.analysis, fidelity=fidelity, size_factor=size_factor, solver="auto",
                        min_layers=None if layers is None else int(layers))
    mode = select(modes, CASES[case].selector, CASES[case].near)
    return {"dofs": modes.dofs, "frequency": mode.frequency, "total": time.perf_counter() - start,
            **{k: modes.timings[k] for k in STAGES}}


def _fresh_modalfe_caches(folder: Path) -> None:
    """Forget meshes and models (new cache ``folder``) so that a repeat meshes and assembles again."""
    import modalfe.caches as caches
    import modalfe.models.mesh

    os.environ["MODALFE_CACHE"] = str(folder)
    modalfe.models.mesh._memory_cache.clear()
    caches.clear()


# ---- peer side (NGSolve) -----------------------------------------------------------------------

def occ_shape(assembly: Assembly, local_maxh: dict[str, float] | None = None):
    """The assembly's boxes, cylinders and rings as one glued OCC shape; each solid's material name is its part
    name, face groups carry their names (electrodes, clamps: the planar faces xmin... of a box, top and bottom of
    a round part); ``local_maxh``: face group -> maxh [m]."""
    from netgen.occ import Box, Cylinder, Glue, Pnt, X, Y, Z

    axes = {"x": X, "y": Y, "z": Z}
    solids, normals = {}, {}
    for part in assembly.parts:
        if hasattr(part, "radii"):  # a cylinder or a ring, from its base centre along its axis
            if part.cuts:
                raise NotImplementedError(f"part {part.name}: cut round parts are not built for the peer")
            inner, outer = part.radii
            solid = Cylinder(Pnt(*part.centre), axes[part.axis], r=outer, h=part.height)
            if inner > 0:
                solid = solid - Cylinder(Pnt(*part.centre), axes[part.axis], r=inner, h=part.height)
            normals[part.name] = {"bottom": part.axis + "min", "top": part.axis + "max"}
        else:
            solid = Box(Pnt(*part.lo), Pnt(*part.hi))
        solid.mat(part.name)
        solids[part.name] = solid
    for group, faces in assembly.faces.items():
        for face in faces:
            if face.window is not None:
                raise NotImplementedError(f"face group {group}: windowed faces are not built for the peer")
            side = normals.get(face.part, {}).get(face.side, face.side)
            if side[1:] not in ("min", "max"):
                raise NotImplementedError(f"face group {group}: {face.part}.{face.side} is not built for the peer")
            faces_of = solids[face.part].faces
            named = faces_of.Min(axes[side[0]]) if side.endswith("min") else faces_of.Max(axes[side[0]])
            named.name = group
            if local_maxh and group in local_maxh:
                named.maxh = local_maxh[group]
    return Glue(list(solids.values()))


def _voigt_strain(u):
    """Engineering strain (xx, yy, zz, yz, xz, xy) of a vector field."""
    from ngsolve import CF, Grad

    G = Grad(u)
    return CF((G[0, 0], G[1, 1], G[2, 2], G[1, 2] + G[2, 1], G[0, 2] + G[2, 0], G[0, 1] + G[1, 0]))


def _poled(material, part):
    """``material`` seen in the global frame of ``part``: poled along its (uniform) poling direction."""
    from modalfe.scene.materials import poling_frames

    if not material.is_piezoelectric:
        return material
    if part.poling_vector is None:
        raise NotImplementedError(f"peer model: part {part.name}: only uniform poling (not {part.poling!r})")
    return material.rotated(poling_frames(part.poling_vector))


def peer_matrices(sc: Scene, mesh, order: int):
    """K, M (scipy CSR, free DOFs only), the space and the free DOF indices, for the scene's elastic and
    piezoelectric parts at polynomial ``order``: electrodes grounded (phi = 0, short circuit), clamps fixed."""
    import scipy.sparse as sp
    from ngsolve import CF, H1, BilinearForm, Compress, Grad, InnerProduct, VectorH1, dx

    assembly = sc.assembly()
    if any(c != "xyz" for c in sc.clamps.values()):
        raise NotImplementedError("peer model: only fully clamped face groups")
    mats = {p.name: _poled(sc.material(p.material), p) for p in assembly.parts}
    piezo = [name for name, m in mats.items() if m.is_piezoelectric]
    C = mesh.MaterialCF({name: CF(tuple(m.C.ravel()), dims=(6, 6)) for name, m in mats.items()})
    rho = mesh.MaterialCF({name: m.rho for name, m in mats.items()})
    U = VectorH1(mesh, order=order, dirichlet="|".join(sc.clamps))
    if piezo:
        P = Compress(H1(mesh, order=order, definedon="|".join(piezo), dirichlet="|".join(sc.electrodes)))
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
    """Frequency [Hz] of the case's mode among the peer's eigenpairs, found by its shape (``box_fits`` or
    ``round_fits``): the one nearest the case's frequency."""
    from ngsolve import GridFunction, VectorH1

    gf = GridFunction(fes)
    disp = gf if isinstance(fes, VectorH1) else gf.components[0]  # (u, phi) on a piezo device
    located = {}  # points -> mesh points: located once for every mode (a search through curved elements)

    def shape(i: int):
        vec = np.zeros(fes.ndof)
        vec[free] = X[:, i]

        def displacement(points: np.ndarray) -> np.ndarray:
            points = np.asarray(points, dtype=float)
            key = points.tobytes()
            if key not in located:
                located[key] = mesh(*points.T)
            gf.vec.FV().NumPy()[:] = vec
            return np.array(disp(located[key]))

        return displacement

    frequencies = np.sqrt(np.maximum(lam, 0.0)) / (2 * np.pi)
    return pick(CASES[case], [(float(f), shape(i)) for i, f in enumerate(frequencies)], sc)


def pick(c: Case, modes: list[tuple[float, Callable]], sc: Scene | None = None) -> float:
    """Frequency [Hz] of the case's mode among (frequency [Hz], displacement at points (n, 3) [m] -> (n, 3)) pairs:
    of those whose shape fits the case (``round_fits``; a box device ``box_fits`` on scene ``sc``), the one nearest
    the case's frequency."""
    fits = [f for f, displacement in modes
            if (round_fits(c, displacement) if c.curved else box_fits(c, sc, displacement))]
    if not fits:
        raise RuntimeError(f"no {c.selector} mode among {len(modes)} near {c.near:g} Hz")
    return min(fits, key=lambda f: abs(f - c.near))


RIM_POINTS = 48  # points round the sampled circle: harmonics up to 23 resolved, the cases' n <= 2 many times over
IN_PLANE = 0.1  # an in-plane mode: |u_z| under this share of |u_r| on the rim (as tests/oracles/discs.py in_plane)


def round_fits(c: Case, displacement: Callable) -> bool:
    """Whether a body of revolution's mode has the case's shape on its rim (``c.rim``): in-plane (max |u_z| under
    ``IN_PLANE`` max |u_r|), mainly radial (rms u_r above rms u_theta: not a torsion mode) and with ``c.harmonic``
    the strongest Fourier harmonic of u_r round the circle."""
    theta = np.linspace(0.0, 2 * np.pi, RIM_POINTS, endpoint=False)
    radius, z = c.rim
    u = displacement(np.stack([radius * np.cos(theta), radius * np.sin(theta), np.full_like(theta, z)], axis=1))
    u_r = u[:, 0] * np.cos(theta) + u[:, 1] * np.sin(theta)
    u_t = u[:, 1] * np.cos(theta) - u[:, 0] * np.sin(theta)
    return bool(np.abs(u[:, 2]).max() < IN_PLANE * np.abs(u_r).max() and np.sum(u_r**2) > np.sum(u_t**2)
                and int(np.argmax(np.abs(np.fft.rfft(u_r)))) == c.harmonic)


def box_fits(c: Case, sc: Scene, displacement: Callable) -> bool:
    """Whether a box device's mode has the case's nodal lines: u_z dominant on the long centre line (mid-height
    of the main part) with ``c.nodes_along`` sign changes and, for a plate (0,n) mode (``c.check_across``), no
    sign change across the width (lines at 10 % of the width from either edge)."""
    assembly = sc.assembly()
    lo, hi = np.min([p.lo for p in assembly.parts], axis=0), np.max([p.hi for p in assembly.parts], axis=0)
    main = assembly.main_part
    z = (main.lo[2] + main.hi[2]) / 2
    xs = np.linspace(lo[0], hi[0], 161)[1:-1]

    def line(y: float) -> np.ndarray:
        return displacement(np.stack([xs, np.full_like(xs, y), np.full_like(xs, z)], axis=1))

    mid, width = (lo[1] + hi[1]) / 2, hi[1] - lo[1]
    centre = line(mid)
    if np.abs(centre[:, 2]).max() < 2 * np.abs(centre[:, :2]).max():
        return False  # not a bending mode about y
    if _sign_changes(centre[:, 2]) != c.nodes_along:
        return False
    return not c.check_across or all(np.dot(centre[:, 2], line(y)[:, 2]) > 0
                                     for y in (lo[1] + 0.1 * width, hi[1] - 0.1 * width))


def _sign_changes(values: np.ndarray) -> int:
    """Sign changes along a sampled line, ignoring values below 1 % of the peak (the clamped end)."""
    big = values[np.abs(values) > 0.01 * np.abs(values).max()]
    return int(np.count_nonzero(np.diff(np.sign(big))))


def peer_solve(case: str, order: int, maxh: float) -> dict:
    """One NGSolve solve at ``order`` and ``maxh`` [m] (on a curved case, elements curved to ``order``: the
    geometry's order equals the field's): DOFs, stage times [s] (curving in "mesh") and the mode frequency [Hz]."""
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
        if CASES[case].curved:
            mesh.Curve(order)
        t_mesh = time.perf_counter() - start
        K, M, fes, free = peer_matrices(sc, mesh, order)
        t_assembly = time.perf_counter() - start - t_mesh
    solution = eigenpairs(K, M, sc.analysis)
    frequency = peer_pick(case, sc, mesh, fes, free, solution.values, solution.vectors)
    return {"dofs": K.shape[0], "frequency": frequency, "total": time.perf_counter() - start, "mesh": t_mesh,
            "assembly": t_assembly, "factorization": solution.factorization_seconds,
            "eigensolve": solution.eigensolve_seconds}


# ---- one sweep point in its own process --------------------------------------------------------

def point(code: str, case: str, order: int | str, level, warm, repeats: int) -> dict:
    """Median of ``repeats`` timed solves after one untimed warm-up solve at level ``warm`` (None: none);
    peak RSS [MB]."""
    solve = {"modalfe": modalfe_solve, "modalfe-axi": functools.partial(modalfe_solve, fidelity="axisymmetric"),
             "NGSolve": peer_solve}[code]
    runs = []
    with tempfile.TemporaryDirectory(prefix="modalfe-bench-") as root:
        for i in range(repeats + 1):
            if code.startswith("modalfe"):
                _fresh_modalfe_caches(Path(root) / str(i))
            if i:
                runs.append(solve(case, order, level))
            elif warm is not None:
                solve(case, order, warm)
    out = dict(sorted(runs, key=lambda r: r["total"])[len(runs) // 2])  # the median run, with its split
    out["peak_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def run_point(code: str, case: str, order: int | str, level, warm, repeats: int, threads: int) -> dict:
    """``point`` in a fresh interpreter with ``threads`` threads (MKL, OpenMP, NGSolve); its JSON result."""
    spec = json.dumps({"code": code, "case": case, "order": order, "level": level, "warm": warm,
                       "repeats": repeats})
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), MKL_NUM_THREADS=str(threads))
    done = subprocess.run([sys.executable, __file__, "--point", spec], capture_output=True, text=True, check=False,
                          env=env)
    if done.returncode != 0:
        raise RuntimeError(f"{code} p={order} {case} at {level}: failed:\n{done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


# ---- analysis ----------------------------------------------------------------------------------

def richardson(points: list[dict]) -> tuple[float, float]:
    """(f_inf [Hz], observed order p in h ~ N^(-1/3)) from the three finest points, by fitting
    f = f_inf + c N^(-q) exactly (q = p / 3; the meshes need not be refined by a constant ratio).
    Fewer than three points or outside the asymptotic range (no such fit with 0.05 < q < 5): the
    finest frequency, order NaN."""
    from scipy.optimize import brentq

    if len(points) < 3:
        return points[-1]["frequency"], math.nan
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


def time_to_target(points: list[dict], target: float) -> tuple[float, float, str]:
    """(seconds, DOFs, how) at error ``target``, interpolated log-log between the bracketing points (the
    first point, coarse to fine, at or below the target, and the one before it); how: "interpolated",
    "bound" (the coarsest point already meets it: its time is an upper bound) or "not reached" (NaN)."""
    for i, p in enumerate(points):
        if p["error"] <= target:
            if i == 0:
                return p["total"], p["dofs"], "bound"
            a = points[i - 1]
            low = max(p["error"], 1e-12)  # a point on the reference itself
            s = (math.log(target) - math.log(a["error"])) / (math.log(low) - math.log(a["error"]))
            return (math.exp(math.log(a["total"]) + s * (math.log(p["total"]) - math.log(a["total"]))),
                    math.exp(math.log(a["dofs"]) + s * (math.log(p["dofs"]) - math.log(a["dofs"]))), "interpolated")
    return math.nan, math.nan, "not reached"


def growth(points: list[dict], key: str) -> float:
    """Exponent a of ``key`` time ~ DOFs^a, least squares in log-log (points under 1 ms left out; NaN
    with fewer than two points or under a factor 2 in DOFs)."""
    pts = [(p["dofs"], p[key]) for p in points if p[key] >= 1e-3]
    if len(pts) < 2 or max(n for n, _ in pts) < 2 * min(n for n, _ in pts):
        return math.nan
    n, t = np.log(np.array(pts, dtype=float)).T
    return float(np.polyfit(n, t, 1)[0])


STYLES = {"modalfe": "o-", "modalfe-axi": "^-.", "NGSolve": "s--"}  # plot lines per code


def plot(results: dict, path: Path) -> None:
    """Error against time, log-log, one panel per case, one line per code and order."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(results), figsize=(6 * len(results), 4.5), squeeze=False)
    for ax, (case, result) in zip(axes[0], results.items()):
        for sweep in result["sweeps"]:
            pts = sweep["points"]
            ax.loglog([p["total"] for p in pts], [max(p["error"], 1e-7) for p in pts],
                      STYLES[sweep["code"]], label=f"{sweep['code']} p={sweep['order']}")
        for target in TARGETS:
            ax.axhline(target, color="grey", lw=0.8, ls=":")
        ax.set(xlabel="wall time per solve [s] (median)", ylabel="relative frequency error",
               title=f"{case}: {CASES[case].selector}")
        ax.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def _fastest(found: dict, code: str, target: float) -> str | None:
    """The sweep whose key ("modalfe 3", "modalfe-axi 4"...) starts with ``code`` ("modalfe": either model,
    "modalfe ": the 3-D solid's) that reaches ``target`` soonest; None if none does."""
    keys = [k for k in found if k.startswith(code) and found[k][target][0] == found[k][target][0]]
    return min(keys, key=lambda k: found[k][target][0]) if keys else None


def _name(key: str) -> str:
    """A sweep's name in the ratio lines: "NGSolve 3" -> "NGSolve p=3"; "best NGSolve" as it is."""
    code, order = key.split()
    return key if code == "best" else f"{code} p={order}"


def _pct(x: float) -> str:
    return f"{100 * x:.4f} %" if x == x else "-"


def reference(sweeps: list[dict], reference_code: str = "modalfe") -> dict:
    """The case's reference frequency from the highest order of ``reference_code`` and its cross-check from
    NGSolve's (see the module docstring), each with its uncertainty: the extrapolation step, or outside the
    asymptotic range the finest point's last change."""
    out = {}
    for role, code in (("reference", reference_code), ("cross_check", "NGSolve")):
        top = max((s for s in sweeps if s["code"] == code), key=lambda s: sweep_element(s["order"]))
        pts = top["points"]
        f, order = richardson(pts)
        last = pts[-2]["frequency"] if order != order and len(pts) > 1 else pts[-1]["frequency"]
        out[role] = {"code": code, "order": top["order"], "frequency": f, "observed_order": order,
                     "finest": pts[-1]["frequency"], "uncertainty": abs(f / last - 1)}
    out["difference"] = out["cross_check"]["frequency"] / out["reference"]["frequency"] - 1
    return out


def report(case: str, sweeps: list[dict]) -> dict:
    """Print the case's tables and ratios; return the figures."""
    ref = reference(sweeps, CASES[case].reference)
    f_ref = ref["reference"]["frequency"]
    print(f"\n== {case}: {CASES[case].selector} near {CASES[case].near:g} Hz, whole device, no symmetry"
          + (" (modalfe-axi: its meridian plane)" if CASES[case].curved else ""))
    for role, what in (("reference", "reference"), ("cross_check", "cross-check")):
        r = ref[role]
        how = (f"Richardson through {r['code']} p={r['order']}'s 3 finest, observed order {r['observed_order']:.2f}; "
               f"finest {r['finest']:.2f} Hz, extrapolation step" if r["observed_order"] == r["observed_order"] else
               f"{r['code']} p={r['order']}'s finest point, not in the asymptotic range; its last change")
        print(f"{what}: {r['frequency']:.2f} Hz ({how} {_pct(r['uncertainty'])})")
    print(f"cross-check - reference: {100 * ref['difference']:+.4f} %; reference uncertainty "
          f"{_pct(ref['reference']['uncertainty'])}: "
          f"{'well below' if ref['reference']['uncertainty'] < 0.1 * TARGETS[-1] else 'NOT well below'} "
          f"{100 * TARGETS[-1]:g} %")

    print(f"\n{'code':11} {'p':>2} {'level':>12} {'DOFs':>8} {'f [Hz]':>10} {'error':>9} {'mesh':>6} {'assem':>6} "
          f"{'factor':>6} {'eigen':>6} {'other':>6} {'total s':>7} {'RSS MB':>7}")
    for sweep in sweeps:
        for p in sweep["points"]:
            p["error"] = abs(p["frequency"] / f_ref - 1)
            other = p["total"] - sum(p[k] for k in STAGES)
            print(f"{sweep['code']:11} {sweep['order']:>2} {describe(sweep['code'], p['level']):>12} {p['dofs']:>8} "
                  f"{p['frequency']:>10.2f} {_pct(p['error']):>9} "
                  + " ".join(f"{p[k]:>6.2f}" for k in STAGES)
                  + f" {other:>6.2f} {p['total']:>7.2f} {p['peak_rss_mb']:>7.0f}")

    found = {f"{s['code']} {s['order']}": {t: time_to_target(s["points"], t) for t in TARGETS} for s in sweeps}
    print("\ntime [s] and DOFs to each accuracy (median run; '<=' the coarsest point already meets it, '-' not "
          "reached in the sweep)")
    print(f"{'code':11} {'p':>2} "
          + " ".join(f"{f'DOFs {100 * t:g}%':>12} {f'time {100 * t:g}%':>12}" for t in TARGETS))
    for key, per in found.items():
        code, order = key.split()
        cells = []
        for t in TARGETS:
            s, n, how = per[t]
            mark = "<=" if how == "bound" else ""
            cells.append(f"{(mark + f'{n:,.0f}') if n == n else '-':>12} {(mark + f'{s:.2f}') if s == s else '-':>12}")
        print(f"{code:11} {order:>2} " + " ".join(cells))

    summary = {"reference": ref, "time_to_target": {k: {str(t): v for t, v in per.items()} for k, per in found.items()},
               "best": {}, "ratios": {}, "per_model": {}}
    peers = [k for k in found if k.startswith("NGSolve")]
    for t in TARGETS:
        ours, theirs = _fastest(found, "modalfe", t), _fastest(found, "NGSolve", t)
        summary["best"][str(t)] = {"modalfe": ours, "NGSolve": theirs}
        if ours is None:
            print(f"to {100 * t:g} %: no modalfe order reached it")
            continue
        ratios = {k: found[ours][t][0] / found[k][t][0] for k in peers}
        ratios["best NGSolve"] = found[ours][t][0] / found[theirs][t][0] if theirs else math.nan
        summary["ratios"][str(t)] = ratios
        print(f"to {100 * t:g} %: best {_name(ours)} {found[ours][t][0]:.2f} s; ratio modalfe / "
              + ", ".join(f"{_name(k)} {r:.3f}" for k, r in ratios.items() if k in peers)
              + f", / best NGSolve ({_name(theirs) if theirs else '-'}) {ratios['best NGSolve']:.3f}")
        models = sorted({s["code"] for s in sweeps if s["code"].startswith("modalfe")})
        if theirs and len(models) > 1:  # each modalfe model's fastest order against the fastest peer
            per_model = {m: found[k][t][0] / found[theirs][t][0] for m in models
                         if (k := _fastest(found, f"{m} ", t)) is not None}
            summary["per_model"][str(t)] = per_model
            print("  per model, fastest order / best NGSolve: "
                  + ", ".join(f"{m} ({_name(_fastest(found, f'{m} ', t))}) {r:.3f}" for m, r in per_model.items()))
    goal_peer = "NGSolve 3" if case == "plate" else "best NGSolve"
    ratio = summary["ratios"].get(str(TARGETS[0]), {}).get(goal_peer, math.nan)
    summary["goal"] = {"against": goal_peer, "ratio": ratio, "met": bool(ratio <= GOAL)}
    print(f"goal: modalfe / {_name(goal_peer)} to {100 * TARGETS[0]:g} % <= {GOAL}: ratio {ratio:.3f}, "
          f"{'met' if ratio <= GOAL else 'NOT met'}")

    print("\ngrowth with DOFs: a in time ~ DOFs^a, least squares over each sweep's points")
    print(f"{'code':11} {'p':>2} {'DOFs':>17} " + " ".join(f"{k:>13}" for k in (*STAGES, "total")))
    summary["growth"] = {}
    for sweep in sweeps:
        pts = sweep["points"]
        a = {k: growth(pts, k) for k in (*STAGES, "total")}
        summary["growth"][f"{sweep['code']} {sweep['order']}"] = a
        span = f"{pts[0]['dofs']:,}-{pts[-1]['dofs']:,}"
        print(f"{sweep['code']:11} {sweep['order']:>2} {span:>17} "
              + " ".join(f"{v:>13.2f}" if v == v else f"{'-':>13}" for v in a.values()))
    return summary


def run_case(case: str, quick: bool, repeats: int, threads: int) -> list[dict]:
    """Every sweep of a case, taking turns coarse to fine; each point in its own process."""
    plan = CASES[case].quick if quick else CASES[case].sweeps
    sweeps = [{"code": code, "order": order, "levels": levels, "points": []}
              for code, orders in plan.items() for order, levels in orders.items()]
    for i in range(max(len(s["levels"]) for s in sweeps)):
        for s in sweeps:
            if i >= len(s["levels"]):
                continue
            level = s["levels"][i]
            p = run_point(s["code"], case, s["order"], level, None if quick else s["levels"][0], repeats, threads)
            s["points"].append({"level": level, **p})
            print(f"{case} {s['code']} p={s['order']} {describe(s['code'], level)}: {p['dofs']} DOFs, "
                  f"{p['frequency']:.2f} Hz, {p['total']:.2f} s", flush=True)
    return [{k: v for k, v in s.items() if k != "levels"} for s in sweeps]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="two coarse levels per code and order, no warm-up solve: a smoke test")
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
        print(json.dumps(point(spec["code"], spec["case"], spec["order"], spec["level"], spec["warm"],
                               spec["repeats"])))
        return
    if args.results:
        saved = json.loads(Path(args.results).read_text())
        results = {case: {"sweeps": r["sweeps"]} for case, r in saved.items()}
    else:
        results = {case: {"sweeps": run_case(case, args.quick, args.repeats, args.threads)} for case in args.cases}
        if args.quick:
            print("\n(--quick: coarse meshes only, the reference is not converged; a smoke test, not a result)")
    for case, result in results.items():
        result["summary"] = report(case, result["sweeps"])
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if not args.results:
        (out / "benchmark_peer.json").write_text(json.dumps(results, indent=1, default=float))
    plot(results, out / "benchmark_peer.png")
    print(f"\nwrote {out / 'benchmark_peer.png'}" + ("" if args.results else f" and {out / 'benchmark_peer.json'}"))


if __name__ == "__main__":
    main()
