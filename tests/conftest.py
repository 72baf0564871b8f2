"""Shared test set-up: a private mesh cache per test session, so tests never touch ~/.cache; no resolved answer
kept from one test to the next (``modalfe.solve.resolved``: each test solves what it asks, as its solve counts
expect; a test of the kept answers keeps them within itself); the design studies' helper modules
(studies/tile_design.py, studies/beam_design.py) importable as the studies import them."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    mp.setenv("MODALFE_CACHE", str(tmp_path_factory.mktemp("modalfe-cache")))
    yield
    mp.undo()


@pytest.fixture(autouse=True)
def _fresh_answers(_private_cache):
    from modalfe.solve import resolved

    resolved.clear(disk=True)
    yield
