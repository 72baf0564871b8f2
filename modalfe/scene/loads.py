"""What drives a forced response, as scene data: a voltage on the driven electrodes, a force or pressure on a face
group, or a base acceleration of the supports (``Load``), and the checks a scene's load must pass before any solve.
The load vectors are assembled in ``modalfe.response.loads``."""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from modalfe.errors import SceneError
from modalfe.scene.checks import check_ground

KINDS = ("voltage", "force", "pressure", "base-acceleration")
UNITS = {"voltage": "V", "force": "N", "pressure": "Pa", "base-acceleration": "m/s^2"}


@dataclass(frozen=True)
class Load:
    """One load case: ``kind`` (one of KINDS), the face ``group`` it acts on (force, pressure),
    ``value`` (force: (Fx, Fy, Fz) [N] in total; pressure: (P,) [Pa]), ``axis`` (base acceleration)."""

    kind: str = "voltage"
    group: str | None = None
    value: tuple[float, ...] = ()
    axis: str | None = None

    def __post_init__(self) -> None:
        field = "drive.load"
        if self.kind not in KINDS:
            raise SceneError(f"{field}: kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        object.__setattr__(self, "value", tuple(float(x) for x in self.value))
        if self.kind in ("force", "pressure"):
            if not isinstance(self.group, str) or not self.group:
                raise SceneError(f"{field}.group: a {self.kind} needs a face group")
            n = 3 if self.kind == "force" else 1
            if len(self.value) != n or not all(math.isfinite(x) for x in self.value):
                what = "Fx, Fy, Fz [N]" if n == 3 else "one pressure [Pa]"
                raise SceneError(f"{field}.value: a {self.kind} needs {what}, got {list(self.value)}")
            if not any(self.value):
                raise SceneError(f"{field}.value: the {self.kind} is zero")
        if self.kind == "base-acceleration" and self.axis not in ("x", "y", "z"):
            raise SceneError(f"{field}.axis: base acceleration needs an axis x, y or z, got {self.axis!r}")

    @property
    def unit(self) -> str:
        """Unit of one load: the results are per this unit."""
        return UNITS[self.kind]

    @property
    def magnitude(self) -> float:
        """Size of the load as given: |F| [N] of a force, |P| [Pa] of a pressure, 1 for a voltage or a base
        acceleration. The response is per unit load (per N along the force, per Pa of the pressure's sign), so a
        force's or pressure's value gives its direction and sign, never its scale."""
        return math.hypot(*self.value) if self.kind in ("force", "pressure") else 1.0

    def describe(self) -> str:
        """The unit load the results are per: the same text for (0, 0, 1) and (0, 0, 2) N."""
        if self.kind == "voltage":
            return "voltage on the driven electrodes"
        if self.kind == "force":
            direction = ", ".join(f"{x / self.magnitude + 0.0:.4g}" for x in self.value)  # + 0.0: no "-0"
            return f"force along ({direction}) on '{self.group}', spread by area"
        if self.kind == "pressure":
            sense = "pushing into the body" if self.value[0] > 0 else "pulling out of the body"
            return f"pressure on '{self.group}', {sense}"
        return f"base acceleration along {self.axis} (clamps and spring anchors move rigidly)"

    @classmethod
    def parse(cls, text: str, field: str = "drive.load") -> Load:
        """``voltage``, ``force GROUP=Fx,Fy,Fz``, ``pressure GROUP=P`` or ``base-acceleration x|y|z``."""
        if not isinstance(text, str):
            raise SceneError(f"{field}: expected a load such as 'force actuator=0,0,1', got {text!r}")
        words = text.strip().split(None, 1)
        kind = words[0].replace("_", "-") if words else ""
        rest = words[1].strip() if len(words) > 1 else ""
        if kind == "voltage" and not rest:
            return cls()
        if kind == "base-acceleration":
            return cls(kind=kind, axis=rest or None)
        match = re.fullmatch(r"([^=\s]+)\s*=\s*(.+)", rest)
        if kind in ("force", "pressure") and match:
            try:
                numbers = tuple(float(x) for x in match.group(2).split(","))
            except ValueError:
                raise SceneError(f"{field}: expected numbers after '{match.group(1)}=', got {text!r}") from None
            return cls(kind=kind, group=match.group(1), value=numbers)
        raise SceneError(f"{field}: expected 'voltage', 'force GROUP=FX,FY,FZ', 'pressure GROUP=P' or "
                         f"'base-acceleration x|y|z', got {text!r}")

    @classmethod
    def from_value(cls, value, field: str = "drive.load") -> Load:
        """A Load, a text (``parse``) or a table ``{kind, group, value, axis}`` from a scene file."""
        if isinstance(value, Load):
            return value
        if isinstance(value, str):
            return cls.parse(value, field)
        if not isinstance(value, Mapping):
            raise SceneError(f"{field}: must be a text such as 'force actuator=0,0,1' or a table "
                             f"{{kind, group, value, axis}}, got {value!r}")
        unknown = sorted(set(value) - {"kind", "group", "value", "axis"})
        if unknown:
            raise SceneError(f"{field}.{unknown[0]}: unknown key; known: axis, group, kind, value")
        kind = value.get("kind", "voltage")
        if not isinstance(kind, str):
            raise SceneError(f"{field}.kind: must be one of {', '.join(KINDS)}, got {kind!r}")
        raw = value.get("value", ())
        raw = [raw] if isinstance(raw, (int, float)) and not isinstance(raw, bool) else raw
        if not isinstance(raw, (list, tuple)) or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                         for x in raw):
            raise SceneError(f"{field}.value: must be a number or an array of numbers, got {raw!r}")
        group = value.get("group")
        if group is not None and not isinstance(group, str):
            raise SceneError(f"{field}.group: must be a face group name, got {group!r}")
        return cls(kind=kind.replace("_", "-"), group=group, value=tuple(raw), axis=value.get("axis"))


def check_forcing(scene, load: Load) -> None:
    """``check_load``, and refuse to force a model of the antisymmetric family (``Scene.antisymmetry``)."""
    if scene.antisymmetry:
        raise SceneError("antisymmetry: forced response needs the symmetric family or the whole device (a load on "
                         "the modes antisymmetric about a plane is not supported); set antisymmetry = []")
    check_load(scene, load)


def check_load(scene, load: Load) -> None:
    """Refuse a load the scene cannot take, before any solve: a missing face group or driven electrode, a load
    that is not symmetric about the mirror planes of a half (quarter) model, or a base acceleration of a body with
    no support along its axis."""
    if load.kind == "voltage":
        if "drive" not in scene.electrodes.values():
            raise SceneError("drive.load: the scene has no driven electrode to apply a voltage to; give a force, "
                             "pressure or base acceleration (--force GROUP=FX,FY,FZ, --pressure GROUP=P, "
                             "--base-acceleration z, or drive.load)")
        check_ground(scene, "electrodes")
        return
    full = scene.full_assembly()
    if load.kind in ("force", "pressure") and load.group not in full.faces:
        raise SceneError(f"drive.load.group: no face group '{load.group}'; known: {sorted(full.faces)}")
    for axis in scene.symmetry:
        k = "xyz".index(axis)
        if load.kind == "base-acceleration" and load.axis == axis:
            raise SceneError(f"drive.load.axis: a base acceleration along {axis} is antisymmetric about the "
                             f"{axis} mid-plane the model keeps (symmetry); set symmetry = [] to solve it")
        if load.kind in ("force", "pressure"):
            lo, hi = _group_bounds(full, load.group)
            mid = 0.5 * (full.bounds[0][k] + full.bounds[1][k])
            if not math.isclose(lo[k] + hi[k], 2 * mid, rel_tol=0, abs_tol=1e-9 * (full.bounds[1][k] + 1)):
                raise SceneError(f"drive.load.group: '{load.group}' is not symmetric about the {axis} mid-plane "
                                 f"the model keeps (symmetry); load a symmetric group or set symmetry = []")
            if load.kind == "force" and load.value[k] != 0:
                raise SceneError(f"drive.load.value: a force along {axis} is antisymmetric about the {axis} "
                                 f"mid-plane the model keeps (symmetry); set symmetry = [] to solve it")
    if load.kind == "base-acceleration" and not supported_along(scene, load.axis):
        raise SceneError(f"drive.load: a base acceleration (--base-acceleration {load.axis}) moves the supports, and "
                         f"the scene has none along {load.axis} (no clamp of u{load.axis}, no spring with k{load.axis} "
                         f"> 0): the whole body would follow the base; add clamps or springs, or apply a force")


def supported_along(scene, axis: str) -> bool:
    """Whether a clamp, an edge support or a face spring holds the body to the ground along ``axis`` (x, y or z)."""
    k = "xyz".index(axis)
    held = [*scene.clamps.values(), *(edge["fix"] for edge in scene.edges.values())]
    return any(axis in components for components in held) or any(
        stiffness[k] > 0 for stiffness in scene.springs.values())


def _group_bounds(assembly, group: str) -> tuple[np.ndarray, np.ndarray]:
    los, his = [], []
    for f in assembly.faces[group]:
        _, _, lo, hi = assembly.part(f.part).face_bounds(f.side, f.window)
        los.append(lo)
        his.append(hi)
    return np.min(los, axis=0), np.max(his, axis=0)


