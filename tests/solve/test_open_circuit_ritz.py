"""The open-circuit partners from the short circuit (``modalfe.solve.open_circuit.bordered_ritz``): Rayleigh-Ritz on
the kept short-circuit modes and a few Krylov blocks of the kept factorization gives each mode the partner a fresh
Lanczos solve of the bordered pencil gives: a property over generated piezo devices (one and two floating
electrodes), and the fallback to Lanczos where the blocks do not settle."""

from __future__ import annotations

from unittest import mock

import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from modalfe.errors import SolverError
from modalfe.results.coupling import antiresonance, shape_likeness
from modalfe.scene import load_scene, scene_from_dict
from modalfe.solve import levels, open_circuit, resolved
from modalfe.solve.api import open_circuit_partner, solve_modes
from tests.oracles.cases import reference_mesh, two_patch_bar_scene

OWN_MESH = {"fidelity": "solid", "error_estimate": False}
# the Ritz values settle to 1e-11 of themselves (``CONVERGED``); the fresh Lanczos solve's are good to ARPACK's
# tolerance, far better than its 1e-8 on the eigenvalues of a well separated pencil (measured: 1e-14 on the Cu-Be
# plate's open circuit): 1e-9 is the agreement the commands owe each other
SAME = 1e-9
SAME_SHAPE = 1 - 1e-6  # mass-weighted MAC of one mode computed twice (1 - MAC ~ the squared vector error)


def _bar(length: float, thickness: float, material: str, base: float, split: bool) -> dict:
    """A free piezo bar (mm) poled +z on an aluminium strip ``base`` mm thick (none: 0), driven on its top face, or
    (``split``) two such bars end to end, each driven on its own top face: two floating potentials in open circuit."""
    pieces = [("a", 0.0, length / 2), ("b", length / 2, length / 2)] if split else [("a", 0.0, length)]
    parts = [{"name": f"bar_{k}", "material": material, "origin": [x, 0, base], "size": [size, 2.0, thickness],
              "poling": 1} for k, x, size in pieces]
    if base > 0:
        parts.append({"name": "strip", "material": "Al-5052", "origin": [0, 0, 0], "size": [length, 2.0, base]})
    faces = {f"top_{k}": [f"bar_{k}.zmax"] for k, _, _ in pieces} | {"bottom": [f"bar_{k}.zmin" for k, _, _ in pieces]}
    electrodes = {f"top_{k}": "drive" for k, _, _ in pieces} | {"bottom": "ground"}
    return {"name": "generated", "units": "mm", "parts": parts, "faces": faces, "electrodes": electrodes,
            "analysis": {"near": 3.2e3 / (2 * length * 1e-3), "count": 6}, "mesh": reference_mesh(length * 1e-3 / 5, 1)}


RITZ_CALLS: list[int] = []  # Rayleigh-Ritz runs of each ``_partners_both_ways``


def _partners_both_ways(scene, near: float, count: int) -> list[tuple]:
    """[(short mode, its open partner sought from the kept short solve (by Rayleigh-Ritz, which must answer: else
    Lanczos did), its partner among a fresh Lanczos solve of the open circuit)] for every short mode whose partner
    both find."""
    levels._SHORT_SOLVES.clear()
    resolved.clear(disk=True)
    short = solve_modes(scene, near=near, count=count, **OWN_MESH)
    answers = []

    def spied(*args):
        answers.append(open_circuit.bordered_ritz(*args))
        return answers[-1]

    found = {}
    with mock.patch.object(levels, "bordered_ritz", spied):
        for mode in short:
            try:
                found[mode.index] = open_circuit_partner(mode, near=near, among=short)
            except SolverError:  # not among the open modes the partner search may solve (as many as the short)
                continue
    # where the short solve's factorization was kept at this shift, Rayleigh-Ritz answered (the short solve of a
    # generated bar may have moved its shift off an eigenvalue: then the partner search factorizes, no Ritz)
    assert all(a is not None for a in answers) or open_circuit.MAX_BLOCKS == 1
    RITZ_CALLS.append(len(answers))
    levels._SHORT_SOLVES.clear()
    resolved.clear(disk=True)
    fresh = solve_modes(scene, near=near, count=2 * count + 4, circuit="open", **OWN_MESH)
    assert fresh.timings["solver"] != "reused"
    pairs = [(mode, found[mode.index], antiresonance(mode, fresh)) for mode in short if mode.index in found]
    assert pairs  # at least the mode nearest the shift has its partner nearby
    return pairs


def _check_same_partners(pairs: list[tuple]) -> None:
    for mode, from_short, fresh in pairs:
        assert from_short.frequency == pytest.approx(fresh.frequency, rel=SAME, abs=0), mode.label
        likeness = shape_likeness(mode.model, fresh.shape[:, None], from_short.shape[:, None])[0, 0]
        assert likeness > SAME_SHAPE, mode.label


BARS = {"length": st.floats(4.0, 10.0), "thickness": st.floats(0.5, 1.5),
        "material": st.sampled_from(["PZT-5A", "PZT-4"]), "base": st.sampled_from([0.0, 0.5, 1.0]),
        "split": st.booleans(), "count": st.integers(2, 6)}
GENERATED = {"deadline": None, "phases": (Phase.explicit, Phase.generate),
             "suppress_health_check": [HealthCheck.too_slow]}


def _check_generated_bar(length, thickness, material, base, split, count) -> None:
    scene = scene_from_dict(_bar(length, thickness, material, base, split))
    _check_same_partners(_partners_both_ways(scene, scene.analysis.near, count))


test_the_partners_from_the_short_modes_are_the_fresh_open_solves = \
    settings(max_examples=4, **GENERATED)(given(**BARS)(_check_generated_bar))
# 20 generated devices, ~1 s each
test_the_partners_from_the_short_modes_are_the_fresh_open_solves_many = \
    pytest.mark.slow(settings(max_examples=20, **GENERATED)(given(**BARS)(_check_generated_bar)))


def test_the_ciliary_beams_partners_come_from_its_short_modes():
    _check_same_partners(_partners_both_ways(load_scene("ciliary_beam"), 21.7e3, 6))
    assert RITZ_CALLS[-1] > 0


def test_two_floating_electrodes_take_the_same_path():
    scene = two_patch_bar_scene()
    _check_same_partners(_partners_both_ways(scene, 47e3, 6))
    assert RITZ_CALLS[-1] > 0


def test_blocks_that_do_not_settle_leave_the_answer_to_lanczos(monkeypatch, caplog):
    scene = scene_from_dict(_bar(6.0, 1.0, "PZT-5A", 0.5, False))
    monkeypatch.setattr(open_circuit, "MAX_BLOCKS", 1)  # one block never settles: no change to compare yet
    with caplog.at_level("INFO", logger="modalfe.solve.open_circuit"):
        pairs = _partners_both_ways(scene, scene.analysis.near, 4)
    assert "Lanczos instead" in caplog.text
    _check_same_partners(pairs)
