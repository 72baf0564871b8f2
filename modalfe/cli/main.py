"""The ``modalfe`` command: a thin layer over the library that parses, calls and prints.

Every subcommand module is imported and registered explicitly: one that fails to import is an error,
not a missing command."""

from __future__ import annotations

import argparse
import logging
import sys

from modalfe.cli import contact, forced, modes, sweep, view
from modalfe.errors import ModalfeError, SceneError

COMMAND_GROUPS = (modes, forced, contact, view, sweep)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="modalfe", description=__doc__)
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress to stderr")
    sub = parser.add_subparsers(dest="command", required=True)
    for group in COMMAND_GROUPS:
        group.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")
    try:
        return args.func(args)
    except SceneError as exc:
        print(f"modalfe: error: {exc}", file=sys.stderr)
        return 2
    except ModalfeError as exc:
        print(f"modalfe: error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
