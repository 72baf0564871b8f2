"""Stated against actual error of the numbers derived from a mode (issue 34, item 2): ``python studies/derived_errors.py
[bimorph ciliary_beam ...] [--tol 0.005]``.

For each device, ``modalfe forced``'s figures (reduced model, BVD, fa, k_eff, amplitudes per volt) at ``--tol``, each
with the error stated from the frequency's own estimate levels (``modalfe.solve.api.derived_errors``), against the
same figures on a reference of our own: the scene's own grid at element order 4 with ``REFERENCE`` x its elements per
wavelength and thickness layers (solved once, no estimate), its change from the grid a step coarser (``COARSER``) given
as its uncertainty. A number is covered when stated >= |ours / reference - 1| - that uncertainty. Prints one row per
number and the count of rows not covered.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from modalfe.response.figures import forced_figures
from modalfe.scene import load_scene


def bimorph_scene():
    """The README's bimorph (tests/hostile/cases.py): a clamped steel strip with a PZT-5A patch, bending-z 1."""
    import tempfile

    from tests.hostile.cases import BIMORPH

    path = Path(tempfile.mkdtemp()) / "bimorph.toml"
    path.write_text(BIMORPH)
    return load_scene(str(path))


def scene_named(name: str):
    return bimorph_scene() if name == "bimorph" else load_scene(name)


OUTPUTS = {"bimorph": ("tip",)}  # devices whose scene names no drive.outputs


REFERENCE = (3.0, 3)  # (elements per wavelength x, thickness layers) of the reference at order 4
COARSER = (2.0, 2)  # the step before it: their difference is the reference's uncertainty


def refined(scene, wavelength_factor: float, layers: int):
    """``scene`` at element order 4 (Lagrange) with ``wavelength_factor`` x its elements per wavelength and ``layers``
    element layers through the thinnest part."""
    mesh = dataclasses.replace(scene.mesh, order=4, family="lagrange", min_layers=layers,
                               elements_per_wavelength=wavelength_factor * scene.mesh.elements_per_wavelength)
    return dataclasses.replace(scene, mesh=mesh)


def coverage(scene, tol: float) -> list[tuple[str, float, float, float, float, float, bool]]:
    """Rows (number, ours, reference, actual, stated, reference's stated, covered) for ``scene``'s working mode."""
    outputs = OUTPUTS.get(scene.name)
    ours = forced_figures(scene, tol=tol, outputs=outputs)
    numbers_ours = _numbers(ours)
    numbers_ref, numbers_coarser = (
        _numbers(forced_figures(refined(scene, *grid), outputs=outputs, fidelity="solid", error_estimate=False))
        for grid in (REFERENCE, COARSER))
    rows = []
    for name, value in numbers_ours.items():
        if name not in numbers_ref or not math.isfinite(ours.error(name)):
            continue
        actual = abs(value / numbers_ref[name] - 1)
        uncertainty = abs(numbers_coarser[name] / numbers_ref[name] - 1)
        rows.append((name, value, numbers_ref[name], actual, ours.error(name), uncertainty,
                     ours.error(name) >= actual - uncertainty))
    return rows


def _numbers(fig) -> dict[str, float]:
    from modalfe.response.figures import device_numbers

    rom = fig.rom
    composed = {"stiffness": rom.stiffness, "damping": rom.damping}
    if rom.is_voltage_driven:
        composed.update({f"bvd:{k}": rom.bvd[k] for k in ("R1", "L1", "C1")})
    return {**device_numbers(rom, fig.antiresonance, fig.stress), **composed}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("devices", nargs="*", default=["bimorph", "ciliary_beam"])
    parser.add_argument("--tol", type=float, default=0.005)
    args = parser.parse_args()
    missed = 0
    for name in args.devices:
        rows = coverage(scene_named(name), args.tol)
        print(f"{name}: tol {args.tol:g} against order 4 at x{REFERENCE[0]:g} elements per wavelength, "
              f"{REFERENCE[1]} layers (uncertainty: its change from x{COARSER[0]:g}, {COARSER[1]} layers)")
        print(f"  {'number':<22} {'ours':>12} {'reference':>12} {'actual':>9} {'stated':>9} {'ref unc':>9}")
        for number, value, ref, actual, stated, uncertainty, covered in rows:
            print(f"  {number:<22} {value:12.6g} {ref:12.6g} {actual:9.3%} {stated:9.3%} {uncertainty:9.3%}"
                  f"{'' if covered else '  NOT COVERED'}")
            missed += not covered
    print(f"rows not covered: {missed}")


if __name__ == "__main__":
    main()
