"""The size of a model before it is built: elements, DOFs and memory, from the element sizes and the
parts' boxes, so that a request far beyond the machine is refused with the figures instead of dying.

Solid (structured and swept hexahedra): per axis, each interval between part boundaries gets ceil(length / h)
elements (h the smallest size asked by a part spanning it, and at least ``min_layers`` across the main
part), as ``modalfe.models.mesh.divisions`` does; each part counts the product of its intervals'
divisions and the nodes of that block (vertices and edge midpoints for quadratic serendipity hexahedra:
~4 per element); 3 displacement DOFs per node plus one potential per node in piezoelectric parts.
Plate: 5 DOFs on ~4 nodes per in-plane cell; beam: 6 DOFs on ~2 nodes per element.

Memory of the solve: ``MEMORY_BYTES_PER_DOF * dofs ** MEMORY_EXPONENT`` (factorization fill plus the
assembled matrices and the Lanczos basis), calibrated on the measured peak resident memory of real solves
(docs/hostile_inputs.md, "Size estimate").
"""

from __future__ import annotations

import itertools
import math
import os
from dataclasses import dataclass

from modalfe.errors import SceneError

# peak resident memory of a solve [bytes] ~ BASE + BYTES * DOFs ** EXPONENT: the upper envelope of the peaks
# measured on 9 solid solves of 720 to 47k DOFs (docs/hostile_inputs.md, "Size estimate"; a free fit gives
# exponent 1.12, the envelope at 1.2 keeps every measured peak below the estimate)
MEMORY_BYTES_PER_DOF = 5000.0
MEMORY_EXPONENT = 1.2
# the block count of ``estimate_size`` over the real DOFs of gmsh's tetrahedral meshes: 0.40 (tile_eq5, one
# coarse layer, 3.9k DOFs), 0.63 (the holed plate of examples/, 19.8k), 1.05 (cube_plate on tetrahedra,
# 139k). Not scaled to an upper bound: the memory model is already the envelope of the measured peaks (of
# hexahedral solves; cube_plate with round feet peaked at 2.5 GB against its 7 GB estimate), and a 2.5x DOF
# envelope on top would refuse that 2.5 GB run on a 16 GB machine. Checked on other meshes in
# tests/scene/test_input_checks.py.
TET_ESTIMATE_RANGE = (0.40, 1.05)
MEMORY_BASE = 150e6  # the interpreter with numpy, scipy, scikit-fem and gmsh loaded


@dataclass(frozen=True)
class SizeEstimate:
    """Estimated elements, DOFs and peak memory [bytes] of a model of a scene."""

    fidelity: str
    elements: float
    dofs: float
    memory: float

    def describe(self) -> str:
        return (f"~{self.elements:.3g} elements, ~{self.dofs:.3g} DOFs, ~{_bytes(self.memory)} of memory "
                f"({self.fidelity} model)")


def _bytes(n: float) -> str:
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= scale:
            return f"{n / scale:.3g} {unit}"
    return f"{n / 1e3:.3g} kB"


def memory_of(dofs: float) -> float:
    """Estimated peak memory [bytes] of a solve with ``dofs`` unknowns."""
    return MEMORY_BASE + MEMORY_BYTES_PER_DOF * max(dofs, 1.0) ** MEMORY_EXPONENT


def machine_memory() -> float:
    """Memory the solve may use [bytes]: ``$MODALFE_MAX_MEMORY`` (bytes) if set, else the physical memory."""
    value = os.environ.get("MODALFE_MAX_MEMORY")
    if value:
        try:
            limit = float(value)
        except ValueError:
            raise SceneError(f"MODALFE_MAX_MEMORY: must be a number of bytes, got '{value}'") from None
        if not limit > 0:
            raise SceneError(f"MODALFE_MAX_MEMORY: must be positive, got '{value}'")
        return limit
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not Linux
        return math.inf


def _intervals(assembly, axis: int, patches=()) -> list[tuple[float, float]]:
    coords = sorted({p.lo[axis] for p in assembly.parts} | {p.hi[axis] for p in assembly.parts}
                    | {c for k, lo, hi, _ in patches if k == axis for c in (lo, hi)})
    return list(itertools.pairwise(coords))


def _divisions(assembly, axis: int, sizes, min_layers: int, patches=()) -> list[tuple[float, float, float]]:
    """(a, b, elements) per interval along ``axis``, in floats (no overflow for absurd requests); ``patches`` as
    ``modalfe.models.mesh.divisions``."""
    from modalfe.models.mesh import interval_size

    return [(a, b, max(1.0, math.ceil((b - a) / interval_size(assembly, axis, a, b, sizes, min_layers, patches)
                                      - 1e-9)))
            for a, b in _intervals(assembly, axis, patches)]


def _per_part(assembly, sizes, min_layers: int, axes=(0, 1, 2), patches=()) -> dict[str, tuple[float, ...]]:
    """Elements of each part along each of ``axes`` in the tensor grid."""
    grid = {axis: _divisions(assembly, axis, sizes, min_layers, patches) for axis in axes}
    return {part.name: tuple(sum(k for a, b, k in grid[axis] if part.lo[axis] <= (a + b) / 2 <= part.hi[axis])
                             for axis in axes) for part in assembly.parts}


def _nodes(n: tuple[float, float, float], mesh) -> float:
    """Nodes of a structured nx x ny x nz block for ``mesh`` (``MeshSettings``): vertices, plus order - 1 per
    edge (serendipity hexahedra, P2 tetrahedra) and the face and body diagonals of the tetrahedra (six per
    cube), or the whole tensor grid of a Lagrange hexahedron of order p."""
    nx, ny, nz = n
    p = mesh.order
    if mesh.element == "hex" and not mesh.serendipity:
        return (p * nx + 1) * (p * ny + 1) * (p * nz + 1)
    vertices = (nx + 1) * (ny + 1) * (nz + 1)
    edges = nx * (ny + 1) * (nz + 1) + (nx + 1) * ny * (nz + 1) + (nx + 1) * (ny + 1) * nz
    if mesh.element == "hex":
        return vertices + (p - 1) * edges
    if p == 1:
        return vertices
    return vertices + edges + nx * ny * (nz + 1) + nx * (ny + 1) * nz + (nx + 1) * ny * nz + nx * ny * nz


def estimate_size(scene, fidelity: str = "solid", *, size_factor: float = 1.0, min_layers: int | None = None
                  ) -> SizeEstimate:
    """Elements, DOFs and memory of ``scene``'s model at ``fidelity``, before any meshing."""
    from modalfe.models.mesh import element_sizes

    assembly = scene.assembly()
    sizes = {k: h * size_factor for k, h in element_sizes(scene).items()}
    layers = scene.mesh.min_layers if min_layers is None else min_layers
    share = {p.name: p.volume / math.prod(p.size) for p in assembly.parts}  # a part's share of its bounding box
    if fidelity == "solid" and scene.mesh.element == "tet":
        from modalfe.models.mesh import tet_size

        # unstructured tetrahedra of one size everywhere (``tet_size``): each part's bounding box in cubes of that
        # size (at least one across), six tetrahedra each, its nodes as for that block, scaled by the part's share
        # of its box (within ``TET_ESTIMATE_RANGE`` of gmsh's meshes)
        h = tet_size(assembly, sizes, layers)
        blocks = {p.name: tuple(max(1.0, s / h) for s in p.size) for p in assembly.parts}
        elements = sum(6 * math.prod(n) * share[name] for name, n in blocks.items())
        nodes = {name: _nodes(n, scene.mesh) * share[name] for name, n in blocks.items()}
        dofs = 3 * sum(nodes.values()) + sum(nodes[p.name] for p in assembly.parts if p.poling)
    elif fidelity == "solid":
        from modalfe.models.mesh import mass_patches

        per_part = _per_part(assembly, sizes, layers, patches=mass_patches(scene, size_factor))
        # swept hexahedra (curved parts on one axis, ``modalfe.models.swept``): each block scaled by its part's share
        # of its bounding box, as for tetrahedra. The section mesher refines round small circles (16 elements a turn)
        # and narrow gaps between parts, which this does not see: estimate / real DOFs 1.11 on the 20 x 1 mm disc
        # of docs/studies.md, 0.17 on the Cu-Be plate with round feet (0.4 mm gaps between its ceramics)
        elements = sum(math.prod(n) * share[name] for name, n in per_part.items())
        nodes = {p.name: _nodes(per_part[p.name], scene.mesh) * share[p.name] for p in assembly.parts}
        dofs = 3 * sum(nodes.values()) + sum(nodes[p.name] for p in assembly.parts if p.poling)
    elif fidelity == "plate":  # the in-plane tensor grid over the whole footprint (an upper bound)
        elements = math.prod(sum(k for _, _, k in _divisions(assembly, axis, sizes, 1)) for axis in (0, 1))
        dofs = 5 * 4.0 * elements
    else:
        elements = sum(k for _, _, k in _divisions(assembly, 0, sizes, 1))
        dofs = 6 * 2.0 * elements
    return SizeEstimate(fidelity, elements, dofs, memory_of(dofs))


def check_size(scene, fidelity: str = "solid", *, size_factor: float = 1.0, min_layers: int | None = None
               ) -> SizeEstimate:
    """The estimate, or a SceneError with its figures when the model would not fit in the machine's memory."""
    estimate = estimate_size(scene, fidelity, size_factor=size_factor, min_layers=min_layers)
    limit = machine_memory()
    if estimate.memory > limit:
        raise SceneError(
            f"mesh: too large for this machine: {estimate.describe()} against {_bytes(limit)}; the mesh resolves "
            f"{scene.max_frequency:.4g} Hz (analysis.near / --band / mesh.max_frequency) at "
            f"{scene.mesh.elements_per_wavelength:g} elements per wavelength: lower them or set mesh.max_size")
    return estimate
