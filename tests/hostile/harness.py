"""Run one hostile-input case and classify what happened.

Verdicts: ``clear error`` (one stderr line ``modalfe: error: FIELD: ...`` naming the expected field, exit
status != 0), ``handled`` (a valid or tolerable input answered correctly), ``traceback`` (an exception
escaped, or the CLI's catch-all reported an internal error: a bug either way), ``hang`` (over the case's
time limit), ``silent wrong`` (a bad input accepted, or a wrong answer), ``wrong blame`` (an error that
names another field, spans several lines, or refuses a valid input).
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import os
import signal
import subprocess
import sys
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

VERDICTS = ("clear error", "handled", "traceback", "hang", "silent wrong", "wrong blame")
BAD = ("traceback", "hang", "silent wrong")


@dataclass(frozen=True)
class Case:
    """One hostile input.

    area: what it attacks; expect: "error" (one line naming ``field``), "ok" (``check`` holds on the result)
    or "interrupt" (``modalfe: interrupted``, exit 130). Exactly one of ``argv`` (CLI, run in process;
    ``{tmp}`` and ``{file}`` are substituted), ``call`` (Python API: ``call(tmp)``) or ``shell`` (a subprocess
    driven by ``run_shell``). ``files``: name -> text or bytes written into the case's folder (the first one
    is ``{file}``); ``prepare(tmp)`` runs before; ``env`` is set while it runs; ``owner``: whose item a
    failure belongs to ("" = items 5, 6, 8: must pass).
    """

    id: str
    area: str
    expect: str
    field: str = ""
    argv: tuple[str, ...] | None = None
    call: Callable[[Path], Any] | None = None
    shell: Callable[[Path], tuple[int, str, str]] | None = None
    check: Callable[[Any], bool] | None = None
    files: dict[str, str | bytes] = dataclasses.field(default_factory=dict)
    prepare: Callable[[Path], None] | None = None
    env: dict[str, str] = dataclasses.field(default_factory=dict)
    owner: str = ""
    timeout: float = 60.0
    slow: bool = False

    @property
    def input(self) -> str:
        if self.argv is not None:
            return "modalfe " + " ".join(self.argv)
        return self.id


@dataclass(frozen=True)
class Observed:
    verdict: str
    detail: str
    seconds: float


class _Hang(BaseException):
    """Raised by the alarm: the case ran over its time limit."""


def _alarm(signum, frame):
    raise _Hang()


def _substitute(text: str, tmp: Path, first: str | None) -> str:
    return text.replace("{tmp}", str(tmp)).replace("{file}", str(tmp / first) if first else "")


def run_case(case: Case, tmp: Path) -> Observed:
    """Run ``case`` in folder ``tmp`` and classify it, with no resolved answer kept from another case (as the tests'
    conftest keeps none): each case answers the question it asks."""
    from modalfe.solve import resolved

    resolved.clear(disk=True)
    tmp.mkdir(parents=True, exist_ok=True)
    for name, content in case.files.items():
        path = tmp / name
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)
    first = next(iter(case.files), None)
    saved = {k: os.environ.get(k) for k in case.env}
    os.environ.update({k: _substitute(v, tmp, first) for k, v in case.env.items()})
    start = time.perf_counter()
    try:
        if case.prepare is not None:
            case.prepare(tmp)
        if case.shell is not None:
            status, out, err = case.shell(tmp)
            return _classify_cli(case, status, out, err, time.perf_counter() - start, tmp)
        previous = signal.signal(signal.SIGALRM, _alarm)
        signal.setitimer(signal.ITIMER_REAL, case.timeout)
        try:
            if case.argv is not None:
                argv = [_substitute(a, tmp, first) for a in case.argv]
                status, out, err = _run_cli(argv)
                signal.setitimer(signal.ITIMER_REAL, 0)
                return _classify_cli(case, status, out, err, time.perf_counter() - start, tmp)
            result = _run_call(case, tmp)
            signal.setitimer(signal.ITIMER_REAL, 0)
            return Observed(*result, time.perf_counter() - start)
        except _Hang:
            return Observed("hang", f"over {case.timeout:g} s", time.perf_counter() - start)
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _run_cli(argv: list[str]) -> tuple[int | str, str, str]:
    """``modalfe.cli.main.main(argv)`` with stdout and stderr captured; an escaping exception becomes
    status "exception" with its traceback on stderr."""
    from modalfe.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            status: int | str = main(argv)
        except SystemExit as exc:
            status = exc.code if isinstance(exc.code, int) else 1
        except _Hang:
            raise
        except BaseException:
            status = "exception"
            err.write(traceback.format_exc())
    return status, out.getvalue(), err.getvalue()


def _run_call(case: Case, tmp: Path) -> tuple[str, str]:
    from modalfe.errors import ModalfeError

    try:
        value = case.call(tmp)
    except _Hang:
        raise
    except ModalfeError as exc:
        message = str(exc)
        if case.expect != "error":
            return "wrong blame", f"refused: {message}"
        if "\n" in message:
            return "wrong blame", f"several lines: {message!r}"
        if not message.startswith(case.field):
            return "wrong blame", f"expected '{case.field}', got: {message}"
        return "clear error", message
    except KeyboardInterrupt:
        return "traceback", "KeyboardInterrupt escaped"
    except Exception as exc:
        return "traceback", f"{type(exc).__name__}: {exc}"
    if case.expect == "error":
        return "silent wrong", f"accepted, returned {str(value)[:80]!r}"
    if case.check is not None and not case.check(value):
        return "silent wrong", f"check failed on {str(value)[:120]!r}"
    return "handled", "as expected"


def _classify_cli(case: Case, status, out: str, err: str, seconds: float, tmp: Path | None = None) -> Observed:
    if tmp is not None:
        case = dataclasses.replace(case, field=_substitute(case.field, tmp, next(iter(case.files), None)))
    lines = [line for line in err.splitlines() if line.strip()]
    if status == "hang":
        return Observed("hang", f"killed after {case.timeout:g} s", seconds)
    if status == "exception" or "Traceback (most recent call last)" in err or "internal error" in err:
        tail = lines[-1] if lines else ""
        return Observed("traceback", tail[:200], seconds)
    if case.expect == "interrupt":
        # a progress bar drawn before the Ctrl-C may stay on stderr (a pipe cannot erase it); nothing else may
        ok = status == 130 and lines[-1:] == ["modalfe: interrupted"] and all(
            "%|" in line for line in lines[:-1])
        return Observed("handled" if ok else "wrong blame", f"status {status}, stderr {lines[-3:]}", seconds)
    if case.expect == "error":
        if status == 0:
            return Observed("silent wrong", f"accepted (exit 0): {out.strip()[:100]!r}", seconds)
        errors = [line for line in lines if line.startswith("modalfe: error: ")]
        if len(lines) != 1 or len(errors) != 1:
            return Observed("wrong blame", f"not one line: {lines[:3]}", seconds)
        message = errors[0][len("modalfe: error: "):]
        if not message.startswith(case.field):
            return Observed("wrong blame", f"expected '{case.field}', got: {message[:200]}", seconds)
        return Observed("clear error", message[:200], seconds)
    if status != 0:
        return Observed("wrong blame", f"refused (exit {status}): {lines[-1] if lines else ''}"[:200], seconds)
    if case.check is not None:
        try:
            good = case.check(out)
        except Exception as exc:  # a failed check of the output, not of modalfe
            good = False
            out = f"{type(exc).__name__}: {exc}"
        if not good:
            return Observed("silent wrong", f"check failed on stdout {out.strip()[:120]!r}", seconds)
    return Observed("handled", "as expected", seconds)


def modalfe_subprocess(args: list[str], *, interrupt_after: float | None = None, timeout: float = 60.0,
                       env: dict | None = None) -> tuple[int | str, str, str]:
    """Run ``python -m modalfe.cli.main ARGS``; with ``interrupt_after`` send SIGINT after that many seconds."""
    command = [sys.executable, "-m", "modalfe.cli.main", *args]
    # a test run started in the background of a non-interactive shell (``(bash .ci/run &)``) ignores SIGINT, and the
    # child inherits that (Python then installs no KeyboardInterrupt handler and the interrupt cases see status 0):
    # the default is restored in the child
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                               env={**os.environ, **(env or {})},
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        if interrupt_after is not None:
            try:
                process.wait(interrupt_after)
            except subprocess.TimeoutExpired:
                process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.kill()
        out, err = process.communicate()
        return "hang", out, err
    return process.returncode, out, err
