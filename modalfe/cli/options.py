"""Options and parsing shared by the ``modalfe`` subcommands."""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
from collections.abc import Mapping
from pathlib import Path

from modalfe.errors import SceneError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

# a number with a unit glued on (0.65mm, 40kHz, 200GPa): refused with a hint, never kept as a string
_NUMBER_WITH_UNIT = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*[A-Za-z%][A-Za-z0-9^/*%]*\s*$")
# output options checked before any work: option -> (flag, allowed suffixes or None)
MAX_SWEEP_POINTS = 10_000  # a sweep larger than this is almost certainly a typo in COUNT
OUTPUT_OPTIONS = {"out": "--out", "plot": "--plot", "vtu": "--vtu", "save_rom": "--save-rom"}


def parse_overrides(pairs: list[str] | None) -> dict:
    """``key=value`` pairs; values are read as TOML literals (numbers, arrays, strings, booleans). A bare
    word that is not TOML is taken as a string (``plate_material=CuBe``); a number with a unit is refused."""
    out = {}
    for pair in pairs or []:
        key, sep, value = pair.partition("=")
        key = key.strip()
        if not sep or not key:
            raise SceneError(f"--set: expected key=value, got '{pair}'")
        if key in out:
            raise SceneError(f"{key}: set twice with --set")
        if not value.strip():
            raise SceneError(f"{key}: --set needs a value after '='")
        try:
            out[key] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            if _NUMBER_WITH_UNIT.match(value):
                raise SceneError(f"{key}: '{value}' is a number with a unit; --set takes plain SI numbers "
                                 f"(metres, Hz, Pa, kg: e.g. 0.65mm -> 0.65e-3)") from None
            if any(c in value for c in "[]{}=,\"'") or value != value.strip():
                raise SceneError(f"{key}: '{value}' is not a TOML value (numbers, \"strings\", [lists], "
                                 f"true/false)") from None
            out[key] = value
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


def _float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got '{text}'") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got '{text}'")
    return value


def frequency(text: str) -> float:
    """argparse type: a frequency > 0 [Hz]."""
    value = _float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be a positive frequency [Hz], got {value:g}")
    return value


def frequency_or_zero(text: str) -> float:
    """argparse type: a frequency >= 0 [Hz] (0: the modes nearest zero, rigid-body modes of a free device)."""
    value = _float(text)
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"must be a frequency >= 0 [Hz], got {value:g}")
    return value


def positive_float(text: str) -> float:
    """argparse type: a finite number > 0."""
    value = _float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value:g}")
    return value


def check_band(band: list[float] | None) -> tuple[float, float] | None:
    """``--band F1 F2`` as a tuple with 0 <= F1 < F2."""
    if band is None:
        return None
    f1, f2 = band
    if not (0 <= f1 < f2):
        raise SceneError(f"--band: needs 0 <= F1 < F2 [Hz], got {f1:g} {f2:g}")
    return (f1, f2)


def check_output_path(flag: str, path: str, *, create_parents: bool = False) -> None:
    """Refuse an output path that cannot be written, before any work: a directory, a missing folder
    (unless ``create_parents``), a folder or file without write permission."""
    if not path or not path.strip():
        raise SceneError(f"{flag}: empty file name")
    p = Path(path)
    if p.is_dir():
        raise SceneError(f"{flag}: '{path}' is a directory; give a file name")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.exists():
        if not create_parents:
            raise SceneError(f"{flag}: folder '{parent}' does not exist")
        while not parent.exists():
            parent = parent.parent
    if not parent.is_dir():
        raise SceneError(f"{flag}: '{parent}' is not a folder")
    if p.exists():
        if not os.access(p, os.W_OK):
            raise SceneError(f"{flag}: '{path}' is not writable")
    elif not os.access(parent, os.W_OK | os.X_OK):
        raise SceneError(f"{flag}: folder '{parent}' is not writable")
    elif p.parent.exists():  # root passes os.access everywhere: creating the file tells (/proc, a read-only mount)
        try:
            p.open("xb").close()
        except OSError as exc:
            raise SceneError(f"{flag}: '{path}' cannot be written ({exc.strerror})") from None
        p.unlink()


def check_output_paths(args: argparse.Namespace) -> None:
    """Every output option of a parsed command line checked (``--out``, ``--plot``, ``--vtu``, ``--save-rom``, and
    ``--html``, a folder made if missing)."""
    html = getattr(args, "html", None)
    if html is not None and Path(html).exists() and not Path(html).is_dir():
        raise SceneError(f"--html: '{html}' is a file; give a folder (it is made if missing)")
    for name, flag in OUTPUT_OPTIONS.items():
        path = getattr(args, name, None)
        if path is None:
            continue
        check_output_path(flag, path, create_parents=(args.command == "sweep" and name == "out"))
        suffixes = {"vtu": (".vtu",), "save_rom": (".json",)}.get(name)
        if args.command == "show" and name == "out":
            suffixes = (".png", ".gif")
        if suffixes and Path(path).suffix.lower() not in suffixes:
            raise SceneError(f"{flag}: '{path}' must end in {' or '.join(suffixes)}")
        if name == "plot" and args.command == "forced":
            stem, dot, ext = path.rpartition(".")
            check_output_path(flag, f"{stem}_admittance.{ext}" if dot else f"{path}_admittance")


def parse_params(items: list[str]) -> dict[str, list[float]]:
    """``--param NAME=START:STOP:COUNT`` specs -> evenly spaced values; every part checked, names unique."""
    import numpy as np

    params, total = {}, 1
    for item in items:
        name, sep, spec = item.partition("=")
        name = name.strip()
        parts = spec.split(":")
        if not sep or not name or len(parts) != 3:
            raise SceneError(f"--param: expected NAME=START:STOP:COUNT, got '{item}'")
        if name in params:
            raise SceneError(f"--param {name}: given twice")
        try:
            start, stop = float(parts[0]), float(parts[1])
        except ValueError:
            raise SceneError(f"--param {name}: START and STOP must be numbers, got '{spec}'") from None
        if not (math.isfinite(start) and math.isfinite(stop)):
            raise SceneError(f"--param {name}: START and STOP must be finite, got '{spec}'")
        try:
            count = int(parts[2])
        except ValueError:
            raise SceneError(f"--param {name}: COUNT must be an integer, got '{parts[2]}'") from None
        if count < 1:
            raise SceneError(f"--param {name}: COUNT must be at least 1, got {count}")
        total *= count
        if total > MAX_SWEEP_POINTS:
            raise SceneError(f"--param {name}: the sweep would have {total} points or more (limit {MAX_SWEEP_POINTS})")
        params[name] = [float(x) for x in np.linspace(start, stop, count)]
    return params


def solve_options(p: argparse.ArgumentParser, *, tol: bool = True) -> None:
    """--fidelity, --tol (default ``modalfe.solve.api.DEFAULT_TOL``, one for every command; ``tol`` False: the
    command's own --tol sets it, as ``tune``'s) and --no-error-estimate: how a command that solves modes is answered
    (``solve_keywords``)."""
    from modalfe.solve.api import DEFAULT_TOL, FIDELITIES

    p.add_argument("--fidelity", choices=FIDELITIES, default="auto",
                   help="model: 1-D beam, 2-D plate, 2-D axisymmetric (a body of revolution: cylinders and rings "
                        "on one axis, harmonics n = 0..mesh.harmonics, refined to the tolerance), 3-D solid (refined "
                        "to the tolerance), or auto: the cheapest meeting the tolerance of beam, plate, axisymmetric "
                        "and solid (default)")
    if tol:
        p.add_argument("--tol", dest="solve_tol", type=positive_float, default=DEFAULT_TOL,
                       help=f"relative frequency error the modes asked about are answered at: the solid is refined "
                            f"(its element order, then its grid) until its stated error meets it (default "
                            f"{DEFAULT_TOL:g}, the same in every command)")
    p.add_argument("--no-error-estimate", action="store_true",
                   help="the scene's own mesh solved once, no refinement: the error is unknown (for the expert who "
                        "sets the mesh with --set mesh.*)")


def solve_keywords(args: argparse.Namespace) -> dict:
    """``solve_modes`` keywords from ``solve_options``' flags."""
    given = {"tol": args.solve_tol} if hasattr(args, "solve_tol") else {}
    return {"fidelity": args.fidelity, "error_estimate": not args.no_error_estimate, **given}


def stated(error: float) -> str:
    """A stated relative error as printed everywhere: a percentage, ``unresolved`` (inf) or ``unknown`` (NaN)."""
    if math.isnan(error):
        return "unknown"
    return "unresolved" if math.isinf(error) else f"{100 * error:.3f}%"


def parse_names(text: str, flag: str = "--vary") -> list[str]:
    """``P1,P2,...`` -> distinct names; SceneError naming ``flag`` if none or repeated."""
    names = [name.strip() for name in text.split(",") if name.strip()]
    if not names or len(set(names)) != len(names):
        raise SceneError(f"{flag}: give distinct parameter names separated by commas, got '{text}'")
    return names


def parse_target(text: str) -> tuple[str, float]:
    """``LABEL=HZ`` (``(0,6)=40.7e3``) -> (label, frequency [Hz])."""
    label, sep, value = text.rpartition("=")
    try:
        hz = float(value)
    except ValueError:
        hz = math.nan
    if not sep or not label.strip() or not (math.isfinite(hz) and hz > 0):
        raise SceneError(f"--target: expected LABEL=HZ with a positive frequency, e.g. \"(0,6)=40.7e3\", got '{text}'")
    return label.strip(), hz


def parse_fraction(flag: str, text: str) -> float:
    """``3%`` or ``0.03`` -> 0.03, in (0, 1); SceneError naming ``flag`` otherwise."""
    body = text.strip()
    percent = body.endswith("%")
    try:
        value = float(body[:-1] if percent else body) / (100 if percent else 1)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and 0 < value < 1):
        raise SceneError(f"{flag}: expected a fraction in (0, 1) or a percentage, e.g. 3%, got '{text}'")
    return value


def parse_positive(flag: str, name: str, text: str) -> float:
    """``text`` as a positive finite number; SceneError naming ``flag`` and ``name`` otherwise."""
    try:
        value = float(text)
    except ValueError:
        raise SceneError(f"{flag}: {name} must be a number, got '{text}'") from None
    if not (math.isfinite(value) and value > 0):
        raise SceneError(f"{flag}: {name} must be a positive finite number, got '{text}'")
    return value


def parse_outcome(flag: str, text: str, kinds: Mapping[str, tuple[str, ...]],
                  optional: Mapping[str, tuple[str, ...]] | None = None):
    """``KIND GIVEN=X ... [preload=N] [speed=M/S] [contact=foot|finger]`` -> (KIND, {GIVEN: X}, contact model),
    ``kinds``: KIND -> the names of its given numbers (``reduction``: a fraction or a percentage; ``volts``: a
    positive voltage), ``optional``: KIND -> other numbers it may be given (``width``: a fraction); the contact
    ``modalfe.contact.chain.FootContact`` (seed 000's, default) or ``FingerContact`` (seed 004's) at that preload [N]
    and sliding speed [m/s]. SceneError naming ``flag`` otherwise (before any solve)."""
    from modalfe.contact.chain import FingerContact, FootContact
    from modalfe.contact.finger import FingerParameters
    from modalfe.errors import ContactError

    optional = optional or {}
    form = " or ".join(f'"{k} ' + " ".join([f"{g}={g[0].upper()}" for g in given] + [
        f"[{o}={o[0].upper()}]" for o in optional.get(k, ())]) + '"' for k, given in kinds.items())
    form += ", then [preload=N] [speed=M/S] [contact=foot|finger]"
    kind, *pairs = text.split() or [""]
    given = kinds.get(kind)
    if given is None:
        raise SceneError(f"{flag}: expected {form}, got '{text}'")
    extras = optional.get(kind, ())
    keys = (*given, *extras, "preload", "speed", "contact")
    fields = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or key not in keys or key in fields:
            raise SceneError(f"{flag}: '{pair}' is not one of {'=, '.join(keys)}= (each once); expected {form}")
        fields[key] = value
    missing = [g for g in given if g not in fields]
    if missing:
        raise SceneError(f"{flag}: give {missing[0]}={missing[0][0].upper()}; expected {form}")
    numbers = {}
    for name in (*given, *(o for o in extras if o in fields)):
        text_value = fields.pop(name)
        fraction = name in ("reduction", "width")
        numbers[name] = parse_fraction(f"{flag} {name}", text_value) if fraction else \
            parse_positive(flag, name, text_value)
    contact = fields.pop("contact", "foot")
    if contact not in ("foot", "finger"):
        raise SceneError(f"{flag}: contact must be foot or finger, got '{contact}'")
    try:
        loads = {k: float(v) for k, v in fields.items()}
    except ValueError:
        raise SceneError(f"{flag}: preload and speed must be numbers, got '{text}'") from None
    try:
        model = FootContact(**loads) if contact == "foot" else FingerContact(FingerParameters().with_(**loads))
    except ContactError as exc:
        raise SceneError(f"{flag}: {exc}") from None
    return kind, numbers, model


def parse_bound(text: str) -> tuple[str, tuple[float, float]]:
    """``NAME=LOW:HIGH`` -> (name, (low, high)) with LOW < HIGH."""
    name, sep, span = text.partition("=")
    low, colon, high = span.partition(":")
    try:
        lo, hi = float(low), float(high)
    except ValueError:
        lo = hi = math.nan
    if not sep or not colon or not name.strip() or not (lo < hi):
        raise SceneError(f"--bounds: expected NAME=LOW:HIGH with LOW < HIGH, got '{text}'")
    return name.strip(), (lo, hi)


def scene_options(p: argparse.ArgumentParser, func) -> None:
    """The tail every scene-fitting subcommand shares (tune, calibrate, sensitivity): ``--set`` overrides, ``--json``
    output, and the handler ``func``."""
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter first")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=func)
