"""Builder parameters as data: name, type, default, unit and constraint, read from the signature.

A builder annotates each keyword with its type and, through ``typing.Annotated``, a constraint and a
unit: ``length: Annotated[float, Positive, Unit("m")] = 64e-3``, or one of the aliases below
(``Length``, ``Gap``, ``Count``...). ``parameters_of`` reads them; ``Parameter.check`` validates a
value against them and raises a one-line ``SceneError`` naming the parameter.
"""

from __future__ import annotations

import inspect
import math
import numbers
import types
import typing
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Annotated, Any, Union

from modalfe.errors import SceneError


class Constraint:
    """A condition on a number; ``text`` completes "must be ..."."""

    text = ""

    def holds(self, value: float) -> bool:
        raise NotImplementedError

    def __repr__(self) -> str:
        return f"<must be {self.text}>"


class _Positive(Constraint):
    text = "positive"

    def holds(self, value: float) -> bool:
        return value > 0


class _NonNegative(Constraint):
    text = ">= 0"

    def holds(self, value: float) -> bool:
        return value >= 0


@dataclass(frozen=True, repr=False)
class AtLeast(Constraint):
    """``value >= bound``."""

    bound: float

    @property
    def text(self) -> str:
        return f">= {self.bound:g}"

    def holds(self, value: float) -> bool:
        return value >= self.bound


Positive = _Positive()
NonNegative = _NonNegative()


@dataclass(frozen=True)
class Unit:
    """The SI unit of a number parameter (``"m"``, ``"kg"``...)."""

    symbol: str


# the usual builder parameters
Length = Annotated[float, Positive, Unit("m")]
Gap = Annotated[float, NonNegative, Unit("m")]
Count = Annotated[int, AtLeast(1)]


@dataclass(frozen=True)
class Parameter:
    """One builder parameter: ``kind`` is its annotation without the Annotated extras; ``default`` is
    None for a ``required`` one."""

    name: str
    kind: Any
    default: Any
    unit: str = ""
    constraint: Constraint | None = None
    required: bool = False

    @property
    def type_name(self) -> str:
        """The type as written: ``float``, ``tuple[float, ...]``, ``str | None``."""
        return _type_name(self.kind)

    def check(self, value: Any) -> None:
        """Raise SceneError("NAME: must be ..., got VALUE") unless ``value`` fits the type and constraint."""
        problem = _problem(self.kind, value)
        if problem is None and self.constraint is not None and _is_number(value) \
                and not self.constraint.holds(value):
            problem = self.constraint.text
        if problem is not None:
            unit = f" {self.unit}" if self.unit and _is_number(value) else ""
            raise SceneError(f"{self.name}: must be {problem}, got {value!r}{unit}")


def parameters_of(builder: Callable) -> dict[str, Parameter]:
    """The keyword parameters of ``builder`` as data, in signature order."""
    hints = typing.get_type_hints(builder, include_extras=True)
    out = {}
    for name, p in inspect.signature(builder).parameters.items():
        if p.kind not in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD):
            continue
        hint = hints.get(name, Any)
        unit, constraint = "", None
        if typing.get_origin(hint) is Annotated:
            for extra in hint.__metadata__:
                if isinstance(extra, Unit):
                    unit = extra.symbol
                elif isinstance(extra, Constraint):
                    constraint = extra
            hint = hint.__origin__
        required = p.default is inspect.Parameter.empty
        out[name] = Parameter(name, hint, None if required else p.default, unit, constraint, required)
    return out


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _problem(kind: Any, value: Any) -> str | None:
    """None if ``value`` fits ``kind``, else what it must be."""
    origin, args = typing.get_origin(kind), typing.get_args(kind)
    if kind is Any:
        return None
    if origin is Annotated:
        inner = _problem(args[0], value)
        if inner is None:
            for extra in kind.__metadata__:
                if isinstance(extra, Constraint) and _is_number(value) and not extra.holds(value):
                    return extra.text
        return inner
    if origin in (Union, types.UnionType):
        if value is None and type(None) in args:
            return None
        options = [a for a in args if a is not type(None)]
        problems = [_problem(a, value) for a in options]
        if any(p is None for p in problems):
            return None
        return problems[0] if len(problems) == 1 and value is not None else f"a {_type_name(kind)}"
    if kind is float:
        if not _is_number(value):
            return "a number"
        return None if math.isfinite(value) else "finite"
    if kind is int:
        if not (isinstance(value, numbers.Integral) and not isinstance(value, bool)):
            return "an integer"
        return None
    if kind is bool:
        return None if isinstance(value, bool) else "true or false"
    if kind is str:
        return None if isinstance(value, str) else "a string"
    if origin is tuple or origin in (Sequence, list):
        if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Sequence):
            return f"a list ({_type_name(kind)})"
        if origin is tuple and args and args[-1] is not Ellipsis:
            if len(value) != len(args):
                return f"a list of {len(args)} ({_type_name(kind)})"
            items = list(zip(args, value))
        else:
            item = args[0] if args else Any
            items = [(item, v) for v in value]
        if any(_problem(k, v) is not None for k, v in items):
            return f"a {_type_name(kind)}"
        return None
    if origin is Mapping or kind is Mapping:
        return None if isinstance(value, Mapping) else "a table"
    return None


def _type_name(kind: Any) -> str:
    origin, args = typing.get_origin(kind), typing.get_args(kind)
    if origin is Annotated:
        return _type_name(args[0])
    if origin in (Union, types.UnionType):
        return " | ".join(_type_name(a) for a in args)
    if kind is type(None):
        return "None"
    if kind is Ellipsis:
        return "..."
    if origin is not None:
        name = getattr(origin, "__name__", str(origin))
        return f"{name}[{', '.join(_type_name(a) for a in args)}]" if args else name
    return getattr(kind, "__name__", str(kind))
