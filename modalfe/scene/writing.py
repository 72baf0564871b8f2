"""Writing a scene as a scene file (docs/guide.md, 'Scene files'), so that ``load_scene`` reads back the same device.

A box scene is written as it is; a built-in builder's device (``cube_plate``...) as the boxes and face groups its
builder makes (``Scene.full_assembly``), lengths in metres. Every value that defines the device and its analysis
is written: parts, faces, materials, electrodes, clamps, edges, guides, springs, masses, analysis, mesh, kind,
symmetry, the drive (damping, load, outputs, with their sources) and the working modes with their targets. What the
file format has no place for (a built-in's assumption lines, its drive targets and reference spectra) is written as
comments.
A window of a face is written as {face = "part.side", window = [[u0, v0], [u1, v1]]}; a scene with a geometry
file names it by its absolute path.
"""

from __future__ import annotations

import json
import math
import numbers
import re
from collections.abc import Mapping, Sequence
from dataclasses import fields
from typing import Any

from modalfe.errors import SceneError
from modalfe.geometry import BUILDERS, SCENE_FILE_DEVICES
from modalfe.geometry.parts import Box
from modalfe.scene.scene import Analysis, MeshSettings, Scene

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def scene_to_toml(scene: Scene) -> str:
    """The text of a scene file (TOML) for ``scene`` (module docstring); SceneError for a scene it cannot write."""
    out = [f"# scene '{scene.name}' written by modalfe" + (f" from the built-in device '{scene.device}'"
                                                            if scene.device not in SCENE_FILE_DEVICES else ""),
           f"name = {_value(scene.name)}", 'units = "m"', f"kind = {_value(scene.kind)}",
           f"symmetry = {_value(list(scene.symmetry))}"]
    if scene.antisymmetry:
        out.append(f"antisymmetry = {_value(list(scene.antisymmetry))}")
    out += [f"# assumption: {line}" for line in scene.assumptions]
    out += [f"# reference spectrum ({family}): {text}" for family, text in scene.reference_spectra.items()]
    out += _table("analysis", {f.name: getattr(scene.analysis, f.name) for f in fields(Analysis)
                               if getattr(scene.analysis, f.name) is not None})
    out += _table("mesh", {f.name: getattr(scene.mesh, f.name) for f in fields(MeshSettings)
                           if getattr(scene.mesh, f.name) is not None})  # None: the default (harmonics as needed)
    for name, constants in scene.materials.items():
        out += _table(f"materials.{_key(name)}", constants)
    if scene.device == "imported":  # the geometry file by its absolute path; its physical groups name the faces
        out += _table("geometry", {"file": scene.params["file"]})
    parts, faces = _boxes(scene)
    for part in parts:
        out += ["", "[[parts]]"] + [f"{_key(k)} = {_value(x)}" for k, x in part.items()]
    for name in ("faces", "electrodes", "clamps", "edges", "guides", "springs", "masses"):
        if name != "faces" or scene.device != "imported":
            out += _table(name, faces if name == "faces" else getattr(scene, name))
    drive = scene.drive
    load = {k: x for k, x in (("kind", drive.load.kind), ("group", drive.load.group),
                              ("value", list(drive.load.value)), ("axis", drive.load.axis)) if x not in (None, [])}
    outputs = [o if isinstance(o, str) else {"name": o[0], "point": list(o[1])} for o in drive.outputs]
    out += _table("drive", {"damping": drive.damping, "damping_source": drive.damping_source,
                            "damping_fallback": drive.damping_fallback,
                            "damping_fallback_source": drive.damping_fallback_source, "load": load,
                            "load_source": drive.load_source, "outputs": outputs})
    out += [f"# drive target: {t.name} = {t.value!r} {t.unit} ({t.kind}; {t.source})" for t in drive.targets]
    for wm in scene.working_modes:
        targets = [{"name": t.name, "value": t.value, "unit": t.unit, "kind": t.kind, "source": t.source}
                   for t in wm.targets]
        out += ["", "[[working_modes]]", f"selector = {_value(wm.selector)}", f"near = {_value(wm.near)}",
                f"targets = {_value(targets)}"]
        out += [f"{key} = {_value(list(getattr(wm, key)))}" for key in ("symmetric", "antisymmetric")
                if getattr(wm, key)]
    return "\n".join(out) + "\n"


def _boxes(scene: Scene) -> tuple[list[dict], dict[str, list]]:
    """The part tables and face groups of the scene file: a scene file's own (boxes or shaped parts, lengths in
    metres), else its builder's assembly (boxes, and windows of their faces)."""
    if scene.device in SCENE_FILE_DEVICES:
        return [dict(p) for p in scene.params["parts"]], {g: list(r) for g, r in scene.params.get("faces", {}).items()}
    if scene.device not in BUILDERS:
        raise SceneError(f"device: unknown builder '{scene.device}'; known: {sorted(BUILDERS)}")
    assembly = scene.full_assembly()
    parts = []
    for part in assembly.parts:
        if isinstance(part, Box):
            table = {"name": part.name, "region": part.region, "material": part.material, "origin": list(part.lo),
                     "size": [_size(a, b) for a, b in zip(part.lo, part.hi)]}
        else:  # a cylinder, ring or extrusion of a built-in (cube_plate's round feet): its shape table (the whole
            # device's: no symmetry ``cuts``, which the scene's symmetry makes again)
            table = {"name": part.name, "shape": type(part).__name__.lower(),
                     **{f.name: getattr(part, f.name) for f in fields(part)
                        if f.name not in ("name", "poling", "cuts")}}
        parts.append({**table, "poling": part.poling} if part.poling else table)
    faces = {group: [f"{face.part}.{face.side}" if face.window is None else
                     {"face": f"{face.part}.{face.side}", "window": [list(corner) for corner in face.window]}
                     for face in members] for group, members in assembly.faces.items()}
    return parts, faces


def _size(lo: float, hi: float) -> float:
    """hi - lo [m], nudged by an ulp where needed so that lo + size == hi exactly (the box is rebuilt from it)."""
    size = hi - lo
    for candidate in (size, math.nextafter(size, math.inf), math.nextafter(size, -math.inf)):
        if lo + candidate == hi:
            return candidate
    return size


def _table(header: str, items: Mapping[str, Any]) -> list[str]:
    return ["", f"[{header}]"] + [f"{_key(k)} = {_value(x)}" for k, x in items.items()]


def _key(key: Any) -> str:
    key = str(key)
    return key if _BARE_KEY.match(key) else json.dumps(key)


def _value(x: Any) -> str:
    """One TOML value: string, boolean, integer, float (repr: exact), array or inline table."""
    if isinstance(x, str):
        return json.dumps(x)  # a JSON string is a TOML basic string (same escapes)
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, numbers.Integral):
        return str(int(x))
    if isinstance(x, numbers.Real):
        x = float(x)
        return repr(x) if math.isfinite(x) else ("nan" if math.isnan(x) else ("inf" if x > 0 else "-inf"))
    if isinstance(x, Mapping):
        return "{" + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in x.items()) + "}"
    if isinstance(x, Sequence):
        return "[" + ", ".join(_value(v) for v in x) + "]"
    raise SceneError(f"scene file: cannot write a {type(x).__name__} value ({x!r})")
