"""Any device made of boxes, as written in a user scene file."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from modalfe.errors import SceneError
from modalfe.geometry.parts import SIDES, Assembly, Box, face_ref


def boxes(*, parts: Sequence[Mapping], faces: Mapping[str, Sequence[str]] | None = None) -> Assembly:
    """Assembly from part tables and face groups (lists or tuples, dicts or read-only mappings).

    parts : each {name, region, material, origin (x, y, z) [m], size (dx, dy, dz) [m], poling}
    faces : group name -> ["part.side", ...], side one of xmin, xmax, ymin, ymax, zmin, zmax, or a window of one
            ({face = "part.side", window = [[u0, v0], [u1, v1]]}, ``modalfe.geometry.parts.face_ref``)
    """
    built = []
    for i, spec in enumerate(parts):
        where = f"parts[{i}]"
        if not isinstance(spec, Mapping):
            raise SceneError(f"{where}: must be a table {{name, material, origin, size}}")
        missing = {"name", "material", "origin", "size"} - set(spec)
        if missing:
            raise SceneError(f"{where}: missing {sorted(missing)}")
        unknown = set(spec) - {"name", "region", "material", "origin", "size", "poling"}
        if unknown:
            raise SceneError(f"{where}: unknown keys {sorted(unknown)}")
        origin, size = _triple(spec["origin"], f"{where}.origin"), _triple(spec["size"], f"{where}.size")
        for k, s in enumerate(size):
            if not s > 0:
                raise SceneError(f"{where}.size: must be positive along {'xyz'[k]}, got {s}")
        built.append(
            Box(str(spec["name"]), str(spec.get("region", spec["name"])), spec["material"]
                if isinstance(spec["material"], str) else str(spec["material"]),
                origin, tuple(o + s for o, s in zip(origin, size)), _poling(spec.get("poling", 0), where))
        )
    groups = {}
    for group, refs in (faces or {}).items():
        if isinstance(refs, str) or not isinstance(refs, Sequence):
            raise SceneError(f"faces.{group}: must be a list of 'part.side'")
        entries = [face_ref(group, ref) for ref in refs]
        for face in entries:
            if face.side not in SIDES:
                raise SceneError(f"faces.{group}: '{face.part}.{face.side}' is not 'part.side' with side in {SIDES}")
        groups[group] = tuple(entries)
    return Assembly(tuple(built), groups)


def _poling(value, where: str) -> int:
    """A box's poling sign along z: 1 or "+z", -1 or "-z", 0 (a box's poling runs between its z faces)."""
    signs = {0: 0, 1: 1, -1: -1, "0": 0, "+z": 1, "-z": -1}
    if isinstance(value, bool) or not isinstance(value, (int, str)) or value not in signs:
        raise SceneError(f"{where}.poling: a box is poled along z only (1 or '+z', -1 or '-z', 0), got {value!r}; "
                         f"lay its thickness along z")
    return signs[value]


def _triple(value, field: str) -> tuple[float, float, float]:
    try:
        out = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        raise SceneError(f"{field}: must be three numbers") from None
    if len(out) != 3:
        raise SceneError(f"{field}: must be three numbers, got {len(out)}")
    return out
