"""Every `modalfe ...` command shown in README.md and docs/*.md (issue 35): its subcommand and flags exist in the real
parser; a concrete one (no placeholder) parses, names a scene that exists, and passes every check made before the
first solve (the solve itself stands in: a documented example must not be refused on its input)."""

from __future__ import annotations

import re
import shlex
import shutil
from pathlib import Path

import pytest

from modalfe.cli.main import build_parser, main
from modalfe.errors import SolverError
from modalfe.scene.builtin import BUILTIN

ROOT = Path(__file__).resolve().parents[2]
# the hostile-input table lists commands refused on purpose
DOCUMENTS = [ROOT / "README.md", *sorted(p for p in (ROOT / "docs").glob("*.md") if p.name != "hostile_inputs.md")]
FENCE = re.compile(r"^\s*(```|~~~)")
HEREDOC = re.compile(r"^cat > (\S+) <<'(\w+)'\n(.*?)^\2$", re.M | re.S)
PLACEHOLDER = re.compile(r"^[A-Z][A-Z0-9_]*(\.\w+)?$|^\{\w+\}")  # SCENE, FILE.toml, P1, DISC.toml, {file}
STAND_IN = "stand-in solve: the input was accepted"


def _code_and_prose(text: str) -> tuple[list[str], str]:
    """(lines of fenced and indented code blocks, the prose joined into one line)."""
    code, prose, fenced = [], [], False
    for line in text.splitlines():
        if FENCE.match(line):
            fenced = not fenced
        elif fenced or line.startswith("    "):
            code.append(line.strip())
        else:
            prose.append(line)
    return code, " ".join(prose)


def documented_commands(path: Path) -> list[str]:
    """The `modalfe ...` lines of the code blocks (continued by a trailing backslash, comments dropped) and the
    `modalfe ...` code spans of the prose."""
    code, prose = _code_and_prose(path.read_text())
    out, i = [], 0
    while i < len(code):
        line = code[i]
        while line.endswith("\\") and i + 1 < len(code):
            i += 1
            line = line[:-1] + " " + code[i]
        if line.startswith("modalfe "):
            out.append(re.split(r"\s{2,}\(|\s+#\s", line)[0].strip())
        i += 1
    out += [m.group(1).strip() for m in re.finditer(r"`(modalfe [^`]+)`", prose)]
    return out


COMMANDS = [pytest.param(path, command, id=f"{path.name}:{command[:70]}")
            for path in DOCUMENTS for command in dict.fromkeys(documented_commands(path))]


def _words(command: str) -> list[str]:
    return shlex.split(command)[1:]


def _concrete(command: str) -> bool:
    """A command meant to be run as written: no optional part, alternative, ellipsis or placeholder, and more than
    the subcommand's name."""
    words = _words(command)
    return (len(words) > 1 and "..." not in command  # `[--json]` is optional; `symmetry=[]` a TOML array
            and not any(PLACEHOLDER.match(w) or "|" in w or w.startswith("[") for w in words))


def _subparsers() -> dict:
    parser = build_parser()
    action = next(a for a in parser._actions if a.dest == "command")
    return action.choices


def test_the_documents_show_commands():
    assert len(COMMANDS) > 40
    assert sum(_concrete(c.values[1]) for c in COMMANDS) >= 15


@pytest.mark.parametrize(("path", "command"), COMMANDS)
def test_every_documented_subcommand_and_flag_exists(path, command):
    words = [w for w in _words(command) if w != "-v"]
    subparsers = _subparsers()
    if PLACEHOLDER.match(words[0]):  # `modalfe -v COMMAND ...`
        return
    assert words[0] in subparsers, f"{path.name}: no command '{words[0]}' in `{command}`"
    options = {o for a in subparsers[words[0]]._actions for o in a.option_strings}
    flags = re.findall(r"(?<![\w-])--[a-z][a-z0-9-]*", command)
    unknown = [f for f in flags if f not in options]
    assert not unknown, f"{path.name}: `{command}`: {unknown} not options of `modalfe {words[0]}`"


def _doc_files(folder: Path) -> None:
    """The files the documents' commands read, written where they run: each `cat > FILE <<'END'` of the documents,
    user guide's scene-file example as bimorph.toml, and docs/studies.md's disc.toml (the .geo scene of
    tests/cli/test_cli_imported.py)."""
    from tests.cli.test_cli_imported import SCENE
    from tests.scene.test_imported_scene import GEO

    for path in DOCUMENTS:
        for match in HEREDOC.finditer(path.read_text()):
            (folder / match.group(1)).write_text(match.group(3))
    guide = (ROOT / "docs" / "guide.md").read_text()
    (folder / "bimorph.toml").write_text(guide.split("```toml\n", 1)[1].split("```", 1)[0])
    (folder / "disc.toml").write_text(SCENE)
    shutil.copy(GEO, folder / "plate.geo")


# `report` runs every built-in scene in worker processes, where the stand-in solve does not reach: real solves
CONCRETE = [pytest.param(*c.values, id=c.id, marks=[pytest.mark.slow] if _words(c.values[1])[0] == "report" else [])
            for c in COMMANDS if _concrete(c.values[1])]


@pytest.mark.parametrize(("path", "command"), CONCRETE)
def test_every_concrete_documented_command_is_accepted_up_to_its_solve(path, command, tmp_path, monkeypatch, capsys):
    argv = _words(command)
    try:
        args = build_parser().parse_args(argv)
    except SystemExit:
        pytest.fail(f"{path.name}: `{command}` does not parse: {capsys.readouterr().err.strip()}")
    scene = getattr(args, "scene", None)
    _doc_files(tmp_path)
    if isinstance(scene, str):
        assert scene in BUILTIN or (ROOT / scene).is_file() or (tmp_path / scene).is_file(), (
            f"{path.name}: `{command}`: no scene '{scene}'")
    for folder in ("studies", "examples"):  # the repository's scene files, as from its root
        (tmp_path / folder).symlink_to(ROOT / folder)
    for word in argv:  # the folders of the files it writes (docs/img/...), so that it may write them
        if "/" in word and not word.startswith("-"):
            (tmp_path / word).parent.mkdir(parents=True, exist_ok=True)
    monkeypatch.chdir(tmp_path)

    def stand_in(*_args, **_kw):
        raise SolverError(STAND_IN)

    monkeypatch.setattr("modalfe.solve.api.solve_at_fidelity", stand_in)
    status = main(argv)
    out, err = capsys.readouterr()
    # `report` prints a FAILED row per stand-in solve and exits 1
    assert status == 0 or (status == 1 and STAND_IN in out + err), f"{path.name}: `{command}` refused: {err.strip()}"


def test_the_readme_sets_up_in_two_commands_and_ci_runs_its_tests():
    """README's set-up is two commands, one installing and running `modalfe report`, one installing the test extras
    and running the tests; .ci/run installs the same extras and runs the same test command."""
    readme = (ROOT / "README.md").read_text()
    setup = readme.split("## Set-up (two commands)\n", 1)[1].split("\n## ", 1)[0]
    commands = [line.strip() for line in setup.splitlines() if line.startswith("    ")]
    assert commands == ['python -m pip install -e . && modalfe report',
                        'python -m pip install -e ".[test]" && python -m pytest -q']
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert 'python -m pip install -q -e ".[test]"' in ci and "python -m pytest -q" in ci
    assert len(readme.splitlines()) <= 200  # issue 37: a README a newcomer reads; the reference is docs/guide.md
