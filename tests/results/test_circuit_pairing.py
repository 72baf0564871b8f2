"""A mode is the same mode in both circuits (issue 35): the open-circuit partner of a short-circuit mode is found by
shape (mass-weighted MAC on one discretization), never by label, and it carries the short-circuit mode's label."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from modalfe.errors import SolverError
from modalfe.results.coupling import antiresonance, partner_labels
from modalfe.results.modes import Mode, Modes


@dataclass(frozen=True)
class _Mesh:
    key: str


class _Model:
    """A stand-in model: ``n`` DOFs, a diagonal mass matrix, a mesh named ``key``."""

    def __init__(self, masses: np.ndarray, key: str = "mesh") -> None:
        self.M = sp.diags(masses).tocsr()
        self.ndofs = len(masses)
        self.mesh = _Mesh(key)


def _modes(model, shapes: np.ndarray, frequencies, labels, circuit: str) -> Modes:
    modes = tuple(Mode(i, float(f), name, shapes[:, i], model, circuit)
                  for i, (f, name) in enumerate(zip(frequencies, labels)))
    return Modes(modes, model, circuit, "solid", model.ndofs)


@settings(max_examples=200, deadline=None)
@given(n=st.integers(2, 8), seed=st.integers(0, 2**32 - 1), noise=st.floats(0.0, 0.2))
def test_open_modes_are_paired_by_shape_and_take_their_partners_labels(n, seed, noise):
    # open-circuit modes in another order (the circuit lifts coupled modes past others), of either sign, disturbed,
    # all labelled alike ("(0,0)", as a piezo cube's f1 and its open circuit's f4 were): each takes its partner's label
    rng = np.random.default_rng(seed)
    masses = rng.uniform(0.5, 2.0, 24)
    model = _Model(masses)
    q, _ = np.linalg.qr(rng.standard_normal((24, n)))
    shapes = q / np.sqrt(masses)[:, None]  # M-orthogonal shapes
    short = _modes(model, shapes, np.arange(1, n + 1) * 1e3, [f"({k},0)" for k in range(n)], "short")
    order = rng.permutation(n)
    moved = shapes[:, order] * rng.choice([-1.0, 1.0], n) + noise * rng.standard_normal((24, n)) / np.sqrt(24)
    opens = _modes(_Model(masses), moved, np.arange(1, n + 1) * 1.1e3, ["(0,0)"] * n, "open")
    labelled = partner_labels(short, opens)
    assert [m.label for m in labelled] == [short[int(k)].label for k in order]
    for i, m in enumerate(short):
        assert antiresonance(m, opens).index == int(np.flatnonzero(order == i)[0])


def test_open_modes_of_another_discretization_are_refused_not_paired_by_label():
    shapes = np.eye(4)[:, :2]
    short = _modes(_Model(np.ones(4), "fine"), shapes, [1e3, 2e3], ["(1,0)", "(0,1)"], "short")
    opens = _modes(_Model(np.ones(4), "coarse"), shapes, [1.1e3, 2.1e3], ["(1,0)", "(0,1)"], "open")
    with pytest.raises(SolverError, match="another discretization"):
        antiresonance(short[0], opens)
    assert partner_labels(short, opens) is opens


def test_a_piezo_cubes_open_circuit_modes_keep_their_short_circuit_labels():
    # a 5 mm PZT-5A cube poled along z, electrodes on its z faces: in open circuit the coupled modes move past others
    # and were labelled anew; solved on the short circuit's model, an open mode with a partner takes its label
    from modalfe.scene import scene_from_dict
    from modalfe.solve.api import open_circuit_modes, solve_modes

    scene = scene_from_dict({
        "units": "mm", "parts": [{"name": "cube", "material": "PZT-5A", "origin": [0, 0, 0], "size": [5, 5, 5],
                                  "poling": 1}],
        "faces": {"top": ["cube.zmax"], "bottom": ["cube.zmin"]}, "electrodes": {"top": "drive", "bottom": "ground"},
        "analysis": {"near": 200e3, "count": 8}})
    short = solve_modes(scene, near=200e3, count=8, error_estimate=False)
    opens = open_circuit_modes(short, near=200e3, count=8)
    paired = 0
    for m in short:
        try:
            partner = antiresonance(m, opens)
        except SolverError:  # its partner lies outside the open band
            continue
        assert partner.label == m.label and partner.frequency >= m.frequency * (1 - 1e-9)
        paired += 1
    assert paired >= 5
    assert len({m.label for m in opens}) == len(opens)
