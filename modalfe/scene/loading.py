"""Loading scenes: a built-in by name, or a device of boxes (and cylinders, rings, extruded outlines:
``modalfe.scene.part_tables``) from a TOML file."""

from __future__ import annotations

import sys
from collections.abc import Mapping
from dataclasses import fields
from pathlib import Path
from typing import Any

import modalfe.scene.values as v
from modalfe.errors import SceneError
from modalfe.scene.builtin import BUILTIN
from modalfe.scene.part_tables import has_shapes, imported_parts, shaped_parts
from modalfe.scene.scene import KINDS, USER_DAMPING_SOURCE, Analysis, Drive, MeshSettings, Scene, Target, WorkingMode

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def load_scene(name_or_path: str | Path, **overrides: Any) -> Scene:
    """A built-in scene by name (``cube_plate``...) or a TOML scene file, with overrides applied."""
    if not isinstance(name_or_path, (str, Path)):
        raise SceneError(f"scene: must be a built-in name or a path to a .toml file, got {name_or_path!r}")
    key = str(name_or_path)
    if key in BUILTIN:
        scene = BUILTIN[key]()
    else:
        path = Path(key)
        if path.suffix.lower() != ".toml":
            raise SceneError(
                f"scene: '{key}' is neither a built-in scene ({', '.join(sorted(BUILTIN))}) nor a .toml file"
            )
        scene = scene_from_toml(path)
    return scene.with_overrides(**overrides)


def scene_from_toml(path: str | Path) -> Scene:
    """Read a box-built device (see docs/guide.md, 'Scene files')."""
    path = Path(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise SceneError(f"scene: '{path}': no such file") from None
    except IsADirectoryError:
        raise SceneError(f"scene: '{path}' is a directory, not a scene file") from None
    except OSError as exc:
        raise SceneError(f"scene: cannot read '{path}': {exc.strerror or exc}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(f"{path}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); "
                         f"scene files are TOML in UTF-8") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = " ".join(str(exc).split())
        raise SceneError(f"{path}: not valid TOML ({message})") from None
    return scene_from_dict(data, default_name=path.stem, folder=path.parent)


_TOP_KEYS = ("name", "units", "geometry", "parts", "faces", "materials", "electrodes", "clamps", "edges", "guides",
             "springs",
             "masses", "analysis", "mesh", "working_modes", "kind", "symmetry", "antisymmetry", "drive")
_DRIVE_KEYS = ("damping", "damping_source", "damping_fallback", "damping_fallback_source", "outputs", "load",
               "load_source")
_UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6}
_TARGET_KEYS = ("name", "value", "unit", "kind", "source")


def scene_from_dict(data: Mapping[str, Any], default_name: str = "scene", folder: str | Path = ".") -> Scene:
    """A scene from the tables of a scene file (boxes, shapes, or a ``[geometry] file`` relative to ``folder``);
    every value is checked and named when wrong."""
    v.table("scene file", data)
    v.known_keys("", data, _TOP_KEYS)
    units = v.string("units", data.get("units", "m"), choices=tuple(_UNITS))
    scale = _UNITS[units]
    if "parts" not in data:
        raise SceneError("parts: a scene file needs at least one [[parts]] table")
    geometry = _geometry(data.get("geometry"), Path(folder)) if "geometry" in data else None
    if geometry is not None and "faces" in data:
        raise SceneError("faces: a geometry file's face groups are its physical surfaces; remove the [faces] table")
    shapes = geometry is not None or has_shapes(data["parts"])
    if geometry is not None:
        params = {**geometry, "parts": imported_parts(data["parts"], scale=scale)}
    else:
        parts = shaped_parts(data["parts"], scale=scale) if shapes else v.box_parts(data["parts"], scale=scale)
        params = {"parts": parts, "faces": v.face_groups(data.get("faces", {}), scale=scale)}
    analysis_data = v.table("analysis", data.get("analysis", {}))
    v.known_keys("analysis", analysis_data, [f.name for f in fields(Analysis)])
    analysis = Analysis(**analysis_data)
    mesh_data = v.table("mesh", data.get("mesh", {}))
    v.known_keys("mesh", mesh_data, [f.name for f in fields(MeshSettings)])
    if shapes and (geometry is not None or len({p["axis"] for p in params["parts"] if p["shape"] != "box"}) != 1):
        # a geometry file, or curved parts on different axes, mesh with tetrahedra only: the default then (parts on
        # one axis keep swept hexahedra, modalfe.models.swept), as kind = "solid" is
        mesh_data = {"element": "tet", **mesh_data}
    mesh = MeshSettings(**mesh_data)
    materials = {str(k): dict(v.table(f"materials.{k}", m)) for k, m in v.table("materials",
                                                                                data.get("materials", {})).items()}
    electrodes = dict(v.table("electrodes", data.get("electrodes", {})))
    springs = {k: v.numbers3(f"springs.{k}", x, unit="N/m", minimum=0.0)
               for k, x in v.table("springs", data.get("springs", {})).items()}
    masses = {k: v.number(f"masses.{k}", x, unit="kg", positive=True)
              for k, x in v.table("masses", data.get("masses", {})).items()}
    working_modes = []
    if isinstance(data.get("working_modes", []), Mapping):
        raise SceneError("working_modes: must be an array of tables ([[working_modes]] for each)")
    for i, w in enumerate(v.array("working_modes", data.get("working_modes", []))):
        where = f"working_modes[{i}]"
        w = v.table(where, w)
        v.known_keys(where, w, ("selector", "near", "targets", "symmetric", "antisymmetric"))
        if "selector" not in w or "near" not in w:
            raise SceneError(f"{where}: needs selector and near [Hz]")
        targets = []
        for j, t in enumerate(v.array(f"{where}.targets", w.get("targets", []))):
            at = f"{where}.targets[{j}]"
            t = v.table(at, t)
            v.known_keys(at, t, _TARGET_KEYS)
            if "value" not in t:
                raise SceneError(f"{at}.value: missing")
            targets.append(Target(v.string(f"{at}.name", t.get("name", "target")),
                                  v.number(f"{at}.value", t["value"]),
                                  v.string(f"{at}.unit", t.get("unit", "Hz")),
                                  v.string(f"{at}.kind", t.get("kind", "reference"),
                                           choices=("measured", "reference", "analytic")),
                                  v.string(f"{at}.source", t.get("source", "user scene file"))))
        planes = {key: tuple(v.string(f"{where}.{key}[{i}]", a, choices=("x", "y", "z"))
                             for i, a in enumerate(v.array(f"{where}.{key}", w.get(key, []))))
                  for key in ("symmetric", "antisymmetric")}
        working_modes.append(WorkingMode(v.string(f"{where}.selector", w["selector"]),
                                         v.number(f"{where}.near", w["near"], unit="Hz", positive=True),
                                         tuple(targets), **planes))
    symmetry = v.array("symmetry", data.get("symmetry", []))
    antisymmetry = v.array("antisymmetry", data.get("antisymmetry", []))
    scene = Scene(
        name=v.string("name", data.get("name", default_name)),
        device="imported" if geometry is not None else "shaped" if shapes else "boxes",
        params=params,
        electrodes=electrodes,
        clamps=_clamps(data.get("clamps", {})),
        edges=dict(v.table("edges", data.get("edges", {}))),
        guides=dict(v.table("guides", data.get("guides", {}))),
        springs=springs,
        masses=masses,
        materials=materials,
        analysis=analysis,
        mesh=mesh,
        working_modes=tuple(working_modes),
        kind=v.string("kind", data.get("kind", "solid" if shapes else "plate"), choices=KINDS),
        symmetry=tuple(v.string(f"symmetry[{i}]", a, choices=("x", "y", "z")) for i, a in enumerate(symmetry)),
        antisymmetry=tuple(v.string(f"antisymmetry[{i}]", a, choices=("x", "y", "z"))
                           for i, a in enumerate(antisymmetry)),
        drive=_drive(data.get("drive", {}), scale),
    )
    scene.validate()
    return scene


def _geometry(value, folder: Path) -> dict[str, str]:
    """The ``[geometry]`` table: ``file`` (relative to the scene file's folder) -> its absolute path and the
    digest of its content (``modalfe.geometry.imported.file_digest``: part of the mesh cache key)."""
    from modalfe.geometry.imported import file_digest

    data = v.table("geometry", value)
    v.known_keys("geometry", data, ("file",))
    if "file" not in data:
        raise SceneError("geometry.file: missing (a .geo, .step, .brep or .msh file)")
    path = (folder / v.string("geometry.file", data["file"])).resolve()
    if not path.is_file():
        raise SceneError(f"geometry.file: '{path}' does not exist")
    return {"file": str(path), "digest": file_digest(path)}


def _drive(value, scale: float) -> Drive:
    """The ``[drive]`` table: damping (with damping_source), outputs (face groups, ``mean:GROUP``, or
    ``{name, point}`` in the file's units), load (a text or ``{kind, group, value, axis}``) with load_source."""
    data = v.table("drive", value)
    v.known_keys("drive", data, _DRIVE_KEYS)
    settings: dict[str, Any] = {}
    for what in ("damping", "damping_fallback", "load"):
        if what in data:
            settings[what] = data[what]
            settings[f"{what}_source"] = f"{USER_DAMPING_SOURCE} (scene file)"
        if f"{what}_source" in data:
            settings[f"{what}_source"] = v.string(f"drive.{what}_source", data[f"{what}_source"])
    outputs = []
    for i, item in enumerate(v.array("drive.outputs", data.get("outputs", []))):
        where = f"drive.outputs[{i}]"
        if isinstance(item, str):
            outputs.append(v.string(where, item))
            continue
        item = v.table(where, item)
        v.known_keys(where, item, ("name", "point"))
        if "name" not in item or "point" not in item:
            raise SceneError(f"{where}: a point output needs name and point = [x, y, z]")
        point = v.numbers3(f"{where}.point", item["point"])
        outputs.append((v.string(f"{where}.name", item["name"]), tuple(scale * x for x in point)))
    settings["outputs"] = tuple(outputs)
    return Drive(**settings)


def _clamps(value) -> dict[str, str]:
    """``["clamp"]`` (all components fixed) or ``{clamp = "xyz", edge = "yz"}``."""
    if isinstance(value, Mapping):
        return {str(k): v.string(f"clamps.{k}", c) for k, c in value.items()}
    if isinstance(value, (list, tuple)):
        return {v.string(f"clamps[{i}]", k): "xyz" for i, k in enumerate(value)}
    raise SceneError("clamps: a list of face groups or a table group = components")
