"""Options and parsing shared by the ``modalfe`` subcommands."""

from __future__ import annotations

import argparse
import sys

from modalfe.errors import SceneError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def parse_overrides(pairs: list[str] | None) -> dict:
    """``key=value`` pairs; values are read as TOML literals (numbers, arrays, strings)."""
    out = {}
    for pair in pairs or []:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise SceneError(f"--set: expected key=value, got '{pair}'")
        try:
            out[key.strip()] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            out[key.strip()] = value
    return out


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got '{text}'") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {value}")
    return value


def fidelity_options(p: argparse.ArgumentParser) -> None:
    from modalfe.solve.api import DEFAULT_TOL, FIDELITIES

    p.add_argument("--fidelity", choices=FIDELITIES, default="auto",
                   help="model: 1-D beam, 2-D plate, 3-D solid, or auto: the cheapest meeting --tol (default)")
    p.add_argument("--tol", type=float, default=DEFAULT_TOL,
                   help=f"relative frequency error asked of --fidelity auto (default {DEFAULT_TOL:g})")
