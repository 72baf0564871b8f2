"""Part tables of a scene file with shapes: boxes, cylinders (discs), rings and extruded outlines.

One ``[[parts]]`` table per part, its ``shape`` one of ``box`` (the default: origin, size), ``cylinder``
(centre of its base, axis, radius, height), ``ring`` (centre, axis, inner, outer, height) or ``extrusion``
(outline of [u, v] vertices, optional holes (polygons) and circles ([u, v, radius] round holes), axis, base,
height); all take name, material, region and poling (0, 1, -1, "+x" ... "-z" (a box: along z only), and
"radial" / "-radial" for rings). Lengths in the file's units, scaled to metres here; the shapes themselves check
their geometry (``modalfe.geometry.shapes``).

A scene whose ``[geometry] file`` names a CAD, ``.geo`` or ``.msh`` file has part tables of another form
(``imported_parts``): ``group`` (the file's physical volume), material, region, poling, and for radial poling
``axis`` and ``centre``; its shapes are the file's.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import modalfe.scene.values as v
from modalfe.errors import SceneError

SHAPES = ("box", "cylinder", "ring", "extrusion")
_COMMON = ("name", "shape", "region", "material", "poling")
_KEYS = {
    "box": ("origin", "size"),
    "cylinder": ("centre", "axis", "radius", "height"),
    "ring": ("centre", "axis", "inner", "outer", "height"),
    "extrusion": ("outline", "holes", "circles", "axis", "base", "height"),
}
_OPTIONAL = {"holes", "circles"}


_IMPORTED_KEYS = ("group", "material", "region", "poling", "axis", "centre")


def imported_parts(parts: Any, *, scale: float = 1.0) -> list[dict]:
    """Part tables of a scene with a geometry file, checked (``centre`` scaled to metres); groups unique."""
    if isinstance(parts, Mapping):
        raise SceneError("parts: must be an array of tables ([[parts]] for each part), got a single table")
    items = v.array("parts", parts)
    if not items:
        raise SceneError("parts: a scene file needs at least one [[parts]] table")
    out, names = [], set()
    for i, p in enumerate(items):
        where = f"parts[{i}]"
        p = v.table(where, p)
        v.known_keys(where, p, _IMPORTED_KEYS)
        for key in ("group", "material"):
            if key not in p:
                raise SceneError(f"{where}.{key}: missing (a part of a geometry file needs group, the physical "
                                 "volume's name, and material)")
        group = v.string(f"{where}.group", p["group"])
        if group in names:
            raise SceneError(f"{where}.group: '{group}' is used by another part")
        names.add(group)
        q: dict[str, Any] = {"group": group, "material": v.string(f"{where}.material", p["material"])}
        if "region" in p:
            q["region"] = v.string(f"{where}.region", p["region"])
        if "poling" in p:
            poling = p["poling"]
            q["poling"] = v.integer(f"{where}.poling", poling) if not isinstance(poling, str) else poling
        if "axis" in p:
            q["axis"] = v.string(f"{where}.axis", p["axis"], choices=("x", "y", "z"))
        if "centre" in p:
            q["centre"] = [scale * x for x in v.numbers3(f"{where}.centre", p["centre"], unit="m")]
        if str(q.get("poling", "")).endswith("radial") and not {"axis", "centre"} <= set(q):
            raise SceneError(f"{where}.poling: radial poling of a part from a geometry file needs its axis and "
                             "centre (a point on the axis) in the part table")
        out.append(q)
    return out


def has_shapes(parts: Any) -> bool:
    """Whether some part table names a shape other than a box."""
    return isinstance(parts, (list, tuple)) and any(isinstance(p, Mapping) and p.get("shape", "box") != "box"
                                                     for p in parts)


def shaped_parts(parts: Any, *, scale: float = 1.0, field: str = "parts") -> list[dict]:
    """Part tables checked and scaled to metres (see the module docstring); names unique."""
    if isinstance(parts, Mapping):
        raise SceneError(f"{field}: must be an array of tables ([[{field}]] for each part), got a single table")
    items = v.array(field, parts)
    if not items:
        raise SceneError(f"{field}: a scene file needs at least one [[{field}]] table")
    out, names = [], set()
    for i, p in enumerate(items):
        where = f"{field}[{i}]"
        p = v.table(where, p)
        shape = v.string(f"{where}.shape", p.get("shape", "box"), choices=SHAPES)
        v.known_keys(where, p, _COMMON + _KEYS[shape])
        for key in ("name", "material", *_KEYS[shape]):
            if key not in p and key not in _OPTIONAL:
                raise SceneError(f"{where}.{key}: missing (a {shape} needs name, material, {', '.join(_KEYS[shape])})")
        name = v.string(f"{where}.name", p["name"])
        if name in names:
            raise SceneError(f"{where}.name: '{name}' is used by another part")
        names.add(name)
        q: dict[str, Any] = {"name": name, "shape": shape, "material": v.string(f"{where}.material", p["material"])}
        if "region" in p:
            q["region"] = v.string(f"{where}.region", p["region"])
        if "poling" in p:
            poling = p["poling"]
            q["poling"] = v.integer(f"{where}.poling", poling) if not isinstance(poling, str) else poling
        for key in _KEYS[shape]:
            if key not in p:
                continue
            at = f"{where}.{key}"
            if key == "axis":
                q[key] = v.string(at, p[key], choices=("x", "y", "z"))
            elif key in ("origin", "centre"):
                q[key] = [scale * x for x in v.numbers3(at, p[key], unit="m")]
            elif key == "size":
                q[key] = [scale * x for x in v.numbers3(at, p[key], unit="m", positive=True)]
            elif key == "outline":
                q[key] = _loop(at, p[key], scale)
            elif key == "circles":
                q[key] = [[scale * x for x in v.numbers3(f"{at}[{j}]", c, unit="m")]
                          for j, c in enumerate(v.array(at, p[key]))]
            elif key == "holes":
                q[key] = [_loop(f"{at}[{j}]", h, scale) for j, h in enumerate(v.array(at, p[key]))]
            elif key == "base":
                q[key] = scale * v.number(at, p[key], unit="m")
            else:  # radius, inner, outer, height
                q[key] = scale * v.number(at, p[key], unit="m", positive=True)
        out.append(q)
    return out


def _loop(field: str, value: Any, scale: float) -> list[list[float]]:
    """A polygon: a list of [u, v] pairs, scaled."""
    items = v.array(field, value)
    return [[scale * v.number(f"{field}[{j}][{k}]", x, unit="m") for k, x in enumerate(v.array(f"{field}[{j}]", pt,
                                                                                              length=2))]
            for j, pt in enumerate(items)]
