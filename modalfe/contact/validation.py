"""Parameter checks shared by the contact simulators: each failure is a one-line ContactError that
starts with the name of the field at fault."""

from __future__ import annotations

import math
from dataclasses import fields, replace

import numpy as np

from modalfe.errors import ContactError


def require(name: str, value, *, positive: bool = False, nonnegative: bool = False) -> float:
    """``value`` as a finite float, or a one-line ContactError naming ``name``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ContactError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ContactError(f"{name}: must be finite, got {x}")
    if positive and x <= 0:
        raise ContactError(f"{name}: must be positive, got {x:g}")
    if nonnegative and x < 0:
        raise ContactError(f"{name}: must be >= 0, got {x:g}")
    return x


def require_fields(obj, *, positive: tuple[str, ...] = (), nonnegative: tuple[str, ...] = ()) -> None:
    """``require`` on the named fields of a parameter dataclass."""
    for name in positive:
        require(name, getattr(obj, name), positive=True)
    for name in nonnegative:
        require(name, getattr(obj, name), nonnegative=True)


def values(name: str, x, *, nonnegative: bool = True) -> np.ndarray:
    """A 1-D array of finite numbers (>= 0 unless told), or a one-line ContactError naming the entry."""
    try:
        arr = np.atleast_1d(np.asarray(x, dtype=float))
    except (TypeError, ValueError):
        raise ContactError(f"{name}: expected numbers, got {x!r}") from None
    if arr.ndim != 1 or arr.size == 0:
        raise ContactError(f"{name}: expected a number or a 1-D sequence of numbers")
    for i, xi in enumerate(arr):
        require(f"{name}[{i}]" if arr.size > 1 else name, xi, nonnegative=nonnegative)
    return arr


def choice(name: str, value, allowed: tuple[str, ...]) -> str:
    """``value`` if it is one of ``allowed``, else a one-line ContactError naming ``name``."""
    if value not in allowed:
        raise ContactError(f"{name}: expected one of {allowed}, got {value!r}")
    return value


def replaced(params, kind: str, changes: dict):
    """A validated copy of a parameter dataclass with ``changes``; unknown names raise ContactError."""
    known = {f.name for f in fields(params)}
    for key in changes:
        if key not in known:
            raise ContactError(f"{key}: not a {kind} parameter (known: {', '.join(sorted(known))})")
    return replace(params, **changes)
