"""Checks of single values read from scene files, ``--set`` or the API: each raises a one-line
``SceneError`` that starts with the field at fault (``analysis.near: must be ...``)."""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence
from typing import Any

from modalfe.errors import SceneError


def is_number(value: Any) -> bool:
    """A real number that is not a bool (TOML ``true`` must never become 1)."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _shown(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def number(field: str, value: Any, *, unit: str = "", minimum: float | None = None, positive: bool = False,
           allow_inf: bool = False) -> float:
    """``value`` as a float: a finite real number (``inf`` only with ``allow_inf``), >= ``minimum``
    or > 0 with ``positive``."""
    u = f" [{unit}]" if unit else ""
    if isinstance(value, str):
        raise SceneError(f"{field}: must be a number{u}, got the string {_shown(value)} "
                         f"(write plain SI numbers, e.g. 0.65e-3 for 0.65 mm)")
    if not is_number(value):
        raise SceneError(f"{field}: must be a number{u}, got {_shown(value)}")
    x = float(value)
    if math.isnan(x) or (math.isinf(x) and not (allow_inf and x > 0)):
        raise SceneError(f"{field}: must be a finite number{u}, got {x}")
    if positive and not x > 0:
        raise SceneError(f"{field}: must be positive{u}, got {x:g}")
    if minimum is not None and not x >= minimum:
        raise SceneError(f"{field}: must be >= {minimum:g}{u}, got {x:g}")
    return x


def integer(field: str, value: Any, *, minimum: int | None = None, maximum: int | None = None) -> int:
    """``value`` as an int (a float with an integer value is refused too: counts are written as integers)."""
    if not (isinstance(value, numbers.Integral) and not isinstance(value, bool)):
        raise SceneError(f"{field}: must be an integer, got {_shown(value)}")
    n = int(value)
    if minimum is not None and n < minimum:
        raise SceneError(f"{field}: must be an integer >= {minimum}, got {n}")
    if maximum is not None and n > maximum:
        raise SceneError(f"{field}: must be an integer <= {maximum}, got {n}")
    return n


def string(field: str, value: Any, *, choices: Sequence[str] | None = None) -> str:
    """``value`` as a non-empty string, one of ``choices`` when given."""
    if not isinstance(value, str) or not value:
        raise SceneError(f"{field}: must be a non-empty string, got {_shown(value)}")
    if choices is not None and value not in choices:
        raise SceneError(f"{field}: must be one of {', '.join(repr(c) for c in choices)}, got {_shown(value)}")
    return value


def table(field: str, value: Any) -> Mapping:
    """``value`` as a table (TOML ``[field]``)."""
    if not isinstance(value, Mapping):
        raise SceneError(f"{field}: must be a table ([{field}] with key = value lines), got {_shown(value)}")
    return value


def array(field: str, value: Any, *, length: int | None = None) -> list:
    """``value`` as a list (TOML array), of ``length`` items when given."""
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Sequence):
        what = f"a list of {length}" if length else "a list"
        raise SceneError(f"{field}: must be {what}, got {_shown(value)}")
    if length is not None and len(value) != length:
        raise SceneError(f"{field}: must be a list of {length}, got {len(value)} items")
    return list(value)


def numbers3(field: str, value: Any, *, unit: str = "", minimum: float | None = None,
             positive: bool = False) -> tuple[float, float, float]:
    """Three finite numbers (a point, a size, a stiffness per axis)."""
    items = array(field, value, length=3)
    return tuple(number(f"{field}[{i}]", v, unit=unit, minimum=minimum, positive=positive)
                 for i, v in enumerate(items))


def known_keys(field: str, value: Mapping, known: Sequence[str]) -> None:
    """Refuse a key not in ``known`` (a typo must not be dropped silently)."""
    for key in value:
        if key not in known:
            prefix = f"{field}." if field else ""
            raise SceneError(f"{prefix}{key}: unknown key; known: {', '.join(sorted(known))}")


PART_KEYS = ("name", "region", "material", "origin", "size", "poling")


def box_parts(parts: Any, *, scale: float = 1.0, field: str = "parts") -> list[dict]:
    """Box part tables checked and scaled to metres: name, material, origin, size (positive, finite),
    optional region and poling (-1, 0 or +1); names unique."""
    if isinstance(parts, Mapping):
        raise SceneError(f"{field}: must be an array of tables ([[{field}]] for each part), got a single table")
    items = array(field, parts)
    if not items:
        raise SceneError(f"{field}: a scene file needs at least one [[{field}]] table")
    out, names = [], set()
    for i, p in enumerate(items):
        where = f"{field}[{i}]"
        p = table(where, p)
        known_keys(where, p, PART_KEYS)
        for key in ("name", "material", "origin", "size"):
            if key not in p:
                raise SceneError(f"{where}.{key}: missing (a part needs name, material, origin, size)")
        name = string(f"{where}.name", p["name"])
        if name in names:
            raise SceneError(f"{where}.name: '{name}' is used by another part")
        names.add(name)
        q = {"name": name, "material": string(f"{where}.material", p["material"])}
        if "region" in p:
            q["region"] = string(f"{where}.region", p["region"])
        q["origin"] = [scale * v for v in numbers3(f"{where}.origin", p["origin"])]
        q["size"] = [scale * v for v in numbers3(f"{where}.size", p["size"], positive=True)]
        if any(not math.isfinite(v) or v <= 0 for v in q["size"]) or any(not math.isfinite(v) for v in q["origin"]):
            raise SceneError(f"{where}.size: out of range once scaled to metres")
        if "poling" in p:
            poling = integer(f"{where}.poling", p["poling"])
            if poling not in (-1, 0, 1):
                raise SceneError(f"{where}.poling: must be 1 (poled +z), -1 (poled -z) or 0, got {poling}")
            q["poling"] = poling
        out.append(q)
    return out


def face_groups(faces: Any, field: str = "faces", *, scale: float = 1.0) -> dict[str, list]:
    """Face groups: group -> list of 'part.side' strings, or of {face = 'part.side', window = [[u0, v0], [u1, v1]]}
    tables for a rectangle of a box face (in the face's two in-plane coordinates in xyz order, lengths x
    ``scale`` to metres)."""
    out = {}
    for group, refs in table(field, faces).items():
        refs = array(f"{field}.{group}", refs)
        entries = []
        for i, ref in enumerate(refs):
            where = f"{field}.{group}[{i}]"
            if not isinstance(ref, Mapping):
                entries.append(string(where, ref))
                continue
            known_keys(where, ref, ("face", "window"))
            if "face" not in ref or "window" not in ref:
                raise SceneError(f"{where}: a windowed face needs face = 'part.side' and window = [[u0, v0], [u1, v1]]")
            corners = array(f"{where}.window", ref["window"], length=2)
            window = [[number(f"{where}.window[{j}]", c, unit="length") * scale
                       for c in array(f"{where}.window[{j}]", corner, length=2)] for j, corner in enumerate(corners)]
            entries.append({"face": string(f"{where}.face", ref["face"]), "window": window})
        out[str(group)] = entries
    return out
