"""Read-only, hashable values for scene fields: ``FrozenMap`` and the deep ``freeze`` that makes them.

A scene's tables (builder parameters, electrodes, clamps, springs, masses, materials) are frozen on
construction: nested dicts become ``FrozenMap``, lists and tuples become tuples, numpy arrays nested
tuples, sets frozensets. The scene can then be hashed, compared and used as a cache key, and nothing
downstream can change it in place.
"""

from __future__ import annotations

import sys
from collections.abc import Iterator, Mapping, Set
from typing import Any


class FrozenMap(Mapping):
    """An immutable, hashable mapping, equal to any mapping with the same items (like a dict).

    ``dict(m)``, ``m.items()``, ``{**m}`` and ``m.get`` work as for a dict; ``to_dict()`` gives plain
    dicts and lists back (for JSON or TOML). Keys keep their insertion order; the hash does not depend
    on it.
    """

    __slots__ = ("_data", "_hash")

    def __init__(self, data: Mapping[Any, Any] | None = None, /, **kwargs: Any) -> None:
        items = dict(data or {}, **kwargs)
        object.__setattr__(self, "_data", {key: freeze(value) for key, value in items.items()})
        object.__setattr__(self, "_hash", None)

    def __getitem__(self, key: Any) -> Any:
        return self._data[key]

    def __iter__(self) -> Iterator[Any]:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def __contains__(self, key: object) -> bool:
        return key in self._data

    def __hash__(self) -> int:
        if self._hash is None:
            object.__setattr__(self, "_hash", hash(frozenset(self._data.items())))
        return self._hash

    def __eq__(self, other: object) -> bool:
        if isinstance(other, FrozenMap):
            return self._data == other._data
        if isinstance(other, Mapping):  # compared frozen: {"k": [1, 2]} equals FrozenMap({"k": (1, 2)})
            return self._data == FrozenMap(other)._data
        return NotImplemented

    def __repr__(self) -> str:
        return f"FrozenMap({self._data!r})"

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"FrozenMap is read-only (cannot set '{name}')")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"FrozenMap is read-only (cannot delete '{name}')")

    def __reduce__(self) -> tuple:
        return (FrozenMap, (self._data,))

    def __copy__(self) -> FrozenMap:
        return self

    def __deepcopy__(self, memo: dict) -> FrozenMap:
        return self

    def __or__(self, other: Mapping) -> FrozenMap:
        return FrozenMap({**self._data, **other})

    def to_dict(self) -> dict[Any, Any]:
        """Plain dicts and lists all the way down (the form TOML or JSON would give)."""
        return {key: thaw(value) for key, value in self._data.items()}


def freeze(value: Any) -> Any:
    """``value`` made deeply immutable: mappings -> FrozenMap, lists/tuples/arrays -> tuples,
    sets -> frozensets; anything else is returned as is."""
    if isinstance(value, FrozenMap):
        return value
    if isinstance(value, Mapping):
        return FrozenMap(value)
    numpy = sys.modules.get("numpy")  # no numpy import here: ``import modalfe`` stays light
    if numpy is not None and isinstance(value, numpy.ndarray):
        return freeze(value.tolist())
    if isinstance(value, (list, tuple)):
        frozen = tuple(freeze(v) for v in value)
        # keep a named tuple's type (and an already frozen tuple itself)
        if type(value) is tuple:
            return value if all(a is b for a, b in zip(frozen, value)) else frozen
        return type(value)(*frozen) if hasattr(value, "_fields") else frozen
    if isinstance(value, Set) and not isinstance(value, frozenset):
        return frozenset(freeze(v) for v in value)
    return value


def thaw(value: Any) -> Any:
    """The inverse of ``freeze`` for JSON/TOML output: FrozenMap -> dict, tuples -> lists."""
    if isinstance(value, Mapping):
        return {key: thaw(v) for key, v in value.items()}
    if isinstance(value, (tuple, list)):
        return [thaw(v) for v in value]
    if isinstance(value, Set):
        return [thaw(v) for v in value]
    return value
