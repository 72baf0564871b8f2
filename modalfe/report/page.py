"""The design report as one HTML page: per scene, what it is made of (parts, materials with their sources, supports,
electrodes), its working modes against the seeds' targets with their stated errors, pictures of the modes, the
forced-response and admittance plots, how each row was resolved (auto's reasoning, the error estimate), the notes
and the assumptions with their sources; the command line and modalfe's version that made it.

The page is plain HTML with its stylesheet inline; its pictures are PNG files in the page's own folder, referenced
by relative paths, so the folder can be moved, zipped or served as it is. Pure formatting: the caller gives the
data (``modalfe.cli.page`` solves and renders).
"""

from __future__ import annotations

import datetime
import math
from dataclasses import dataclass, field
from html import escape
from pathlib import Path

STYLE = """
body { font-family: sans-serif; margin: 2em auto; max-width: 75em; color: #222; }
h1 { font-size: 1.6em; } h2 { border-bottom: 2px solid #ccc; margin-top: 2em; } h3 { margin-bottom: 0.3em; }
table { border-collapse: collapse; margin: 0.5em 0 1em; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; vertical-align: top; }
th { background: #f2f2f2; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
figure { margin: 0.5em 0 1.5em; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.85em; color: #555; } .meta { color: #555; font-size: 0.9em; }
ul.notes li { margin-bottom: 0.3em; font-size: 0.9em; }
"""


@dataclass(frozen=True)
class Picture:
    """A PNG in the page's folder: ``file`` (a name relative to it) and its caption."""

    file: str
    caption: str


@dataclass(frozen=True)
class SceneSection:
    """One scene of the page: ``info`` (``modalfe info --json``'s document), ``rows`` (its ``ReportRow``s),
    ``pictures`` of its working modes, ``plots`` (forced response, admittance) and ``notes`` on what is missing."""

    info: dict
    rows: list
    pictures: list[Picture] = field(default_factory=list)
    plots: list[Picture] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def _table(head: list[str], body: list[list[str]], numeric: set[int] = frozenset()) -> str:
    """An HTML table; cells are escaped here, column indices in ``numeric`` aligned right."""
    rows = ["<tr>" + "".join(f"<th>{escape(h)}</th>" for h in head) + "</tr>"]
    for cells in body:
        rows.append("<tr>" + "".join(f"<td class=\"num\">{escape(c)}</td>" if k in numeric else f"<td>{escape(c)}</td>"
                                     for k, c in enumerate(cells)) + "</tr>")
    return "<table>" + "".join(rows) + "</table>"


def _mm(values) -> str:
    return " x ".join(f"{1e3 * v:g}" for v in values)


def _error(error: float | None) -> str:
    if error is None:
        return "n/a"
    return "unresolved" if math.isinf(error) else f"{100 * error:.2g} %"


def _figures(pictures: list[Picture]) -> str:
    return "".join(f'<figure><img src="{escape(p.file)}" alt="{escape(p.caption)}">'
                   f"<figcaption>{escape(p.caption)}</figcaption></figure>" for p in pictures)


def scene_html(section: SceneSection) -> str:
    """The HTML of one scene's section."""
    info, rows = section.info, section.rows
    out = [f"<h2 id=\"{escape(info['scene'])}\">{escape(info['scene'])}</h2>",
           f"<p class=\"meta\">device '{escape(info['device'])}', {escape(info['kind'])} labels; "
           f"{escape(info['symmetry']['model'])} solved</p>", "<h3>Parts</h3>"]
    out.append(_table(["part", "material", "origin [mm]", "size [mm]", "poling"],
                      [[p["name"], p["material"], _mm(p["origin_m"]).replace(" x ", ", "), _mm(p["size_m"]),
                        p["poling"]] for p in info["parts"]]))
    out.append("<h3>Materials</h3>")
    out.append(_table(["material", "kind", "rho [kg/m^3]", "C11 [GPa]", "source"],
                      [[n, m["kind"], f"{m['rho_kg_m3']:g}", f"{m['C11_Pa'] / 1e9:.4g}", m["source"]]
                       for n, m in info["materials"].items()], numeric={2, 3}))
    out.append("<h3>Electrodes, supports and feet</h3>")
    roles = [[g, f["role"], ", ".join(f["faces"])] for g, f in info["face_groups"].items() if f["role"] != "none"]
    out.append(_table(["face group", "role", "faces"], roles) if roles else "<p>none</p>")
    if info["supports"].get("note"):
        out.append(f"<p>{escape(info['supports']['note'])}</p>")
    out.append("<h3>Working modes against the targets</h3>")
    body = []
    for r in rows:
        coupling = [f"{r.antiresonance_hz:.1f}", f"{r.k_eff:.4f}"] if r.k_eff is not None else ["", ""]
        body.append([r.mode, f"{r.frequency_hz:.1f}", _error(r.error_estimate), *coupling, r.fidelity, f"{r.dofs}",
                     f"{r.seconds:.1f}"])
        for t in r.targets:
            dev = f"{100 * t['deviation']:+.1f} %" if t["deviation"] is not None else "n/a"
            body.append([f"  vs {t['name']}", f"{t['value']:.6g} {t['unit']}", dev, "", "", t["kind"], t["source"], ""])
    out.append(_table(["mode / target", "f [Hz] / target", "stated error / deviation", "fa [Hz]", "k_eff", "model",
                       "DOFs / source", "s"], body, numeric={1, 2, 3, 4}))
    out.append(_figures(section.pictures))
    out.append(_figures(section.plots))
    how = [f"{r.mode}: {text}" for r in rows for text in (r.fidelity_note, r.estimate_method) if text]
    if how:
        out.append("<h3>How each row was resolved</h3><ul class=\"notes\">"
                   + "".join(f"<li>{escape(h)}</li>" for h in how) + "</ul>")
    notes = [f"{r.mode}: {n}" for r in rows for n in r.notes] + section.notes
    if notes:
        out.append("<h3>Notes</h3><ul class=\"notes\">" + "".join(f"<li>{escape(n)}</li>" for n in notes) + "</ul>")
    assumptions = list(dict.fromkeys(a for r in rows for a in r.assumptions))
    if assumptions:
        out.append("<h3>Assumptions and their sources</h3><ul class=\"notes\">"
                   + "".join(f"<li>{escape(a)}</li>" for a in assumptions) + "</ul>")
    return "\n".join(out)


def write_page(directory: str | Path, sections: list[SceneSection], *, command: str, version: str) -> Path:
    """Write ``directory``/index.html (the pictures already in ``directory``) and return its path."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    contents = "".join(f"<li><a href=\"#{escape(s.info['scene'])}\">{escape(s.info['scene'])}</a></li>"
                       for s in sections)
    body = "\n".join(scene_html(s) for s in sections)
    page = (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>modalfe design report</title>"
            f"<style>{STYLE}</style></head><body>\n<h1>modalfe design report</h1>\n"
            f"<p class=\"meta\">made by <code>{escape(command)}</code> with modalfe {escape(version)}, {stamp}. "
            f"Stated errors are relative errors of the frequencies (their estimate: \"How each row was resolved\").</p>"
            f"\n<ul>{contents}</ul>\n{body}\n</body></html>\n")
    path = directory / "index.html"
    path.write_text(page, encoding="utf-8")
    return path
