"""The ``modalfe`` command: a thin layer over the library that parses, calls and prints.

Every subcommand module is imported and registered explicitly: one that fails to import is an error,
not a missing command."""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import logging
import os
import shlex
import sys
import traceback

from modalfe.cli import view
from modalfe.cli.options import check_output_paths
from modalfe.errors import ModalfeError, SceneError
from modalfe.progress import shown, wanted

EXIT_INPUT, EXIT_FAILED, EXIT_INTERNAL, EXIT_INTERRUPTED = 2, 1, 70, 130


class OneLineParser(argparse.ArgumentParser):
    """argparse with one-line errors: ``modalfe: error: --count: must be ...`` and exit status 2."""

    def error(self, message: str) -> None:
        message = message.replace("argument ", "", 1)
        required = "the following arguments are required: "
        if message.startswith(required):  # name the missing field first, like every other error
            message = f"{message[len(required):]}: required"
        self.exit(EXIT_INPUT, f"modalfe: error: {' '.join(message.split())}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="modalfe", description=__doc__)
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress to stderr")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser)
    # the commands load the library as they register (~0.6 s of one core): after ``view.early_drawer`` has started
    from modalfe.cli import admittance, calibrate, contact, forced, info, modes, place, sensitivity, sweep, tune

    for group in (modes, forced, contact, view, sweep, info, place, admittance, sensitivity, tune, calibrate):
        group.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; exit status 0 done, 1 failed solve, 2 bad input, 70 a bug, 130 interrupted.

    With ``--json`` stdout carries only the JSON document; every other line goes to stderr."""
    argv = sys.argv[1:] if argv is None else list(argv)
    early = view.early_drawer(argv)  # `show`'s rendering process loads VTK while this one loads the library
    try:
        return _run(argv, early)
    finally:
        if early is not None:
            early.close()


def _run(argv: list[str], early) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except KeyboardInterrupt:
        print("modalfe: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    configure_logging(args.verbose)
    args.command_line = shlex.join(["modalfe", *argv])  # as typed, for pages
    args.early_drawer = early
    captured = io.StringIO() if getattr(args, "json", False) else None
    status = EXIT_INTERNAL
    try:
        check_output_paths(args)  # a missing folder or an unwritable file fails now, before any work
        with (contextlib.redirect_stdout(captured) if captured is not None else contextlib.nullcontext(),
              shown(wanted(captured is not None))):  # bars on a terminal's stderr, none with --json or piped
            status = args.func(args)
    except KeyboardInterrupt:
        status = _fail("interrupted", EXIT_INTERRUPTED, prefix="modalfe: ")
    except SceneError as exc:
        status = _fail(exc, EXIT_INPUT)
    except ModalfeError as exc:
        status = _fail(exc, EXIT_FAILED)
    except MemoryError:
        status = _fail("out of memory (coarsen the mesh: mesh.elements_per_wavelength, mesh.max_size)", EXIT_FAILED)
    except OSError as exc:
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        status = _fail(f"{where}{exc.strerror or exc}", EXIT_FAILED)
    except Exception as exc:  # a bug: one line, the traceback with -v
        if args.verbose:
            traceback.print_exc()
        status = _fail(f"internal error ({type(exc).__name__}: {' '.join(str(exc).split())}); this is a bug, "
                       f"rerun with -v for the traceback", EXIT_INTERNAL, prefix="modalfe: ")
    finally:
        if captured is not None:
            _emit_json(captured.getvalue(), status)
    return status


QUIET_LOGGERS = ("skfem", "distributed", "tornado", "bokeh", "asyncio", "matplotlib", "PIL", "numba")


def configure_logging(verbose: bool) -> None:
    """Warnings only; with ``-v`` modalfe's own steps and timings at INFO, never the libraries' chatter
    (scikit-fem logs every assembly at INFO, dask's ``distributed`` every worker, VTK every offscreen window)."""
    logging.basicConfig(level=logging.WARNING, format="%(asctime)s %(levelname)s %(name)s: %(message)s",
                        datefmt="%H:%M:%S")
    logging.getLogger("modalfe").setLevel(logging.INFO if verbose else logging.WARNING)
    for name in QUIET_LOGGERS:
        logging.getLogger(name).setLevel(logging.WARNING)


def _fail(exc: object, status: int, prefix: str = "modalfe: error: ") -> int:
    print(f"{prefix}{' '.join(str(exc).split())}", file=sys.stderr)
    return status


def _emit_json(text: str, status: int) -> None:
    """The JSON document of ``text`` to stdout, anything printed around it to stderr."""
    document, rest = _split_json(text) if status == 0 else (None, text)
    if rest.strip():
        sys.stderr.write(rest if rest.endswith("\n") else rest + "\n")
    if document is not None:
        sys.stdout.write(document + "\n")
        sys.stdout.flush()


def _split_json(text: str) -> tuple[str | None, str]:
    decoder = json.JSONDecoder()
    start = 0
    while start < len(text):
        if text[start] in "[{":
            try:
                _, end = decoder.raw_decode(text, start)
            except ValueError:
                end = -1
            if end > 0 and (end == len(text) or text[end:].split("\n", 1)[0].strip() == ""):
                return text[start:end], text[:start] + text[end:].lstrip("\n")
        newline = text.find("\n", start)
        if newline < 0:
            break
        start = newline + 1
    return None, text


if __name__ == "__main__":
    try:
        sys.exit(main())
    except BrokenPipeError:  # `modalfe ... | head`
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        sys.exit(EXIT_FAILED)
