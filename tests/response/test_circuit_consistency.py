"""Circuit consistency (issue 35, item 4): a mode's fa and k_eff are one answer, whichever asks (``table``, ``forced``,
``admittance`` and the Python API's ``sweep``), its open-circuit partner found by shape (``open_circuit``), fa >= fr,
and the mode keeps its label in both circuits. A property over generated piezo devices, and the free PZT-5A disc of
the issue as a regression."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, Phase, example, given, settings
from hypothesis import strategies as st

from modalfe.design.sweep import coupling_extra, sweep
from modalfe.errors import SolverError
from modalfe.response.admittance import admittance
from modalfe.response.figures import forced_figures
from modalfe.response.mode_table import mode_table
from modalfe.results.coupling import antiresonance
from modalfe.scene import load_scene, scene_from_dict
from modalfe.scene.writing import scene_to_toml
from modalfe.solve.api import open_circuit_modes, solve_modes
from tests.oracles.cases import reference_mesh

# one answer to 1e-9: every command solves the same model (the scene's own mesh) and finds the same open-circuit mode
# by shape; what may differ is the shift of the eigen solve (the question's) and so the Lanczos rounding, ~1e-12
SAME = 1e-9
OWN_MESH = {"error_estimate": False}  # the scene's own mesh in every command: one discretization, cheap
NO_SHRINK = (Phase.explicit, Phase.generate)  # a failing device is printed as generated: a shrink step costs 5-20 s
CHEAP_ENOUGH = [HealthCheck.too_slow, HealthCheck.function_scoped_fixture]  # tmp_path: a file per example


def _device(length: float, width: float, thickness: float, material: str, poling: int, layout: str,
            base: float) -> dict:
    """A free piezo bar (mm) poled along +-z, alone or bonded on an aluminium strip ``base`` mm thick (a unimorph),
    with electrodes on its z faces, the drive on top (``layout`` "top-driven") or on the bottom ("bottom-driven");
    elements of a fifth of the length (coarse: a few hundred unknowns)."""
    parts = [{"name": "bar", "material": material, "origin": [0, 0, base], "size": [length, width, thickness],
              "poling": poling}]
    if base > 0:
        parts.append({"name": "strip", "material": "Al-5052", "origin": [0, 0, 0], "size": [length, width, base]})
    drive, ground = ("top", "bottom") if layout == "top-driven" else ("bottom", "top")
    return {"name": "generated", "units": "mm", "parts": parts, "faces": {"top": ["bar.zmax"], "bottom": ["bar.zmin"]},
            "electrodes": {drive: "drive", ground: "ground"},
            # the first length-extensional mode, the most coupled (k31) of a bar: c = sqrt(E / rho) ~ 3 km/s for PZT
            "analysis": {"near": 3.2e3 / (2 * length * 1e-3), "count": 6},
            "mesh": reference_mesh(length * 1e-3 / 5, 1)}


def _check_one_answer(scene_file: Path, tmp_path: Path) -> dict:
    """fa and k_eff of the most coupled of the scene's modes (its analysis' near and count) from table, forced,
    admittance and the API (``sweep`` with ``coupling_extra``) are one answer; returns its label, fr, fa, k_eff."""
    scene = load_scene(scene_file)
    drive = next(name for name, role in scene.electrodes.items() if role == "drive")
    short = solve_modes(scene, near=scene.analysis.near, count=scene.analysis.count, fidelity="solid", **OWN_MESH)
    table = mode_table(scene, near=scene.analysis.near, count=scene.analysis.count, fidelity="solid", **OWN_MESH)
    rows = [r for r in table.rows if r["k_eff"] is not None and r["frequency_Hz"] > 0]
    assert rows, "no coupled mode near the length-extensional one"  # a k31 bar's, driven through its faces
    row = max(rows, key=lambda r: r["k_eff"])
    label, fr, fa = row["label"], row["frequency_Hz"], row["fa_Hz"]
    # the open circuit only stiffens (floating potentials add stiffness, no mass): fa >= fr for every mode
    assert all(r["fa_Hz"] >= r["frequency_Hz"] * (1 - SAME) for r in table.rows if r["fa_Hz"] is not None)

    # labels are unique within one solve (a "#2" follows the modes solved): forced and the sweep ask the table's
    # question (the scene's near and count), so the label names the same mode; the admittance's band is matched by fr
    near = scene.analysis.near
    forced = forced_figures(scene, selector=label, near=near, outputs=(drive,), fidelity="solid", **OWN_MESH)
    assert forced.mode.label == label and forced.mode.frequency == pytest.approx(fr, rel=SAME)
    forced_json = forced.to_json()
    assert forced_json["antiresonance_hz"] == pytest.approx(fa, rel=SAME)
    assert forced_json["k_eff"] == pytest.approx(row["k_eff"], rel=SAME)

    result = admittance(scene, (0.97 * fr, 1.03 * fr), 8, damping="Q=100", fidelity="solid", **OWN_MESH)
    own = [c for c in json.loads(json.dumps(result.to_json()))["open_circuit"]
           if c["fr_hz"] == pytest.approx(fr, rel=SAME)]
    if row["k_eff"] ** 2 > 2e-3:  # a BVD circuit (k_eff^2 above BVD_MIN_COUPLING = 1e-3), so a listed resonance
        assert len(own) == 1
    for c in own:
        assert c["fa_hz"] == pytest.approx(fa, rel=SAME) and c["k_eff"] == pytest.approx(row["k_eff"], rel=SAME)

    rows_api = sweep(str(scene_file), {}, out=tmp_path / "sweep.csv", selector=label, near=near, count=6,
                     scheduler="inline", extra=coupling_extra, progress=False,
                     resolution={"fidelity": "solid", **OWN_MESH})
    assert rows_api[0]["label"] == label and rows_api[0]["frequency_hz"] == pytest.approx(fr, rel=SAME)
    assert rows_api[0]["extra"]["fa_hz"] == pytest.approx(fa, rel=SAME)
    assert rows_api[0]["extra"]["k_eff"] == pytest.approx(row["k_eff"], rel=SAME)

    # the same mode in both circuits: every open mode paired by shape with a short-circuit mode carries its label,
    # in the partners sought from the short modes and in the open circuit's own answer to the same question
    question = {"near": scene.analysis.near, "count": scene.analysis.count}
    for opens in (open_circuit_modes(short, near=question["near"], count=len(short) + 2),
                  solve_modes(scene, **question, circuit="open", fidelity="solid", **OWN_MESH)):
        for m in short:
            try:
                partner = antiresonance(m, opens)
            except SolverError:  # its partner lies outside the open modes solved
                continue
            assert partner.label == m.label and partner.frequency >= m.frequency * (1 - SAME)
    return {"label": label, "fr": fr, "fa": fa, "k_eff": row["k_eff"]}


def _written(data: dict, folder: Path) -> Path:
    """The generated scene as a scene file (the sweep reads its scene from one)."""
    path = folder / "generated.toml"
    path.write_text(scene_to_toml(scene_from_dict(data)))
    return path


DEVICES = {
    "length": st.floats(4.0, 10.0), "width": st.floats(1.0, 3.0), "thickness": st.floats(0.5, 1.5),
    "material": st.sampled_from(["PZT-5A", "PZT-4", "PZT-5H"]), "poling": st.sampled_from([1, -1]),
    "layout": st.sampled_from(["top-driven", "bottom-driven"]), "base": st.sampled_from([0.0, 0.5, 1.0]),
}


@settings(max_examples=4, deadline=None, phases=NO_SHRINK, suppress_health_check=CHEAP_ENOUGH)
@given(**DEVICES)
# found in CI: a band centred on the resonance, whose second residual solve stalled in GMRES on the kept factorization
# and then factorized on the resonance itself ("singular"; ``modal_admittance`` moves the shift for both solves now)
@example(length=4.000000000000001, width=2.97536016861023, thickness=0.5, material="PZT-5A", poling=1,
         layout="bottom-driven", base=0.0)
def test_fa_and_k_eff_are_one_answer_on_generated_devices(tmp_path, length, width, thickness, material, poling,
                                                          layout, base):
    _check_one_answer(_written(_device(length, width, thickness, material, poling, layout, base), tmp_path), tmp_path)


@pytest.mark.slow
@settings(max_examples=20, deadline=None, phases=NO_SHRINK, suppress_health_check=CHEAP_ENOUGH)
@given(**DEVICES)
def test_fa_and_k_eff_are_one_answer_on_generated_devices_many(tmp_path, length, width, thickness, material, poling,
                                                               layout, base):
    _check_one_answer(_written(_device(length, width, thickness, material, poling, layout, base), tmp_path), tmp_path)


@pytest.mark.slow  # 35 s of CPU: the 13k-DOF disc solved by four commands
def test_a_free_pzt5a_discs_radial_mode_has_one_fa_in_every_command(tmp_path):
    # issue 35: on the free 20 x 1 mm PZT-5A disc `table` once gave R1 fa = 102.8 kHz (another mode's) and k_eff
    # 0.257, `forced` 117.3 kHz and 0.533. R1's partner lies past the neighbouring modes (k_eff ~ 0.53 lifts it by
    # ~ 18 %): every command now finds the one open mode of its shape. The solid's R1 at its resolved mesh:
    # fr 99,365 Hz, fa 117,317 Hz (tests/oracles/discs.SOLID_FA); on the scene's own mesh within 1 % of those
    from tests.oracles.discs import PZT5A_DISC, SOLID_FA

    answer = _check_one_answer(Path(PZT5A_DISC), tmp_path)
    assert answer["label"] == "R1"
    assert answer["fa"] == pytest.approx(SOLID_FA, rel=1e-2)  # own mesh vs resolved: the R1 fr differs by < 0.1 %
    assert 0.45 < answer["k_eff"] < 0.6  # IEEE Std 176-1987 thin-disc k_p = 0.60 for PZT-5A; the 3-D disc 0.532
