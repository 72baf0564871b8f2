"""Loading scenes: a built-in by name, or a box-built device from a TOML file."""

from __future__ import annotations

import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from modalfe.errors import SceneError
from modalfe.scene.builtin import BUILTIN
from modalfe.scene.scene import Analysis, MeshSettings, Scene, Target, WorkingMode

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def load_scene(name_or_path: str | Path, **overrides: Any) -> Scene:
    """A built-in scene by name (``cube_plate``...) or a TOML scene file, with overrides applied."""
    key = str(name_or_path)
    if key in BUILTIN:
        scene = BUILTIN[key]()
    else:
        path = Path(key)
        if path.suffix != ".toml" or not path.exists():
            raise SceneError(
                f"scene: '{key}' is neither a built-in scene ({', '.join(sorted(BUILTIN))}) nor a .toml file"
            )
        scene = scene_from_toml(path)
    return scene.with_overrides(**overrides)


def scene_from_toml(path: Path) -> Scene:
    """Read a box-built device (see README, 'Scene files')."""
    try:
        data = tomllib.loads(Path(path).read_text())
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML ({exc})") from None
    return scene_from_dict(data, default_name=Path(path).stem)


_TOP_KEYS = {"name", "units", "parts", "faces", "materials", "electrodes", "clamps", "springs",
             "masses", "analysis", "mesh", "working_modes", "kind", "symmetry"}
_UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "um": 1e-6}


def scene_from_dict(data: Mapping[str, Any], default_name: str = "scene") -> Scene:
    unknown = set(data) - _TOP_KEYS
    if unknown:
        raise SceneError(f"{sorted(unknown)[0]}: unknown top-level key; known: {sorted(_TOP_KEYS)}")
    units = data.get("units", "m")
    if units not in _UNITS:
        raise SceneError(f"units: must be one of {sorted(_UNITS)}, got '{units}'")
    scale = _UNITS[units]
    parts = []
    for i, p in enumerate(data.get("parts", [])):
        p = dict(p)
        for key in ("origin", "size"):
            if key in p:
                try:
                    p[key] = [float(v) * scale for v in p[key]]
                except (TypeError, ValueError):
                    raise SceneError(f"parts[{i}].{key}: must be three numbers") from None
        parts.append(p)
    if not parts:
        raise SceneError("parts: a scene file needs at least one [[parts]] table")
    try:
        analysis = Analysis(**{k: (tuple(v) if k == "band" else v) for k, v in data.get("analysis", {}).items()})
        mesh = MeshSettings(**data.get("mesh", {}))
    except TypeError as exc:
        raise SceneError(f"analysis/mesh: {exc}") from None
    working_modes = []
    for i, w in enumerate(data.get("working_modes", [])):
        if "selector" not in w or "near" not in w:
            raise SceneError(f"working_modes[{i}]: needs selector and near [Hz]")
        targets = tuple(
            Target(str(t.get("name", "target")), float(t["value"]), str(t.get("unit", "Hz")),
                   str(t.get("kind", "reference")), str(t.get("source", "user scene file")))
            for t in w.get("targets", [])
        )
        working_modes.append(WorkingMode(str(w["selector"]), float(w["near"]), targets))
    scene = Scene(
        name=str(data.get("name", default_name)),
        device="boxes",
        params={"parts": parts, "faces": dict(data.get("faces", {}))},
        electrodes=dict(data.get("electrodes", {})),
        clamps=_clamps(data.get("clamps", {})),
        springs={k: tuple(float(x) for x in v) for k, v in data.get("springs", {}).items()},
        masses={k: float(v) for k, v in data.get("masses", {}).items()},
        materials=dict(data.get("materials", {})),
        analysis=analysis,
        mesh=mesh,
        working_modes=tuple(working_modes),
        kind=str(data.get("kind", "plate")),
        symmetry=tuple(data.get("symmetry", ())),
    )
    scene.validate()
    return scene


def _clamps(value) -> dict[str, str]:
    """``["clamp"]`` (all components fixed) or ``{clamp = "xyz", edge = "yz"}``."""
    if isinstance(value, Mapping):
        return {str(k): str(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return {str(k): "xyz" for k in value}
    raise SceneError("clamps: a list of face groups or a table group = components")
