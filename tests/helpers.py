"""Helpers shared by the test modules."""

import importlib.util
import sys
from pathlib import Path

import pytest

STUDIES = Path(__file__).resolve().parents[1] / "studies"


def load_study(name: str):
    """A script of studies/ as a module (studies/ is not a package)."""
    spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up while the file runs
    spec.loader.exec_module(module)
    return module


def assert_one_line_error(call, field: str, error: type[Exception]) -> None:
    """``call()`` raises ``error`` with one line that starts with the field at fault."""
    with pytest.raises(error) as info:
        call()
    message = str(info.value)
    assert message.startswith(field + ":") and "\n" not in message, message
