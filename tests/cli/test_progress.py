"""Progress on a terminal and early failure (issue 37 item 3): the steps that can take long (mesh and assembly, the
eigen solve of each level) show a bar on stderr when it is a terminal, none with --json or when stderr is piped; a bad
input fails before anything is meshed or solved."""

from __future__ import annotations

import io
import json
import sys

import pytest

import modalfe.progress as progress
from modalfe.cli.main import main
from tests.hostile.cases import BIMORPH, TINY

SOLVE = ("--fidelity", "solid", "--no-error-estimate")


class Terminal(io.StringIO):
    """A stderr that says it is a terminal, as a user's shell is."""

    def isatty(self) -> bool:
        return True


@pytest.fixture
def tiny(tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    return str(path)


def _run(monkeypatch, stderr, argv) -> tuple[int, str]:
    monkeypatch.setattr(sys, "stderr", stderr)
    monkeypatch.setattr(progress, "DELAY", 0.0)  # every step shows at once: the tiny solve takes well under 2 s
    status = main(list(argv))
    return status, stderr.getvalue()


def test_a_terminal_sees_each_step_of_the_solve(monkeypatch, tiny, capsys):
    status, err = _run(monkeypatch, Terminal(), ("modes", tiny, *SOLVE))
    assert status == 0
    assert "mesh and assembly" in err and "eigen solve, 3 modes near 2000 Hz, short circuit" in err
    assert "mesh and assembly" not in capsys.readouterr().out  # the bars go to stderr, never into the output


@pytest.mark.parametrize("stderr, extra", [(Terminal(), ("--json",)), (io.StringIO(), ())],
                         ids=["json-on-a-terminal", "piped"])
def test_no_bar_with_json_or_when_piped(monkeypatch, tiny, capsys, stderr, extra):
    status, err = _run(monkeypatch, stderr, ("modes", tiny, *SOLVE, *extra))
    assert status == 0
    assert "eigen solve" not in err and "mesh and assembly" not in err
    if extra:
        json.loads(capsys.readouterr().out)  # stdout is the JSON document alone


def test_progress_is_off_in_the_library_unless_asked():
    assert not progress.is_shown()
    with progress.shown():
        assert progress.is_shown()
        with progress.shown(False):
            assert not progress.is_shown()
    assert not progress.is_shown()
    assert not progress.wanted(False, io.StringIO()) and progress.wanted(False, Terminal())
    assert not progress.wanted(True, Terminal())


def _bimorph(tmp_path) -> str:
    path = tmp_path / "bimorph.toml"
    path.write_text(BIMORPH)
    return str(path)


BAD = [  # (argv with {tiny} / {bimorph}, the field the one-line error names)
    (("forced", "{bimorph}", "--damping", "Q=-1"), "damping"),
    (("forced", "{bimorph}", "--mode", "(0,6"), "--mode"),
    (("forced", "{bimorph}", "--stress", "nowhere"), "stress"),
    (("forced", "{bimorph}", "--volts", "3"), "--volts"),
    (("admittance", "{bimorph}", "--band", "900", "300"), "--band"),
    (("admittance", "{bimorph}", "--band", "300", "900", "--damping", "Q=abc"), "--damping"),
    (("admittance", "{bimorph}", "--band", "300", "900", "--mode-damping", "nolabel"), "--mode-damping"),
    (("show", "{tiny}", "--out", "{tmp}/tiny.png"), "--mode"),
    (("export", "{tiny}", "--vtu", "{tmp}/tiny.txt"), "--vtu"),
    (("sensitivity", "{bimorph}", "--amplitude", "--damping", "Q=abc", "--vary", "materials.steel.E"),
     "damping"),
]


@pytest.mark.parametrize("argv, field", BAD, ids=[" ".join(a[:1] + a[2:4]) for a, _ in BAD])
def test_bad_input_fails_before_any_mesh_or_solve(monkeypatch, tmp_path, capsys, argv, field):
    import modalfe.solve.levels as levels

    def no_solve(*_args, **_kw):
        raise AssertionError("meshed or solved before the input was checked")

    monkeypatch.setattr(levels, "build_model", no_solve)
    monkeypatch.setattr(levels, "eigenpairs", no_solve)
    names = {"tiny": str(tmp_path / "tiny.toml"), "bimorph": _bimorph(tmp_path), "tmp": str(tmp_path)}
    (tmp_path / "tiny.toml").write_text(TINY)
    status = main([a.format(**names) for a in argv])
    err = capsys.readouterr().err
    assert status in (1, 2), err
    assert "meshed or solved" not in err and "internal error" not in err
    line = err.strip().splitlines()[-1]
    assert line.startswith("modalfe: error:") and field in line, line
