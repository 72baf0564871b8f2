"""Measured modes for model updating (``modalfe.design.calibration``): ``Measurement`` and the ``[[mode]]`` tables
of a TOML file that give them, each field checked before any solve."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from modalfe.errors import SceneError
from modalfe.results.labels import check_selector

_FIELDS = {"label", "frequency", "sigma", "wavelength", "wavelength_sigma"}


@dataclass(frozen=True)
class Measurement:
    """One measured mode: ``label`` (its shape, e.g. ``(0,6)``), ``frequency`` and its 1-sigma ``sigma`` [Hz];
    optionally its bending ``wavelength`` along the length and ``wavelength_sigma`` [m] (NaN when not measured)."""

    label: str
    frequency: float
    sigma: float
    wavelength: float = math.nan
    wavelength_sigma: float = math.nan


def read_measurements(path: str | Path) -> tuple[Measurement, ...]:
    """Measurements from a TOML file of ``[[mode]]`` tables (``measurements_from_dict``); SceneError naming the
    file and field at fault."""
    from modalfe.scene.loading import tomllib  # the standard library's, or tomli before Python 3.11

    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{path}: not valid TOML ({exc})") from None
    except UnicodeDecodeError as exc:
        raise SceneError(f"{path}: not UTF-8 text (byte {exc.start}: a binary file?); --measured takes a TOML file "
                         f"of [[mode]] tables") from None
    return measurements_from_dict(data, source=str(path))


def measurements_from_dict(data: Mapping, *, source: str = "measured") -> tuple[Measurement, ...]:
    """``{"mode": [{"label": "(0,6)", "frequency": 40.7e3, "sigma": 50.0, "wavelength": ..., "wavelength_sigma":
    ...}, ...]}``: frequency, sigma [Hz] and wavelength, wavelength_sigma [m] positive; sigma is required (there is
    no default uncertainty), wavelength_sigma with a wavelength; labels distinct."""
    if not isinstance(data, Mapping) or set(data) != {"mode"}:
        extra = sorted(set(data) - {"mode"}) if isinstance(data, Mapping) else []
        raise SceneError(f"{source}: {extra[0] if extra else 'mode'}: expected only [[mode]] tables")
    rows = data["mode"]
    if not isinstance(rows, list) or not rows or not all(isinstance(row, Mapping) for row in rows):
        raise SceneError(f"{source}: mode: give one or more [[mode]] tables")
    out = []
    for i, row in enumerate(rows):
        where = f"{source}: mode[{i}]"
        unknown = sorted(set(row) - _FIELDS)
        if unknown:
            raise SceneError(f"{where}.{unknown[0]}: unknown field; known: {sorted(_FIELDS)}")
        label = row.get("label")
        if not isinstance(label, str) or not label.strip():
            raise SceneError(f"{where}.label: required, the mode's shape label, e.g. \"(0,6)\"")
        check_selector(label, f"{where}.label")  # its form, before any solve
        values = {key: _positive(f"{where}.{key}", row[key]) if key in row else math.nan
                  for key in ("frequency", "sigma", "wavelength", "wavelength_sigma")}
        for key in ("frequency", "sigma"):
            if math.isnan(values[key]):
                raise SceneError(f"{where}.{key}: required ({'Hz' if key == 'frequency' else '1-sigma, Hz'})")
        if math.isnan(values["wavelength"]) != math.isnan(values["wavelength_sigma"]):
            missing, given = (("wavelength_sigma", "wavelength") if math.isnan(values["wavelength_sigma"])
                              else ("wavelength", "wavelength_sigma"))
            raise SceneError(f"{where}.{missing}: required with {given} [m]")
        out.append(Measurement(label.strip(), **values))
    labels = [m.label for m in out]
    for i, name in enumerate(labels):
        if name in labels[:i]:
            raise SceneError(f"{source}: mode[{i}].label: '{name}' measured twice; give each mode once")
    return tuple(out)


def _positive(field: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0):
        raise SceneError(f"{field}: must be a positive number (SI: Hz, m), got {value!r}")
    return float(value)
