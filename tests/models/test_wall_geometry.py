"""The bound on what a swept mesh's round walls cost a frequency (``modalfe.models.wall_geometry``): the walls'
deviation measured on the mesh is the quadratic arc's, and moving the walls changes each frequency by less than the
bounds of the two geometries together (each bounds its distance from the true wall, so their sum bounds the
distance between them: a check that fails if the bound is short)."""

from __future__ import annotations

import numpy as np
import pytest

import modalfe.caches as caches
from modalfe.models import swept
from modalfe.models.wall_geometry import wall_deviations, wall_errors
from modalfe.scene.loading import scene_from_dict
from modalfe.solve.api import solve_modes

FOOT = ((8e-3, 7e-3), 2e-3)  # the round foot's centre (x, y) and radius [m]
INWARD = 0.03  # the perturbed geometry: the arcs' middle nodes moved this fraction of the radius toward the axis


def _scene():
    """A free 30 x 20 x 2 mm Cu-Be plate, a PZT-4 layer on it whose edge crosses the round foot under it (a block
    with a crossing), quartic elements on one layer: six modes near 30 kHz."""
    (x, y), r = FOOT
    return scene_from_dict({
        "units": "mm",
        "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [30, 20, 2]},
                  {"name": "ceramic", "region": "piezo", "material": "PZT-4", "origin": [2, 7.6, 2],
                   "size": [26, 10, 0.5], "poling": 1},
                  {"name": "foot", "shape": "cylinder", "material": "CuBe", "centre": [1e3 * x, 1e3 * y, -3],
                   "axis": "z", "radius": 1e3 * r, "height": 3}],
        "faces": {"top": ["ceramic.zmax"], "bottom": ["ceramic.zmin"]},
        "electrodes": {"top": "drive", "bottom": "ground"},
        "analysis": {"near": 30e3, "count": 6},
        "mesh": {"order": 4, "min_layers": 1, "elements_per_wavelength": 3}})


def _solved(monkeypatch, inward: float):
    """The scene's modes with the foot circle's arc middle nodes moved ``inward`` x radius toward its axis."""
    original = swept.section_mesh

    def moved(assembly, axis, sizes):
        uv, quads = original(assembly, axis, sizes)
        (x, y), r = FOOT
        middle = np.unique(quads[4:8])
        rho = np.hypot(uv[0, middle] - x, uv[1, middle] - y)
        on = middle[np.abs(rho / r - 1) < 1e-9]
        uv = uv.copy()
        uv[:, on] = np.array([[x], [y]]) + (uv[:, on] - np.array([[x], [y]])) * (1 - inward)
        return uv, quads

    monkeypatch.setattr(swept, "section_mesh", moved)
    caches.clear()
    return solve_modes(_scene(), fidelity="solid", error_estimate=False)


@pytest.fixture(scope="module")
def monkeymodule():
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("MODALFE_CACHE", "off")
        yield mp


def test_moving_the_walls_changes_the_frequencies_within_the_two_bounds(monkeymodule):
    """Measured: the quadratic arcs' deviation 1.06 % of the radius, the moved ones' 3.0 %; the six modes move by
    up to 29 % of the two bounds' sum. The modes pair in frequency order (one mesh, shifts of < 0.1 %; the labeller
    names one of them differently on the two)."""
    standard, moved = _solved(monkeymodule, 0.0), _solved(monkeymodule, INWARD)
    caches.clear()
    eps = wall_deviations(standard.model)["foot"], wall_deviations(moved.model)["foot"]
    assert eps[0] == pytest.approx(0.0108, rel=0.05)  # a quadratic arc of 90 degrees: 1.08 % at its worst
    assert eps[1] > 0.5 * INWARD + eps[0]  # the middle nodes' move, measured 3.0 %
    bounds = [wall_errors(m.model, np.column_stack([x.shape for x in m]), np.array([x.omega**2 for x in m]))[0]
              for m in (standard, moved)]
    assert len(standard) == len(moved) == 6
    for a, b, ba, bb in zip(standard, moved, *bounds):
        assert abs(a.frequency - b.frequency) / a.frequency <= ba + bb, a.label
