"""Shared test set-up: a private mesh cache per test session, so tests never touch ~/.cache."""

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    mp = pytest.MonkeyPatch()
    mp.setenv("MODALFE_CACHE", str(tmp_path_factory.mktemp("modalfe-cache")))
    yield
    mp.undo()
