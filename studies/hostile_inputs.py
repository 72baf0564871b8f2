"""The hostile-input suite of issue 16: every case of tests/hostile/cases.py run and classified.

    python studies/hostile_inputs.py [--slow] [--only SUBSTRING] [--markdown docs/hostile_inputs.md]

prints one row per case (area, input, expected, verdict, owner, detail) and the totals by verdict;
``--markdown FILE`` writes the same table as Markdown between the markers of FILE.
"""

from __future__ import annotations

import argparse
import collections
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.hostile.cases import CASES
from tests.hostile.harness import BAD, VERDICTS, run_case

BEGIN, END = "<!-- hostile-table: begin -->", "<!-- hostile-table: end -->"


def run(only: str | None = None, slow: bool = False) -> list[tuple]:
    rows = []
    with tempfile.TemporaryDirectory(prefix="modalfe-hostile-") as root:
        os.environ.setdefault("MODALFE_CACHE", str(Path(root) / "cache"))
        for i, case in enumerate(CASES):
            if only and only not in case.id:
                continue
            if case.slow and not slow:
                continue
            observed = run_case(case, Path(root) / f"{i:03d}-{case.id}")
            rows.append((case, observed))
            print(f"{case.area:<12} {case.id:<36} {case.expect:<9} {observed.verdict:<13} "
                  f"{case.owner or '-':<12} {observed.seconds:6.2f}s  {observed.detail[:110]}", flush=True)
    return rows


def totals(rows) -> collections.Counter:
    return collections.Counter(observed.verdict for _, observed in rows)


def markdown(rows) -> str:
    count = totals(rows)
    lines = [f"{len(rows)} cases: " + ", ".join(f"{count[v]} {v}" for v in VERDICTS), "",
             "| # | area | case | input | expected | verdict | owner | message or detail |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for i, (case, observed) in enumerate(rows, 1):
        expected = f"error naming `{case.field}`" if case.expect == "error" else case.expect
        text = observed.detail.replace("|", "\\|").replace("\n", " ")[:160]
        shown = case.input.replace("|", "\\|")
        shown = shown if len(shown) <= 90 else shown[:87] + "..."
        lines.append(f"| {i} | {case.area} | {case.id} | `{shown}` | {expected} | {observed.verdict} | "
                     f"{case.owner or ''} | {text} |")
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--slow", action="store_true", help="also the slow cases (subprocess report interrupt...)")
    parser.add_argument("--only", help="cases whose id contains this")
    parser.add_argument("--markdown", type=Path, help="write the table into this file between its markers")
    args = parser.parse_args()
    start = time.perf_counter()
    rows = run(args.only, args.slow)
    count = totals(rows)
    print(f"\n{len(rows)} cases in {time.perf_counter() - start:.0f} s: "
          + ", ".join(f"{count[v]} {v}" for v in VERDICTS))
    mine_bad = [c.id for c, o in rows if o.verdict in BAD and not c.owner]
    others_bad = [c.id for c, o in rows if o.verdict in BAD and c.owner]
    print(f"bad verdicts (traceback, hang, silent wrong): {len(mine_bad) + len(others_bad)}"
          f" ({len(others_bad)} owned by other items: {', '.join(others_bad) or 'none'})")
    if args.markdown:
        text = args.markdown.read_text()
        head, _, rest = text.partition(BEGIN)
        _, _, tail = rest.partition(END)
        args.markdown.write_text(f"{head}{BEGIN}\n{markdown(rows)}\n{END}{tail}")
    return 1 if mine_bad else 0


if __name__ == "__main__":
    sys.exit(main())
