"""Gmsh OCC model of a box assembly, with physical groups named by part and by face role.

Two ways to cut the assembly into volumes:
- ``grid`` given (break coordinates per axis): every part is split into the cells of the tensor
  grid, so every volume is a six-sided box and gmsh can mesh it with structured hexahedra;
- ``grid`` None: the parts themselves, fragmented so that touching parts share faces (tetrahedra).
In both cases ``fragment`` makes bonded parts share their interface nodes.
"""

from __future__ import annotations

import itertools

import numpy as np

from geometries.parts import Assembly, Box
from modalfe.errors import MeshError

TOL = 1e-9


def grid_breaks(assembly: Assembly) -> list[np.ndarray]:
    """Sorted distinct box coordinates along x, y and z."""
    out = []
    for k in range(3):
        coords = [v for p in assembly.parts for v in (p.lo[k], p.hi[k])]
        for faces in assembly.faces.values():
            for f in faces:
                if f.window is not None:
                    _, _, lo, hi = assembly.part(f.part).face_bounds(f.side, f.window)
                    coords += [lo[k], hi[k]]
        c = np.unique(coords)
        scale = c[-1] - c[0]
        keep = np.concatenate([[True], np.diff(c) > TOL * scale])
        out.append(c[keep])
    return out


def _cells(part: Box, breaks: list[np.ndarray]):
    """Grid cells (lo, hi) that tile one part."""
    ranges = []
    for k in range(3):
        c = breaks[k]
        scale = c[-1] - c[0]
        inside = c[(c >= part.lo[k] - TOL * scale) & (c <= part.hi[k] + TOL * scale)]
        ranges.append(list(itertools.pairwise(inside)))
    for (x0, x1), (y0, y1), (z0, z1) in itertools.product(*ranges):
        yield (x0, y0, z0), (x1, y1, z1)


def add_assembly(assembly: Assembly, *, grid: list[np.ndarray] | None = None) -> dict[str, list[int]]:
    """Add the assembly to the current gmsh model; return part name -> volume tags.

    Creates one physical volume group per part (named after the part) and one physical surface
    group per named face group. The caller owns ``gmsh.initialize``/``finalize``.
    """
    import gmsh

    occ = gmsh.model.occ
    owners: list[str] = []
    tags: list[tuple[int, int]] = []
    for part in assembly.parts:
        boxes = _cells(part, grid) if grid is not None else [(part.lo, part.hi)]
        for lo, hi in boxes:
            tag = occ.addBox(*lo, *(h - l for l, h in zip(lo, hi)))
            tags.append((3, tag))
            owners.append(part.name)
    if len(tags) > 1:
        _, children = occ.fragment(tags, [])
    else:
        children = [tags]  # nothing to glue: fragment would return no map
    occ.synchronize()
    volumes: dict[str, list[int]] = {}
    for owner, child in zip(owners, children):
        volumes.setdefault(owner, []).extend(t for d, t in child if d == 3)
    for name, vols in volumes.items():
        gmsh.model.addPhysicalGroup(3, sorted(set(vols)), name=name)
    lo, hi = assembly.bounds
    scale = max(h - l for l, h in zip(lo, hi))
    for group, faces in assembly.faces.items():
        surfaces: set[int] = set()
        for face in faces:
            axis, c, flo, fhi = assembly.part(face.part).face_bounds(face.side, face.window)
            bmin = [flo[k] if k != axis else c for k in range(3)]
            bmax = [fhi[k] if k != axis else c for k in range(3)]
            eps = 1e-5 * scale  # OCC bounding boxes carry ~1e-7 m of tolerance
            found = gmsh.model.getEntitiesInBoundingBox(
                *(b - eps for b in bmin), *(b + eps for b in bmax), dim=2
            )
            surfaces.update(t for _, t in found)
        if not surfaces:
            raise MeshError(f"faces.{group}: no surface found on the named faces")
        gmsh.model.addPhysicalGroup(2, sorted(surfaces), name=group)
    return volumes
