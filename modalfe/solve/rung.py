"""One rung of the 3-D solid's ladder: a scene meshed at one element size (and, for an estimate level, a number of
thickness layers), solved by one solver, maybe rotated; and what follows from it, decided once: how its error is
estimated (the orders on its grid, or coarser grids), which estimate levels and refinement steps it has, and why it
states no error where it cannot. ``modalfe.solve.fidelity`` walks the ladder with these values instead of
re-deriving each answer from the scene.

Orders or grids: quadratic box hexahedra are refined by the order first (quartic Lagrange elements on a grid
``P_COARSENING`` x coarser, whose node spacing 3h / 4 is the quadratic grid's at 1.5h), then that grid
``REFINE_RATIO`` finer a step; other meshes by the grid (elements 1.5x smaller a step, the thickness layers as many
times more). A solid of order >= 4 on boxes is estimated from its two lower orders on its own grid (p-refinement,
``modalfe.solve.estimates.p_extrapolation``); other meshes from two coarser grids (``CHECK_FACTORS``), Lagrange
cubics also from the order-2 step on their grid.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass, replace

from modalfe.results.modes import Modes
from modalfe.solve.estimates import COARSE_FACTOR, LOWEST_P_LEVEL
from modalfe.solve.levels import solve_level

CHECK_FACTORS = (COARSE_FACTOR, COARSE_FACTOR**2)  # the estimate's (and the reduced models' cross-check's) two grids
REFINE_RATIO = COARSE_FACTOR  # auto's refinement of a solid whose estimate exceeds tol: elements 1.5x smaller a step
# auto refines a solid of quadratic box hexahedra by the order first (``Rung.raises_order``): quartic Lagrange elements
# on a grid P_COARSENING x coarser (layers too, at least one), whose node spacing (3h / 4) is the quadratic grid's
# at 1.5h, then that grid REFINE_RATIO finer a step. Measured at tol 0.5 % (stated / actual against
# studies/report_tolerance.py's references): the Cu-Be plate's (0,6) 0.283 / 0.211 % at 15,514 DOFs where the
# quadratic grid needed 34,547 (0.454 / 0.282 %); the glass plate's (0,16) 0.350 / 0.077 % at 18,348 DOFs (93,994
# and 28 s quadratic, 6 s quartic); the ciliary beam's bending-z 6 0.342 / 0.166 % at 3,510 DOFs (30,404). Its
# p-estimate (``modalfe.solve.estimates.p_extrapolation``) takes a singular field's rate floor as h takes its order
P_ORDER = 4
P_COARSENING = 3.0

# the cubic serendipity hexahedron (mesh.family = "serendipity", order 3) states no error: on the coarse grids of
# studies/verification_errors.py --order 3S its h-estimate was short on 10 of 76 modes (clamped roots, a coarse
# piezo cube; the Lagrange cubic on the same grids: 1, none with ``checks_order_step``), an estimate from order 2
# on its grid on 25, and the larger of the two still on at least 6 (its order 2-3 step is small where both miss
# the clamped root)
UNVERIFIED = ("none: no verified error estimate for the cubic serendipity hexahedron (short on coarse clamped grids "
              "in verification); use mesh.family = \"lagrange\" or mesh.order = 4 for a stated error")
UNCOARSENED = ("none: an estimate level's tetrahedra would be those of the level before it (sized by the main part's "
               "thickness / layers, and the levels keep at least 2 then 1 layers); set mesh.min_layers >= 3 for a "
               "stated error")


@dataclass(frozen=True)
class Rung:
    """``scene``'s solid meshed with element sizes x ``size_factor`` (and ``min_layers`` thickness layers where an
    estimate level overrides the scene's), solved by ``solver``, rotated by ``frame`` (None: as drawn)."""

    scene: object
    size_factor: float = 1.0
    min_layers: int | None = None
    solver: str = "auto"
    frame: object = None

    def solve(self, analysis, *, labels: bool = True) -> Modes:
        """The solid's modes on this rung (``modalfe.solve.levels.solve_level``), no error estimate."""
        return solve_level(self.scene, analysis, solver=self.solver, frame=self.frame, size_factor=self.size_factor,
                           min_layers=self.min_layers, labels=labels)

    @functools.cached_property
    def uses_orders(self) -> bool:
        """Whether the error is estimated from the two lower element orders on this grid (p-refinement: box
        hexahedra of ``mesh.order`` >= 4, so that both are at least ``LOWEST_P_LEVEL``) rather than from coarser grids
        (h-refinement). Not on curved (swept) hexahedra: the orders share one quadratic geometry, so their steps miss
        the geometry's own error (studies/swept_verification.py disc: order 4's p-estimate stated 1.6e-9 on fr, which
        differs from a finer grid's by 1.7e-7); coarser grids change the geometry too."""
        return self._box_hexahedra and self.scene.mesh.order - 2 >= LOWEST_P_LEVEL

    @functools.cached_property
    def _box_hexahedra(self) -> bool:
        """Hexahedra on box parts, with round parts (swept hexahedra) only as O-grid blocks on the boxes' grid
        (``modalfe.models.section_blocks.all_blocked``: round feet, a round sensor), where the p-estimate adds the
        bound on the walls' geometry (``modalfe.models.wall_geometry``). A body of revolution alone, or a section
        left unstructured, keeps the grids' h-estimate, verified there (studies/swept_verification.py)."""
        from modalfe.models.section_blocks import all_blocked

        assembly = self.scene.assembly()
        return self.scene.mesh.element == "hex" and (not assembly.shaped or all_blocked(assembly))

    @functools.cached_property
    def checks_order_step(self) -> bool:
        """Whether the h-estimate is also checked against the step from order 2 on this grid: Lagrange hexahedra of
        order 3, whose h-estimate alone was short on a coarse clamped grid (studies/verification_errors.py --order 3:
        the 25 mm cantilever's bending 3 stated 0.95 % against 1.78 %)."""
        mesh = self.scene.mesh
        return mesh.element == "hex" and mesh.order == 3 and not mesh.serendipity

    @functools.cached_property
    def raises_order(self) -> bool:
        """Whether auto refines by the order before the grid (``P_ORDER``): quadratic hexahedra on boxes, where the
        quartic p-estimate applies (``uses_orders``)."""
        return self._box_hexahedra and self.scene.mesh.order == LOWEST_P_LEVEL

    @functools.cached_property
    def reuses_grids(self) -> bool:
        """Whether the estimate levels are coarser grids of this order (h-refinement), which a refinement step finds
        among the grids solved before it; not the orders on one grid nor with the order step."""
        return not self.uses_orders and not self.checks_order_step

    @functools.cached_property
    def no_estimate_reason(self) -> str | None:
        """Why this rung states no error estimate (``UNVERIFIED``, ``UNCOARSENED``), None when it does. Tetrahedra are
        one size everywhere, at most the thickness / min_layers (``modalfe.models.mesh.tet_size``): with one layer the
        coarser levels mesh exactly as the solid (and with two, the first as the solid): Richardson would see no step
        and state a zero error."""
        scene = self.scene
        if scene.mesh.serendipity and scene.mesh.order == 3:
            return UNVERIFIED
        if scene.mesh.element == "tet":
            from modalfe.models.mesh import element_sizes, tet_size

            assembly, sizes = scene.assembly(), element_sizes(scene)

            def size(level: dict) -> float:
                return tet_size(assembly, {k: h * level["size_factor"] for k, h in sizes.items()},
                                level["min_layers"])

            levels = [{"size_factor": self.size_factor, "min_layers": scene.mesh.min_layers},
                      *(coarse_level(scene, factor, self.size_factor) for factor in CHECK_FACTORS)]
            steps = [size(b) / size(a) for a, b in itertools.pairwise(levels)]
            if min(steps) < 1.1:  # a level no coarser than the one before: Richardson would see no step
                return UNCOARSENED
        return None

    def level(self, index: int) -> Rung:
        """Estimate level 0 or 1: orders p-1 and p-2 on this grid (``uses_orders``), else elements x1.5 and x2.25
        with the thickness layers scaled alike (``coarse_level``)."""
        if self.uses_orders:
            lower = replace(self.scene.mesh, order=self.scene.mesh.order - 1 - index)
            return replace(self, scene=replace(self.scene, mesh=lower))
        grid = coarse_level(self.scene, CHECK_FACTORS[index], self.size_factor)
        return replace(self, size_factor=grid["size_factor"], min_layers=grid["min_layers"])

    def order_step(self) -> Rung | None:
        """Order 2 on this grid where ``checks_order_step``, else None."""
        if not self.checks_order_step:
            return None
        return replace(self, scene=replace(self.scene, mesh=replace(self.scene.mesh, order=LOWEST_P_LEVEL)))

    def step(self, steps: int) -> Rung:
        """Auto's refinement step ``steps`` (1, 2, ...) of this rung: where ``raises_order``, quartic elements on a grid
        ``P_COARSENING`` x coarser, then ``REFINE_RATIO`` finer a step, the layers scaled alike (rounded down: one
        quartic layer holds a plate's bending through the thickness); else this order on a grid
        ``REFINE_RATIO``^steps finer (``refined``)."""
        if not self.raises_order:
            return self.refined(steps)
        mesh = self.scene.mesh
        scale = REFINE_RATIO ** (steps - 1) / P_COARSENING
        layers = max(1, math.floor(mesh.min_layers * scale + 1e-9))
        quartic = replace(mesh, order=P_ORDER, family="lagrange", min_layers=layers)
        return replace(self, scene=replace(self.scene, mesh=quartic), size_factor=self.size_factor / scale)

    def refined(self, steps: int) -> Rung:
        """This order on a grid ``REFINE_RATIO``^steps finer, the thickness layers raised alike (rounded half up)."""
        mesh = self.scene.mesh
        layers = max(mesh.min_layers, math.floor(mesh.min_layers * REFINE_RATIO**steps + 0.5))
        return replace(self, scene=replace(self.scene, mesh=replace(mesh, min_layers=layers)),
                       size_factor=self.size_factor / REFINE_RATIO**steps)

    @property
    def grid(self) -> tuple[int, float]:
        """(thickness layers, element size factor): the grid this rung meshes, as a refinement step finds it among
        the grids solved before (``reuses_grids``)."""
        layers = self.scene.mesh.min_layers if self.min_layers is None else self.min_layers
        return layers, round(self.size_factor, 9)

    def level_grids(self) -> list[tuple[int, float]]:
        """The grids of this rung's estimate levels (h-refinement), as ``grid`` names them."""
        return [(level_layers(self.scene.mesh.min_layers, f), round(self.size_factor * f, 9)) for f in CHECK_FACTORS]


def coarse_level(scene, factor: float, size_factor: float = 1.0) -> dict:
    """Mesh of a coarser level: elements ``factor`` times larger, thickness layers scaled alike
    (``level_layers``)."""
    return {"size_factor": size_factor * factor, "min_layers": level_layers(scene.mesh.min_layers, factor)}


def level_layers(layers: int, factor: float) -> int:
    """Thickness layers of the level ``factor`` x coarser than one with ``layers``: round(layers / factor),
    at least 1. Where that would give the first coarse level (x1.5) as few layers as the second (x2.25) although
    the fine level has more (2 layers: 1 and 1), the first keeps one more (2, 1): the pair of coarse levels the
    reduced models' cross-check extrapolates from then refines the thickness too, as it does from 3 (2, 1)."""
    n = max(1, round(layers / factor))
    if factor < COARSE_FACTOR**2 - 1e-9 and n < layers and n == max(1, round(layers / (factor * COARSE_FACTOR))):
        n += 1
    return n


def coarser(a):
    """The analysis of a coarser level: a few more modes (or a wider band) so that every mode of the
    fine level finds its partner."""
    from modalfe.scene import Analysis

    if a.band is None:
        return Analysis(near=a.near, count=a.count + 4, circuit=a.circuit)
    return Analysis(band=(a.band[0] * 0.9, a.band[1] * 1.1), circuit=a.circuit)
