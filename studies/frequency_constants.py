"""The disc frequency constants Np and Nt of four PZT grades: the axisymmetric model and the 3-D solid against the
thin-disc theory of the same constants and against manufacturers' data sheets (issue 36).

A thin free disc (diameter 20 mm, thickness 1 mm: D / t = 20, electrodes on both faces, poled through the thickness)
of each grade of ``modalfe.scene.materials``: PZT-5A, PZT-4, PZT-5H (Berlincourt, Curran & Jaffe 1964, the library's
source) and Sonox-P4 (CeramTec's Sonox P4 data sheet, its missing s12E, s13E, s44E completed from the same sheet by
IEEE Std 176 identities). Both constants are short-circuit (series) resonances, as IEEE Std 176-1987:

- Np = fr D of the planar (radial) mode R1. Theory: the thin disc of IEEE Std 176-1987 (Meitzler et al. 1961, Onoe
  1956), eta J0(eta) = (1 - sigma) J1(eta), sigma = -s12^E / s11^E, fr = eta / (pi D) / sqrt(rho s11^E (1 - sigma^2))
  (``tests.oracles.discs.thin_disc``). Solved on the axisymmetric model (n = 0) and the 3-D solid.
- Nt = fr t of the thickness mode: the mode labelled ``thickness`` among those near the theory's (a disc of finite
  D / t has many radial overtones there; the labeller picks the one whose motion is the uniform thickness stretch).
  Theory: the 1-D thickness-extensional resonator of IEEE Std 176-1987, fa = sqrt(c33^D / rho) / 2t, fr from
  k_t^2 = (pi fr / 2 fa) tan(pi (fa - fr) / 2 fa) (``tests.oracles.discs.thickness_resonator``), which holds for a
  laterally infinite plate. Solved on the axisymmetric model only: the 3-D solid at 2 MHz needs elements of ~0.13 mm
  (6 per shear wavelength) across the whole 20 mm disc: ~160,000 quadratic hexahedra, ~4 million DOFs.

The data sheets (``SHEETS``, ``DATASHEET``) are CTS's, APC's and CeramTec's. For PZT-5A, PZT-4 and PZT-5H they describe
the makers' own formulations of the Navy types (II, I, VI), not Berlincourt's samples: those comparisons check the
order only, the comparison with the theory of the library's constants checks the model. Sonox-P4 is the one row whose
constants and frequency constants come from the same sheet.

Run:  python studies/frequency_constants.py [--no-solid]
Prints the table of docs/axisymmetric.md ("Frequency constants"); times are in-process wall seconds of each solve
(imports and the first mesh excluded: one process runs them all).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root: tests.oracles
from modalfe.scene.loading import scene_from_dict
from modalfe.solve.api import solve_modes
from tests.oracles.discs import thickness_resonator, thin_disc

DIAMETER = 20e-3  # m
THICKNESS = 1e-3  # m
GRADES = ("PZT-5A", "PZT-4", "PZT-5H", "Sonox-P4")
# the data sheets: maker, document, address, the frequency constants' definitions and stated tolerance
SHEETS = {
    "CTS": "CTS Corporation, 'PZT5A & 5H Materials Technical Data (Typical Values)' (3195STD, 3203STD), "
           "https://dtsheet.com/doc/1396950/3195std---cts-corp.: Nr (radial), Ntr (thickness, resonant), Nta "
           "(thickness, anti-resonant) in kHz cm; fr(radial) = Nr / d, ft(thickness) = Nt / t; typical values, no "
           "tolerance given",
    "APC": "APC International, 'Physical and Piezoelectric Properties of APC Materials' (Rev. 3, Feb. 2017), "
           "https://www.americanpiezo.com/apc-materials/physical-piezoelectric-properties.html: NP (planar), NT "
           "(thickness) in Hz m (resonance or anti-resonance not said; compared as fr); 'values pertain to test "
           "specimens', standard tolerance 'Frequency: +-5 %'",
    "CeramTec": "CeramTec, 'Piezoceramic Hard Materials - Material Data' (Sonox P4, Navy type I), stored copy "
                "https://de.scribd.com/document/628850476/Piezoceramic-Hard-Materials: Np, Nt in kHz mm (resonance "
                "or anti-resonance not said; compared as fr); no tolerance in the stored copy",
}
# grade -> [(sheet, the maker's type, Np, Nt, Nta or None, tolerance or None)]: Np, Nt, Nta [Hz m] (the sheets'
# kHz cm x 10, kHz mm x 1); Nta = fa t of the thickness mode where the sheet gives it
DATASHEET = {
    "PZT-5A": [("CTS", "3195STD", 2020.0, 2040.0, 2290.0, None), ("APC", "850, Navy II", 1980.0, 2040.0, None, 0.05)],
    "PZT-4": [("APC", "840, Navy I", 2130.0, 2005.0, None, 0.05),
              ("CeramTec", "Sonox P4, Navy I", 2210.0, 2000.0, None, None)],
    "PZT-5H": [("CTS", "3203STD", 1920.0, 1910.0, 2220.0, None), ("APC", "855, Navy VI", 1920.0, 2079.0, None, 0.05)],
    "Sonox-P4": [("CeramTec", "Sonox P4, same sheet", 2210.0, 2000.0, None, None)],
}
THICKNESS_MESH = 1.15  # the mesh resolves up to this times the theory's thickness fr (its window's top mode)


def disc_scene(grade: str, *, near: float, max_frequency: float = 0.0, harmonics: int | None = None):
    """The free thin disc of ``grade`` (DIAMETER x THICKNESS, poled through the thickness, electrodes on both
    faces) asking for modes near ``near`` [Hz]; its mesh resolving ``max_frequency`` [Hz] (0: the analysis's)."""
    mesh = {"max_frequency": max_frequency} | ({"harmonics": harmonics} if harmonics is not None else {})
    part = {"name": "disc", "shape": "cylinder", "material": grade, "centre": [0, 0, 0], "axis": "z",
            "radius": DIAMETER / 2 * 1e3, "height": THICKNESS * 1e3, "poling": 1}
    return scene_from_dict({"units": "mm", "parts": [part], "mesh": mesh,
                            "faces": {"electrode_a": ["disc.top"], "electrode_b": ["disc.bottom"]},
                            "electrodes": {"electrode_a": "drive", "electrode_b": "ground"},
                            "analysis": {"near": near, "count": 3}})


def timed(call):
    """(result, wall seconds) of ``call()``."""
    start = time.perf_counter()
    result = call()
    return result, time.perf_counter() - start


def radial(grade: str, fidelity: str):
    """(R1 mode, seconds) of the grade's disc at ``fidelity``, default tol."""
    fr, _ = thin_disc(grade, DIAMETER / 2)
    modes, seconds = timed(lambda: solve_modes(disc_scene(grade, near=fr), fidelity=fidelity, mode="R1"))
    return modes.labelled("R1"), seconds


def thickness(grade: str):
    """(thickness mode, seconds) of the grade's disc on the axisymmetric model (n = 0), default tol."""
    fr, _ = thickness_resonator(grade, THICKNESS)
    scene = disc_scene(grade, near=fr, max_frequency=THICKNESS_MESH * fr, harmonics=0)
    modes, seconds = timed(lambda: solve_modes(scene, fidelity="axisymmetric", near=fr, count=5))
    return modes.labelled("thickness"), seconds


def sheet_column(grade: str, computed: float, which: str) -> str:
    """The data sheets' ``which`` ("Np", "Nt" or "Nta") of ``grade`` with the maker's type, stated tolerance and the
    difference of ``computed`` [Hz m] from each."""
    cells = []
    for sheet, kind, *values, tol in DATASHEET.get(grade, ()):
        value = values[("Np", "Nt", "Nta").index(which)]
        stated = f" +-{tol:.0%}" if tol else ""
        if value is not None:
            cells.append(f"{value:.0f} ({sheet} {kind}{stated}: {computed / value - 1:+.1%})")
    return " / ".join(cells) or "-"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--no-solid", action="store_true", help="leave out the 3-D solid's R1")
    args = parser.parse_args()
    print("Np = fr D (planar R1), Nt = fr t (thickness), short circuit, Hz m; disc 20 x 1 mm; stated errors in "
          "brackets; differences relative to the theory of each grade's constants, and of the axisymmetric model "
          "from each data sheet")
    print("| grade | Np axi | Np solid | Np theory | Np data sheets (maker, type, tolerance: axi's difference) | "
          "axi - theory | solid - theory | Nt axi | Nt theory (1-D) | Nt data sheets | axi - theory | "
          "Nta theory (1-D, fa t) | Nta data sheets (theory's difference) | "
          "time axi R1 / solid R1 / axi thickness [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for grade in GRADES:
        np_theory = thin_disc(grade, DIAMETER / 2)[0] * DIAMETER
        nt_theory, nta_theory = (f * THICKNESS for f in thickness_resonator(grade, THICKNESS))
        r1, t_r1 = radial(grade, "axisymmetric")
        if args.no_solid:
            solid_text, dev_solid, t_solid = "-", "-", "-"
        else:
            r1_solid, seconds = radial(grade, "solid")
            np_solid = r1_solid.frequency * DIAMETER
            solid_text = f"{np_solid:.1f} ({r1_solid.error_estimate:.1e})"
            dev_solid, t_solid = f"{np_solid / np_theory - 1:+.3%}", f"{seconds:.1f}"
        th, t_th = thickness(grade)
        np_axi, nt_axi = r1.frequency * DIAMETER, th.frequency * THICKNESS
        print(f"| {grade} | {np_axi:.1f} ({r1.error_estimate:.1e}) | {solid_text} | {np_theory:.1f} | "
              f"{sheet_column(grade, np_axi, 'Np')} | {np_axi / np_theory - 1:+.3%} | {dev_solid} | "
              f"{nt_axi:.1f} ({th.error_estimate:.1e}) | {nt_theory:.1f} | {sheet_column(grade, nt_axi, 'Nt')} | "
              f"{nt_axi / nt_theory - 1:+.3%} | {nta_theory:.1f} | {sheet_column(grade, nta_theory, 'Nta')} | "
              f"{t_r1:.1f} / {t_solid} / {t_th:.1f} |")
    for sheet, text in SHEETS.items():
        print(f"{sheet}: {text}")


if __name__ == "__main__":
    main()
