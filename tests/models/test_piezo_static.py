"""Driven electrodes: a free PZT bar under a prescribed voltage strains exactly by d31 E3 and d33 E3."""

import numpy as np
import pytest

from modalfe.models.build import build_model
from modalfe.response.superposition import static_voltage_response
from modalfe.scene import scene_from_dict
from modalfe.scene.materials import MATERIALS

L, W, T = 0.02, 0.004, 0.001


def _bar(poling: int):
    return scene_from_dict({
        "name": "bar", "kind": "beam",
        "parts": [{"name": "bar", "material": "PZT-5A", "origin": [0, 0, 0], "size": [L, W, T], "poling": poling}],
        "faces": {"x0": ["bar.xmin"], "y0": ["bar.ymin"], "z0": ["bar.zmin"], "top": ["bar.zmax"],
                  "bottom": ["bar.zmin"]},
        # rollers on three orthogonal faces: rigid motions removed, expansion free in every direction
        "clamps": {"x0": "x", "y0": "y", "z0": "z"},
        "electrodes": {"top": "drive", "bottom": "ground"},
        "analysis": {"near": 1e5},
    })


@pytest.mark.parametrize("poling", [1, -1])
def test_free_bar_strains_by_the_d_constants(poling):
    volts = 100.0
    scene = _bar(poling)
    model, _ = build_model(scene)
    x = static_voltage_response(model, volts)
    u = model.nodal_displacement(x)
    p = model.mesh.mesh.p
    m = MATERIALS["PZT-5A"]
    d = m.e @ np.linalg.inv(m.C)  # d = e s^E [C/N] (IEEE Std 176-1987)
    E3 = -volts / T  # field from the driven top (V) to the grounded bottom (0 V), along -z
    # with stress-free expansion the strain is uniform, S = d^T E, which quadratic elements
    # represent exactly: only round-off remains
    far_x = np.isclose(p[0], L)
    top = np.isclose(p[2], T)
    assert u[0, far_x] == pytest.approx(poling * d[2, 0] * E3 * L, rel=1e-8)
    assert u[2, top] == pytest.approx(poling * d[2, 2] * E3 * T, rel=1e-8)
    assert d[2, 0] < 0 < d[2, 2]  # PZT: contracts across, extends along the poling axis


@pytest.mark.parametrize("poling", [1, -1])
def test_the_voltage_load_is_minus_k_times_the_prescribed_potential(poling):
    """``voltage_load`` reads K's driven rows only (K symmetric): the same vector as the full product -K x_V to
    round-off (one product's sums in another order), and K is symmetric and canonical (sorted rows, no duplicates:
    its projection then needs no sort) for the row reading to be right."""
    model, _ = build_model(_bar(poling))
    K = model.K
    assert K.has_canonical_format
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    full = -(K @ model.prescribed_potential(100.0))
    assert np.abs(model.voltage_load(100.0) - full).max() <= 1e-12 * np.abs(full).max()
    assert np.abs(full).max() > 0
