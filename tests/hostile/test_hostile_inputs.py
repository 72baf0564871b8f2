"""The hostile-input suite (issue 16): no traceback, no hang, no silent wrong answer on any case; every
case gives the verdict it expects (``owner`` names the part of the code a case exercises)."""

import collections

import pytest

from tests.hostile.cases import CASES
from tests.hostile.harness import BAD, run_case


@pytest.fixture(autouse=True)
def _own_cache(tmp_path_factory, monkeypatch):
    monkeypatch.setenv("MODALFE_CACHE", str(tmp_path_factory.getbasetemp() / "hostile-cache"))


def _param(case):
    marks = [pytest.mark.slow] if case.slow else []
    return pytest.param(case, id=case.id, marks=marks)


def test_the_suite_is_large_and_its_ids_unique():
    ids = [c.id for c in CASES]
    assert len(ids) >= 150
    assert [i for i, n in collections.Counter(ids).items() if n > 1] == []
    assert {c.expect for c in CASES} <= {"error", "ok", "interrupt"}


@pytest.mark.parametrize("case", [_param(c) for c in CASES])
def test_case(case, tmp_path):
    observed = run_case(case, tmp_path)
    assert observed.verdict not in BAD, f"{case.input}: {observed.verdict}: {observed.detail}"
    wanted = "clear error" if case.expect == "error" else "handled"
    assert observed.verdict == wanted, f"{case.input}: {observed.verdict}: {observed.detail}"
