"""Discretization error estimates: solves on coarser levels, paired with the fine modes by shape (the modal
assurance criterion on common sample points), and Richardson extrapolation at an observed, bounded order.

Pairing by shape, not label: a degenerate pair (any rotation of it is a mode), or two modes one label reads
alike, are still paired with the mode they are. MAC (Allemang & Brown 1982) of the displacement sampled at the
same points of the whole device on both levels; when no single coarse mode matches (a degenerate pair
rotated differently on each level), the fine shape's projection on the span of the coarse modes near it
(a subspace MAC) pairs it with that cluster, at their frequencies weighted by the projection.

Order: the eigenvalue error of degree-p elements is ~h^(2p) = h^4 for smooth modes (Strang & Fix, An Analysis
of the Finite Element Method, 1973, ch. 6), but a singular field of strength h^alpha slows it to h^(2 alpha):
clamped edges, bonded patches and feet (studies/convergence.py observes 1.5-2.1 on the seed devices; a
clamped thin plate ~1.3). With three levels the order is observed from the two differences and used within
[MIN_ORDER, ceiling]; with two levels, or where the differences change sign or the coarsest partner is a
mixed shape (MAC below ``SUBSPACE_PAIR``; pre-asymptotic), the bound MIN_ORDER = 1 is used (with the larger
step): alpha >= 1/2 for every 3-D elasticity singularity (a crack tip, the strongest; Grisvard, Elliptic Problems
in Nonsmooth Domains, 1985), so order 2 alpha >= 1.

The ceiling is CONVERGENCE_ORDER = 2 for a field with no singular point (``singular_field``: one part, free or on
mirror-type supports), else MIN_ORDER itself: as the grid refines, a singular field takes over the error and the
order falls toward 2 alpha, below what three levels show, which is that of the coarser ones. The Cu-Be plate's
(0,6) (ten ceramics bonded over the plate, four feet below) showed 2.15 through its refinement's grids of 34,547,
15,064 and 6,010 DOFs, while nested uniform refinement of its default grid (every grid interval split 2, 3 and 4
times, to 307,966 DOFs) converges at 1.68 and then 1.34 (studies/singular_convergence.py); at the ceiling 2 its
finest grid stated 0.199 % against an error of 0.282 %. The glass plate's (0,16), whose two small end patches hold
little of the mode, converges at 2.41 there: at order 1 its estimates are 2-3x its errors, the price of a bound.
"""

from __future__ import annotations

import logging
import math
import weakref
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from modalfe.results.modes import Mode, Modes

log = logging.getLogger(__name__)

COARSE_FACTOR = 1.5  # coarse levels of the Richardson estimate: elements 1.5x and 2.25x larger
CONVERGENCE_ORDER = 2.0  # the highest order used where the field is not singular (module docstring)
MIN_ORDER = 1.0  # the lowest order of an eigenvalue error with a singular field (module docstring)
OBSERVED_ORDERS = (1.5, 2.1)  # the cross-check extrapolation's uncertainty: orders observed on the seed devices
MAC_PAIR = 0.8  # a single coarse mode this alike is the partner (the sweeps' crossing threshold)
SUBSPACE_PAIR = 0.9  # else the coarse modes near it must hold this fraction of the fine shape
CLUSTER = 0.05  # relative frequency span of the coarse modes a subspace pairing may use
# the least refinement a level must have in every direction to be used: at 1.2 and order 1 the step is already
# multiplied by 5, and below it the rounding of element counts per grid interval (ceil) moves the step more
# than the coarsening does (the Cu-Be plate's first coarse level: 1.24 across y, the least of the seeds)
MIN_RATIO = 1.2
SAMPLES = 400  # sample points for the MAC: 1200 values a shape, enough to tell modes apart
# p-refinement (``p_extrapolation``): the eigenvalue error of order-p elements on a fixed grid falls like p^-q, with
# q >= 4 alpha >= MIN_P_RATE = 2 where a singular field of strength r^alpha limits it (the p-version doubles the
# h-version's rate at singular points on element vertices: Babuska & Suri, SIAM J. Numer. Anal. 24 (1987) 750;
# eigenvalue errors are the squares of energy-norm errors; alpha >= 1/2 for every 3-D elasticity singularity).
# The estimate assumes that floor: a faster rate observed through three orders is not used, since on a coarse
# grid the low orders resolve the smooth part of a clamped or bonded edge's field and the rate they show (3.9-7
# on clamped beams and bars) overstates how the singular part left at order p falls (verification at order 4,
# studies/verification_errors.py --order 4: rates above 2.8 under-stated clamped cantilevers and bars). A rate
# observed below the floor (not yet converging) is used: it raises the estimate.
MIN_P_RATE = 2.0
# The doubling needs the singular or boundary-layer behaviour on element vertices and edges. A thin part's edges carry
# zones of width ~ its thickness t (the twisting and shear boundary layers of a plate: Arnold & Falk, SIAM J. Math.
# Anal. 20 (1989) 1276); the p-version resolves such a layer only with elements no wider than ~p t beside it (Schwab &
# Suri, Math. Comp. 65 (1996) 1403). On a p-grid whose elements are wider than p times the main part's thickness
# (``unresolved_edges``) the zone lies inside the elements, where the p-version converges no faster than the h-version:
# the floor is 2 alpha >= UNRESOLVED_P_RATE = 1. Measured (studies/level_coverage.py, cantilever): a 30 x 10 x 0.5 mm
# clamped Cu-Be plate on quartic elements 5 mm wide (10 t) stepped 35.1 then 9.19 Hz through orders 2-3-4 on its
# twisting mode (1,0), while 14.7 Hz of error was left (order 4 on grids 8x finer: 2146.53 Hz): at the floor 2 it stated
# 0.55 % against 0.68 %. The seeds' quartic grids are 0.4-0.9 p t wide (the Cu-Be plate's 11 mm over 3 mm the widest)
UNRESOLVED_P_RATE = MIN_P_RATE / 2
# a number derived from a mode's shape (an amplitude, a force factor, a mass at a point, k_eff) converges at the energy
# norm's rate, not at its square as an eigenvalue does (Strang & Fix 1973, ch. 6: the eigenvalue error is the square of
# the eigenvector's energy-norm error): its orders and rates are the eigenvalue's halved (``EstimatePlan.
# derived_errors``), h^0.5 at the least (alpha = 1/2, an electrode's or a bond's edge). Measured (studies/
# derived_errors.py, issue 34): the ciliary beam's force factor converges at h^0.49 (quartic, one layer: 0.04006,
# 0.03929, 0.03874 N/V on grids x2, x1, x0.5), while its orders 2-3-4 on one grid step 8.4 % then 0.85 % (the
# smooth part's fast phase hides the singular part's slow tail: 3.9 % left): on a p-plan a number of the shape is
# taken as pre-asymptotic, the larger step at the halved rate
SHAPE_SLOWDOWN = 2.0
LOWEST_P_LEVEL = 2  # order-1 hexahedra lock in bending (their error is not the start of the p-sequence)


def sample_points(modes: Modes) -> np.ndarray:
    """Points (m, 3) [m] where shapes are compared across levels and fidelities, at most ``SAMPLES``: for a
    3-D solid the centroids of its elements (strictly inside the device, so inside every other mesh of it
    too), else the points the model reads its labels from."""
    model = modes.model
    mesh = getattr(getattr(model, "mesh", None), "mesh", None)
    if mesh is not None and getattr(model, "frame", None) is None:
        points = mesh.p[:, mesh.t].mean(axis=1)
    else:
        points, _ = model.label_field(modes[0].shape)
    step = max(1, points.shape[1] // SAMPLES)
    return np.ascontiguousarray(points[:, ::step].T)


# the last probe matrix built for each model, with its points: ``common_points`` builds it to test the points and
# ``sampled`` then reads the same points (the solid's probes cost ~0.2 s a build on the tile's 24k DOFs)
_PROBES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def probes(model, points: np.ndarray):
    """``model.displacement_probes(points)``, the last one built for ``model`` reused when ``points`` are the same."""
    key = np.ascontiguousarray(points, dtype=float).tobytes()
    kept = _PROBES.get(model)
    if kept is not None and kept[0] == key:
        return kept[1]
    P = model.displacement_probes(points)
    _PROBES[model] = (key, P)
    return P


def _inside(model, points: np.ndarray) -> np.ndarray:
    """Mask of the ``points`` (m, 3) that ``model`` can evaluate (a point on a face of one mesh may fall a hair
    outside another's elements): the whole set at once, else halves, recursively."""
    try:
        probes(model, points)
        return np.ones(len(points), dtype=bool)
    except ValueError:
        if len(points) == 1:
            return np.zeros(1, dtype=bool)
        half = len(points) // 2
        return np.concatenate([_inside(model, points[:half]), _inside(model, points[half:])])


def common_points(points: np.ndarray, *models) -> np.ndarray:
    """The ``points`` every one of ``models`` can evaluate."""
    keep = np.ones(len(points), dtype=bool)
    for model in models:
        keep &= _inside(model, points)
    return points[keep]


def sampled(modes: Modes, points: np.ndarray) -> np.ndarray:
    """Displacements of every mode at ``points``: (3 m, k), columns scaled to unit norm (zero stays zero)."""
    P = probes(modes.model, points)
    S = np.asarray(P @ np.column_stack([m.shape for m in modes]))
    norms = np.linalg.norm(S, axis=0)
    return S / np.where(norms > 0, norms, 1.0)


def shape_partners(fine: Modes, coarse: Modes,
                   points: np.ndarray | None = None) -> dict[int, tuple[Mode, float, float]]:
    """{fine index: (coarse partner, partner frequency [Hz], MAC)} of the modes paired by shape (module
    docstring); a fine mode with no partner is left out. One-to-one by the best total MAC (Hungarian
    assignment); a fine mode whose assigned MAC is below ``MAC_PAIR`` is paired with the span of the coarse
    modes within ``CLUSTER`` of its best match if that holds ``SUBSPACE_PAIR`` of its shape."""
    from scipy.optimize import linear_sum_assignment

    if len(fine) == 0 or len(coarse) == 0:
        return {}
    if points is None:
        points = sample_points(coarse)
    points = common_points(points, fine.model, coarse.model)
    if len(points) == 0:
        return {}
    F, C = sampled(fine, points), sampled(coarse, points)
    mac = (F.T @ C) ** 2
    f_fine, f_coarse = fine.frequencies, coarse.frequencies
    # modes more than 30 % apart are not the same mode on two meshes of one device
    apart = np.abs(f_coarse[None, :] - f_fine[:, None]) > 0.3 * np.maximum(f_fine[:, None], 1e-300)
    rows, cols = linear_sum_assignment(np.where(apart, -1.0, mac), maximize=True)
    out = {}
    for i, j in zip(rows, cols):
        if mac[i, j] >= MAC_PAIR and not apart[i, j]:
            out[fine[i].index] = (coarse[j], float(f_coarse[j]), float(mac[i, j]))
            continue
        best = int(np.argmax(np.where(apart[i], -1.0, mac[i])))
        near = np.flatnonzero(np.abs(f_coarse - f_coarse[best]) <= CLUSTER * f_coarse[best])
        Q, _ = np.linalg.qr(C[:, near])
        weights = (Q.T @ F[:, i]) ** 2
        if weights.sum() >= SUBSPACE_PAIR and not apart[i, best]:
            w = mac[i, near] / mac[i, near].sum() if mac[i, near].sum() > 0 else np.full(len(near), 1 / len(near))
            out[fine[i].index] = (coarse[best], float(w @ f_coarse[near]), float(weights.sum()))
    return out


def observed_order(f0: float, f1: float, f2: float, r1: float, r2: float) -> float | None:
    """Order p of f_i = f + C h_i^p through three levels h0 < h1 = r1 h0 < h2 = r2 h0, or None where the
    differences change sign or vanish (no order to observe)."""
    d1, d2 = f1 - f0, f2 - f1
    if d1 == 0 or d2 == 0 or (d1 > 0) != (d2 > 0):
        return None
    target = d2 / d1

    def g(p: float) -> float:
        return (r2**p - r1**p) / (r1**p - 1) - target

    lo, hi = 0.05, 12.0
    if g(lo) > 0 or g(hi) < 0:
        return lo if g(lo) > 0 else hi
    for _ in range(80):  # bisection: g increases with p
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def richardson_error(q0: float, q1: float, q2: float | None = None, ratio: float = COARSE_FACTOR,
                     ratio_2: float | None = None, ceiling: float = CONVERGENCE_ORDER, alike: float = 1.0,
                     floor: float = MIN_ORDER) -> float:
    """Relative error estimate of a number ``q0`` on the fine level from its values ``q1`` on a level ``ratio`` x
    coarser and ``q2`` (or None) on one ``ratio_2`` x coarser: |q0 - q1| / ((ratio^p - 1) |q0|) at the order p
    observed through the three within [``floor``, ``ceiling``], else (two levels, differences changing sign, or a
    coarsest partner less ``alike`` than ``SUBSPACE_PAIR``: pre-asymptotic) the larger step at ``floor`` (module
    docstring; MIN_ORDER for an eigenvalue). inf where ``q0`` is zero and the levels differ."""
    order, step = floor, abs(q1 - q0)
    if q2 is not None:
        p = observed_order(q0, q1, q2, ratio, ratio_2)
        if p is None or alike < SUBSPACE_PAIR:
            # pre-asymptotic: the larger step at the lowest order. A coarsest partner less alike than a cluster
            # must be is a mixed shape: the tile's twisting mode on its quarter, 1121.74 Hz at x1.5, pairs at MAC
            # 0.805 with a 1402 Hz pad twist at x2.25 (its own (1,1) there mixed with the pad's), and the last
            # step alone (0.10 %, at order 2) stated 0.18 % against an error of 0.23 %
            step = max(step, abs(q2 - q1))
        else:
            order = min(max(p, floor), ceiling)
    return _relative(step / (ratio**order - 1), q0)


def order_tail(p: int, q0: float, q1: float, q2: float | None = None, rate: float = MIN_P_RATE,
               observe: bool = True) -> tuple[float, float | None]:
    """(relative error estimate of a number ``q0`` at element order ``p`` from its values at orders p-1 (``q1``) and
    p-2 (``q2``, or None) on the same grid: the tail of e_k = C k^-q beyond order p at q = ``rate`` (``MIN_P_RATE``
    for an eigenvalue), or at the rate observed through the three where that is slower; the rate observed, else None).
    Where the steps change sign (pre-asymptotic), or without ``observe`` (taken as pre-asymptotic), the larger step at
    ``rate``."""
    step, q, observed = q1 - q0, rate, None
    if q2 is not None:
        observed = p_rate(p, q2 - q1, step) if observe else None
        if observed is not None:
            q = min(observed, rate)
        else:
            step = max(abs(step), abs(q2 - q1))
    return _relative(abs(step) / ((p / (p - 1)) ** q - 1), q0), observed


def _relative(error: float, q0: float) -> float:
    if q0 == 0:
        return 0.0 if error == 0 else math.inf
    return error / abs(q0)


def richardson(fine: Modes, coarse: Modes, ratio: float, coarsest: Modes | None = None,
               ratio_2: float | None = None, ceiling: float = CONVERGENCE_ORDER) -> dict[int, float]:
    """Relative error estimate of each fine mode from its coarse partner (by shape): |f_h - f_coarse| /
    ((ratio^p - 1) f_h), p observed through ``coarsest`` (elements ``ratio_2`` x the fine level's) within
    [MIN_ORDER, ``ceiling``], else MIN_ORDER (module docstring); inf where a mode has no partner (the
    coarse level does not resolve it, so the fine one is not converged either).

    ``ratio`` is the refinement every direction has at least (``axis_ratio``): with errors of one sign in each
    direction (conforming elements), f_coarse - f_h >= (ratio^p - 1) (f_h - f), so the estimate bounds the
    error at order p. A level coarser by less than ``MIN_RATIO`` in some direction sees too little of that
    direction's error and is not used: with only one level left, two-level Richardson at MIN_ORDER from it;
    with none, inf (no level measures the error)."""
    usable = ratio >= MIN_RATIO
    usable_2 = coarsest is not None and len(coarsest) > 0 and ratio_2 is not None and ratio_2 >= MIN_RATIO
    if not usable and usable_2:
        return richardson(fine, coarsest, ratio_2, ceiling=ceiling)
    estimates, rigid = {}, fine.rigid_indices()
    pairs = shape_partners(fine, coarse) if usable else {}
    chain = shape_partners(coarse, coarsest) if usable and usable_2 else {}
    for mode in fine:
        if mode.index in rigid:
            continue  # a rigid-body mode: no relative error to speak of
        if mode.index not in pairs:
            log.info("mode %s at %.6g Hz has no partner on a coarse mesh that coarsens every direction: error "
                     "unknown, refine the mesh", mode.label, mode.frequency)
            estimates[mode.index] = math.inf
            continue
        other, f1, _ = pairs[mode.index]
        f2, alike = chain[other.index][1:] if other.index in chain else (None, 1.0)
        estimates[mode.index] = richardson_error(mode.frequency, f1, f2, ratio, ratio_2, ceiling, alike)
    return estimates


# what a line support means on the 3-D solid (docs/supports.md): its reaction is a line load, whose field is singular
# at the line (stresses ~ 1/r, displacements ~ log r: Flamant's solution), so a line holds the continuum with no
# stiffness in the limit and the mesh's nodes on it hold it less as they refine (NAFEMS FV52, measured there)
LINE_SUPPORT_CAVEAT = ("line supports, a singular line load on the 3-D solid held at the mesh's nodes on the line: "
                       "the frequencies it affects fall slowly as the mesh refines (no mesh-independent limit) and "
                       "stresses at the line do not converge (docs/supports.md)")


def singular_field(scene) -> str:
    """What makes ``scene``'s elastic field singular somewhere, in words, or "" (module docstring): parts bonded to one
    another (their interfaces end at re-entrant or bi-material edges), a clamp other than a mirror condition (the
    normal displacement alone, or the two tangential ones, fixed on whole faces: the field then continues smoothly
    by reflection, as the diaphragm's simple supports and the half models' cuts do), edge (line) supports, guided
    faces other than a whole face's normal component, springs and attached masses
    (supports that end on a face), electrodes on part of a face."""
    assembly = scene.assembly()
    reasons = ["bonded parts"] if len(assembly.parts) > 1 else []

    def mirror_type(face, components: str) -> bool:
        normal = face.side[0]
        return face.window is None and set(components) in ({normal}, set("xyz") - {normal})

    clamps = [g for g, c in scene.clamps.items() if not all(mirror_type(f, c) for f in assembly.faces.get(g, ()))]
    reasons += [f"clamps ({', '.join(clamps)})"] if clamps else []
    reasons += [f"{LINE_SUPPORT_CAVEAT} ({', '.join(scene.edges)})"] if scene.edges else []
    # a guided face whose normal component alone is uniform is a mirror plane moved rigidly: smooth; others end a
    # rigid patch at the face's edges, as a clamp does
    guides = [g for g, c in scene.guides.items() if not all(f.window is None and set(c) == {f.side[0]}
                                                            for f in assembly.faces.get(g, ()))]
    reasons += [f"guides ({', '.join(guides)})"] if guides else []
    reasons += ["springs"] if scene.springs else []
    reasons += ["attached masses"] if scene.masses else []
    if any(f.window is not None for g in scene.electrodes for f in assembly.faces.get(g, ())):
        reasons.append("electrodes on part of a face")
    return ", ".join(reasons)


def p_rate(p: int, d_low: float, d_high: float) -> float | None:
    """Rate q of e_k = C k^-q through the orders p-2, p-1, p from the steps ``d_low`` = f_(p-2) - f_(p-1) and
    ``d_high`` = f_(p-1) - f_p; None where the steps change sign or vanish (no rate to observe)."""
    if d_low == 0 or d_high == 0 or (d_low > 0) != (d_high > 0):
        return None
    target = d_high / d_low

    def ratio(q: float) -> float:  # decreases from 1 toward 0 as q grows
        return ((p - 1) ** -q - p**-q) / ((p - 2) ** -q - (p - 1) ** -q)

    lo, hi = 0.01, 60.0
    if ratio(lo) <= target:
        return lo
    if ratio(hi) >= target:
        return hi
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ratio(mid) > target else (lo, mid)
    return 0.5 * (lo + hi)


def p_extrapolation(fine: Modes, lower: Modes, lowest: Modes | None = None,
                    rate: float = MIN_P_RATE) -> tuple[dict[int, float], list[float]]:
    """(relative error estimate of each mode of ``fine``, the rates observed) from the same grid at orders p-1
    (``lower``) and p-2 (``lowest``, may be None): |f_p - f_(p-1)| / ((p / (p-1))^q - 1) / f_p, the tail of
    e_k = C k^-q beyond order p at q = ``rate`` (``MIN_P_RATE``, or ``UNRESOLVED_P_RATE``), or at the rate observed
    through the three orders where that is slower. Modes are paired by shape; inf where a mode has no partner."""
    p = fine.model.scene.mesh.order
    estimates, rates, rigid = {}, [], fine.rigid_indices()
    pairs = shape_partners(fine, lower)
    chain = shape_partners(lower, lowest) if lowest is not None and len(lowest) else {}
    for mode in fine:
        if mode.index in rigid:
            continue
        if mode.index not in pairs:
            log.info("mode %s at %.6g Hz has no partner at order %d on the same grid: error unknown, refine",
                     mode.label, mode.frequency, p - 1)
            estimates[mode.index] = math.inf
            continue
        other, f1, _ = pairs[mode.index]
        f2 = chain[other.index][1] if other.index in chain else None
        estimates[mode.index], observed = order_tail(p, mode.frequency, f1, f2, rate=rate)
        if observed is not None:
            rates.append(observed)
    return estimates, rates


def axis_sizes(mesh, scene) -> np.ndarray:
    """Mean element extent [m] along x, y and z over the main part's elements of a solid ``mesh``
    (``DeviceMesh``), and the number of elements across the main part along each axis: (2, 3)."""
    main = scene.assembly().main_part.name
    cells = mesh.mesh.t[:, mesh.parts[main]]
    p = mesh.mesh.p
    extent = (p[:, cells].max(axis=1) - p[:, cells].min(axis=1)).mean(axis=1)
    nodes = p[:, np.unique(cells)]
    across = (nodes.max(axis=1) - nodes.min(axis=1)) / extent
    return np.vstack([extent, across])


def axis_ratio(fine_mesh, coarse_mesh, scene) -> float:
    """The smallest element-size ratio, coarse over fine, along an axis the fine level can coarsen (more than
    one element across the main part): the refinement every direction's error has at least. An axis the coarse
    level does not coarsen gives 1 (that level sees none of that direction's error)."""
    fine, coarse = axis_sizes(fine_mesh, scene), axis_sizes(coarse_mesh, scene)
    ratios = coarse[0] / fine[0]
    can = fine[1] > 1.5
    return float(ratios[can].min()) if can.any() else float(ratios.min())


def interval_extents(mesh, scene) -> dict[tuple[str, int, int], tuple[float, float]]:
    """{(part, axis, grid interval): (largest element extent [m] along the axis, the interval's length [m])} of a
    hexahedral ``mesh`` (``DeviceMesh``), over each part's elements whose centres lie in that interval of the
    assembly's grid (``grid_breaks``: the parts' faces and face windows' edges, which every level of the scene keeps
    as element boundaries): along every axis on box hexahedra, along the sweep axis alone on swept ones (their
    section meshes are unstructured); {} on tetrahedra. The largest extent, not the mean: layers graded toward a
    clamped face scale with the level's element size, the uniform elements beside them are the level's own size."""
    from modalfe.geometry.gmsh_model import grid_breaks

    if mesh.element != "hex":
        return {}
    assembly = scene.assembly()
    axes = range(3) if not assembly.shaped else (() if assembly.sweep_axis is None else (assembly.sweep_axis,))
    breaks = grid_breaks(assembly)
    p, t = mesh.mesh.p, mesh.mesh.t[:8]
    out = {}
    for name, cells in mesh.parts.items():
        for axis in axes:
            coords = p[axis][t[:, cells]]
            extent, centre = coords.max(axis=0) - coords.min(axis=0), coords.mean(axis=0)
            where = np.clip(np.searchsorted(breaks[axis], centre) - 1, 0, len(breaks[axis]) - 2)
            for i in np.unique(where):
                length = float(breaks[axis][i + 1] - breaks[axis][i])
                out[name, int(axis), int(i)] = (float(extent[where == i].max()), length)
    return out


def uncoarsened(fine_mesh, coarse_mesh, scene) -> tuple[float, str]:
    """(the least element-size ratio, coarse over fine, over every part's grid intervals along each axis that the
    fine level splits into two elements or more (``interval_extents``), inf where there is none; the part, axis and
    interval of that least ratio in words). A part or a face window's interval whose element count rounds to the
    same on both levels (ceil of its length over the level's size: 0.5 mm of ceramic at 0.30 and 0.45 mm elements is
    2 layers on both) has ratio 1: the coarse level sees none of the error there, however much the main part
    coarsens (``axis_ratio`` measures the main part alone)."""
    fine, coarse = interval_extents(fine_mesh, scene), interval_extents(coarse_mesh, scene)
    worst, where = math.inf, ""
    for key, (h, length) in fine.items():
        if key not in coarse or h > length * (1 - 1e-6):
            continue  # one element across: no level can coarsen it (its grid lines are the geometry's)
        ratio = coarse[key][0] / h
        if ratio < worst:
            part, axis, i = key
            worst, where = ratio, f"part '{part}' along {'xyz'[axis]} (grid interval {i}, {length * 1e3:.3g} mm)"
    return worst, where


def level_ratio(fine_mesh, coarse_mesh, scene) -> tuple[float, str]:
    """(the refinement ratio every direction of every part has at least between two levels: the smaller of
    ``axis_ratio`` and ``uncoarsened``; where the second decides it, the part and interval in words, else "")."""
    main = axis_ratio(fine_mesh, coarse_mesh, scene)
    least, where = uncoarsened(fine_mesh, coarse_mesh, scene)
    return (least, where) if least < main else (main, "")


def refinement_ratio(fine_mesh, coarse_mesh, scene) -> float:
    """Mean element-size ratio between two meshes of the main part: (n_fine / n_coarse)^(1/3)."""
    main = scene.assembly().main_part.name
    return float((len(fine_mesh.parts[main]) / len(coarse_mesh.parts[main])) ** (1 / 3))


def unresolved_edges(mesh, scene) -> str:
    """Where the largest element of a p-grid's main part (``mesh``, a ``DeviceMesh`` of box hexahedra) across its
    thickness is wider than the element order times that thickness, the phrase saying so (its edge zones lie inside
    the elements: ``UNRESOLVED_P_RATE``), else ""."""
    assembly = scene.assembly()
    main, axis, order = assembly.main_part, assembly.thickness_axis, scene.mesh.order
    thickness = main.size[axis]
    extents = interval_extents(mesh, scene)
    width = max((h for (part, a, _), (h, _) in extents.items() if part == main.name and a != axis), default=0.0)
    if width <= order * thickness:
        return ""
    return (f"its part '{main.name}' is {thickness * 1e3:.3g} mm thick under elements {width * 1e3:.3g} mm wide, "
            f"more than {order} x its thickness: edge zones inside the elements")


def partner(mode: Mode, candidates: Modes) -> Mode | None:
    """The mode of ``candidates`` most alike ``mode`` in shape (MAC >= ``MAC_PAIR``, frequency within 30 %)."""
    one = replace(candidates, modes=(replace(mode, index=0),), model=mode.model)
    found = shape_partners(one, candidates, sample_points(candidates)).get(0)
    return found[0] if found is not None else None


@dataclass(frozen=True)
class EstimatePlan:
    """How a solid's stated errors are made, fixed once its estimate levels are solved, and applied alike to its
    frequencies (``frequency_errors``) and to every number derived from one of its modes (``derived_errors``):

    rule ``grids``: Richardson through ``levels`` (two coarser grids, elements ``ratios`` x the solid's) at the order
    observed within [MIN_ORDER, ``ceiling``]; ``grid``: two-level Richardson at MIN_ORDER from each of ``levels``
    (the grids that coarsen every part), the larger; ``orders``: the order tail from orders p-1 and p-2 on the
    solid's grid (``levels``) at the rate floor ``rate`` (``MIN_P_RATE``, or ``UNRESOLVED_P_RATE`` where
    ``unresolved_edges``); ``none``: no level measures the error (inf). ``floor``: the order-2 solve on the
    grid whose step the estimate is at least (cubic hexahedra, ``modalfe.solve.rung.Rung.checks_order_step``), else
    None. ``method``: the plan in words (``Modes.estimate_method``)."""

    rule: str
    levels: tuple[Modes, ...] = ()
    ratios: tuple[float, ...] = ()
    ceiling: float = CONVERGENCE_ORDER
    floor: Modes | None = None
    method: str = ""
    rate: float = MIN_P_RATE

    def frequency_errors(self, fine: Modes) -> tuple[dict[int, float], list[float]]:
        """({mode index: relative error estimate} of every mode of ``fine`` (partners by shape, module docstring), the
        rates the ``orders`` rule observed (empty for the others))."""
        rates: list[float] = []
        if self.rule == "orders":
            estimates, rates = p_extrapolation(fine, *self.levels, rate=self.rate)
        elif self.rule == "grids":
            estimates = richardson(fine, self.levels[0], self.ratios[0], self.levels[1], self.ratios[1],
                                   ceiling=self.ceiling)
        elif self.rule == "grid":  # each level bounds the error at order 1 by itself; one without a partner yields
            found = [richardson(fine, level, ratio) for level, ratio in zip(self.levels, self.ratios)]
            estimates = {}
            for m in fine:
                values = [e[m.index] for e in found if m.index in e]
                if values:
                    finite = [v for v in values if math.isfinite(v)]
                    estimates[m.index] = max(finite) if finite else math.inf
        else:
            rigid = fine.rigid_indices()
            estimates = {m.index: math.inf for m in fine if m.index not in rigid}
        if self.floor is not None:
            step, _ = p_extrapolation(fine, self.floor)
            estimates = {i: max(e, step.get(i, e)) for i, e in estimates.items()}
        return estimates, rates

    def level_holding(self, mode: Mode) -> Modes:
        """The level (or the order-2 floor) whose model ``mode`` belongs to: a partner ``derived_errors`` handed on."""
        return next(level for level in (*self.levels, self.floor) if level is not None and level.model is mode.model)

    def derived_errors(self, mode: Mode, values: Callable[[Mode], dict[str, float]],
                       fine: dict[str, float] | None = None,
                       eigenvalues: tuple[str, ...] = ()) -> dict[str, tuple[float, str]]:
        """{name: (relative error estimate, "" or why it is not estimated)} of the numbers ``values(mode)`` derives
        from ``mode`` (fa, masses, amplitudes per volt): each number on ``mode``'s partner (by shape) on each level,
        through this plan's rule, ``values`` called once a level. A number a level cannot give (missing, None or
        not finite there) is inf with the reason; ``fine``: ``values(mode)`` when already computed. Orders and rates
        are the eigenvalue's halved (``SHAPE_SLOWDOWN``) but for the ``eigenvalues`` named (an open circuit's fa)."""
        fine = values(mode) if fine is None else fine
        order = mode.model.scene.mesh.order
        chain = self.rule in ("grids", "orders")
        levels = _level_values(mode, self.levels, values, chain) if self.rule != "none" else []
        floor_level = _level_values(mode, (self.floor,), values, False)[0] if self.floor is not None else None
        out = {}
        for name, q0 in fine.items():
            slowdown = 1.0 if name in eigenvalues else SHAPE_SLOWDOWN
            floor, rate = MIN_ORDER / slowdown, self.rate / slowdown
            if q0 is None or not math.isfinite(q0):
                out[name] = (math.inf, "not found on the answer's own model")
                continue
            if self.rule == "none":
                out[name] = (math.inf, self.method)
                continue
            q = [_get(level, name) for level in levels]
            if self.rule == "grid":
                found = [richardson_error(q0, v, None, r, floor=floor) for v, r in zip(q, self.ratios)
                         if v is not None]
                error = max(found) if found else None
            elif q[0] is None:
                error = None
            elif self.rule == "grids":
                error = richardson_error(q0, q[0], q[1], self.ratios[0], self.ratios[1],
                                         self.ceiling / slowdown, floor=floor)
            else:  # a number of the shape: the orders' steps taken as pre-asymptotic (``SHAPE_SLOWDOWN``)
                error, _ = order_tail(order, q0, q[0], q[1], rate=rate, observe=slowdown == 1.0)
            if error is None:
                out[name] = (math.inf, "no estimate level holds the mode or this number (error unknown)")
                continue
            if self.floor is not None:
                step = _get(floor_level, name)
                if step is None:
                    out[name] = (math.inf, "the order-2 level holds no partner of the mode (error unknown)")
                    continue
                error = max(error, order_tail(order, q0, step, rate=rate)[0])
            out[name] = (error, "")
        return out


def _level_values(mode: Mode, levels, values: Callable[[Mode], dict[str, float]],
                  chain: bool) -> list[dict[str, float] | None]:
    """``values`` on ``mode``'s partner on each of ``levels`` (None where it has none): with ``chain``, the partner
    on a level is that of the partner on the level before (as ``richardson`` and ``p_extrapolation`` pair them)."""
    out, current = [], mode
    for level in levels:
        source = current if chain else mode
        found = partner(source, level) if source is not None else None
        out.append(values(found) if found is not None else None)
        current = found
    return out


def _get(level_values: dict[str, float] | None, name: str) -> float | None:
    q = None if level_values is None else level_values.get(name)
    return float(q) if q is not None and math.isfinite(q) else None
