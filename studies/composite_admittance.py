"""A composite transducer's admittance against its published figures (issue 36): the 20 mm piezo buzzer disc
FT-20T-6.5A (a PZT disc bonded on a brass disc, examples/buzzer_ft20t.toml) on the axisymmetric model.

Published (the manufacturer's sheet "PIEZO ELEMENT SPECIFICATIONS, MODEL: FT-20T-6.5A", shipped as the datasheet of
the DFRobot piezo disk vibration sensor, github.com/Arduinolibrary/DFRobot_Piezo_Disk_Vibration_Sensor): resonant
frequency Fr 6.5 +- 0.7 kHz, capacitance Cm 15000 pF +- 30 %, resonant impedance R 300 ohm max; brass plate 20.0 x
0.20 mm, ceramic diameter 15.0 mm, total height 0.42 mm. The sheet names no ceramic grade: PZT-5A (Berlincourt 1964)
is the scene's stated assumption, and the row of PZT-5H, the other soft grade of the library, shows what that
assumption is worth (the spread between grades, not a fit; the test asserts the scene's row only).

modalfe's figures: fr, the |Y| maximum of the first axisymmetric bending mode (0,1), and the FE open circuit's fa
and k_eff of the same mode (``Admittance.open_circuit``); the capacitance Im Y / omega at 1 kHz, far below fr (the
sheet states no frequency for Cm: buzzer sheets measure it at 1 kHz or 120 Hz, e.g. CUI CEB-27D44, CEB-35FD29), and
|Z| there; |Z| at fr, the resonant impedance, from each material's losses (PZT-5A Qm 75, tan delta 0.02; brass: the
default Q 150, an assumption: docs/assumptions.md).

    python studies/composite_admittance.py

Seconds are wall seconds of each admittance (the model's solve included: the study turns modalfe's disk cache off,
``MODALFE_CACHE=off``, unless it is set).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from modalfe.response.admittance import admittance
from modalfe.scene.loading import load_scene

SCENE = Path(__file__).resolve().parents[1] / "examples" / "buzzer_ft20t.toml"
BAND = (1000.0, 9000.0)  # Hz: 1 kHz (the capacitance) to above the (0,1) resonance and its fa
WORKING = "(0,1)"  # the first axisymmetric bending mode (one nodal circle): the buzzer's resonance

# the sheet's values and tolerances
FR, FR_TOL = 6.5e3, 0.7e3  # Hz
CM, CM_TOL = 15000e-12, 0.30  # F, relative
R_MAX = 300.0  # ohm


@dataclass(frozen=True)
class Figures:
    """modalfe's figures of the buzzer with one ceramic grade: fr, fa [Hz], k_eff; capacitance [F] and |Z| [ohm] at
    1 kHz; |Z| at fr [ohm]; DOFs; seconds of the admittance (wall)."""

    grade: str
    fr: float
    fa: float
    k_eff: float
    capacitance: float
    z_1khz: float
    z_fr: float
    dofs: int
    seconds: float


def buzzer(grade: str = "PZT-5A"):
    """The scene of examples/buzzer_ft20t.toml with its ceramic of ``grade`` (a library name)."""
    scene = load_scene(SCENE)
    return scene.with_overrides(parts=[{**p, "material": grade} if p["name"] == "ceramic" else p
                                       for p in scene.params["parts"]])


def figures(grade: str = "PZT-5A") -> Figures:
    """modalfe's admittance of the buzzer (axisymmetric model, each material's losses) read as the sheet's figures."""
    start = time.perf_counter()
    result = admittance(buzzer(grade), BAND, 9, damping="material", fidelity="axisymmetric")
    seconds = time.perf_counter() - start
    row = next(r for r in result.open_circuit if r["label"] == WORKING)
    peaks = np.asarray(result.extrema()["max_abs_Y_hz"])
    fr = float(peaks[np.argmin(abs(peaks - row["fr_hz"]))])  # the |Y| maximum of the working mode
    y_1khz, y_fr = result.model_Y(np.array([BAND[0], fr]))
    return Figures(grade, fr, row["fa_hz"], row["k_eff"], y_1khz.imag / (2 * math.pi * BAND[0]), 1 / abs(y_1khz),
                   1 / abs(y_fr), result.dofs, seconds)


def table(rows: list[Figures]) -> str:
    """The published figures beside modalfe's, one column per grade, with relative differences."""
    def rel(x: float, ref: float) -> str:
        return f"{(x - ref) / ref:+.1%}"

    head = f"{'':28s}{'published':>22s}" + "".join(f"{'modalfe ' + r.grade:>18s}{'diff':>8s}" for r in rows)
    lines = [head]
    z_pub = 1 / (2 * math.pi * BAND[0] * CM)
    cells = [("fr [Hz]", f"{FR:.0f} +- {FR_TOL:.0f}", lambda r: (f"{r.fr:.0f}", rel(r.fr, FR))),
             ("C at 1 kHz [nF]", f"{CM * 1e9:.1f} +- {CM_TOL:.0%}",
              lambda r: (f"{r.capacitance * 1e9:.2f}", rel(r.capacitance, CM))),
             ("|Z| at 1 kHz [ohm]", f"{z_pub:.0f} (1/wCm)", lambda r: (f"{r.z_1khz:.0f}", rel(r.z_1khz, z_pub))),
             ("|Z| at fr [ohm]", f"<= {R_MAX:.0f}", lambda r: (f"{r.z_fr:.0f}", "ok" if r.z_fr <= R_MAX else "over")),
             ("fa [Hz] (FE open circuit)", "-", lambda r: (f"{r.fa:.0f}", "")),
             ("k_eff", "-", lambda r: (f"{r.k_eff:.3f}", "")),
             ("DOFs, seconds", "-", lambda r: (f"{r.dofs}, {r.seconds:.1f} s", ""))]
    for name, published, cell in cells:
        lines.append(f"{name:28s}{published:>22s}" + "".join(f"{a:>18s}{b:>8s}" for a, b in map(cell, rows)))
    return "\n".join(lines)


def main() -> None:
    os.environ.setdefault("MODALFE_CACHE", "off")
    print(f"FT-20T-6.5A buzzer disc ({SCENE.name}), axisymmetric model, material losses")
    print(table([figures("PZT-5A"), figures("PZT-5H")]))
    print("PZT-5A: the scene's grade (assumption); PZT-5H: the spread between grades, not a fit.")


if __name__ == "__main__":
    main()
