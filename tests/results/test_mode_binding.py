"""A Mode knows its model: displacement and potential at points, modal mass, scene; and ``near`` is only the
eigen solver's shift (the mesh follows the scene's frequency range)."""

import numpy as np
import pytest

from modalfe.solve.api import solve_modes
from tests.oracles.cases import free_plate_scene, k31_bar_scene


@pytest.fixture(scope="module")
def bar_modes():
    return solve_modes(k31_bar_scene(2e-3), error_estimate=False)


def test_a_mode_evaluates_itself_at_points(bar_modes):
    mode = bar_modes.nearest(47e3)
    model = mode.model
    assert mode.scene is model.scene
    # mass-normalised shapes: the generalised mass is 1 kg to solver precision (ARPACK tol 1e-8)
    assert mode.modal_mass == pytest.approx(1.0, rel=1e-6)
    # at the mesh vertices the probe must reproduce the nodal values exactly (interpolation of the
    # field at its own nodes), up to the 1e-9-relative nudge of boundary points into the mesh
    vertices = model.mesh.mesh.p[:, :50].T
    expected = model.nodal_displacement(mode.shape)[:, :50].T
    scale = np.abs(model.nodal_displacement(mode.shape)).max()
    assert np.abs(mode.displacement(vertices) - expected).max() < 1e-6 * scale
    # the potential: 0 V on the grounded bottom in short circuit, up to the nudge of 1e-9 of the device's size
    # that puts a face point inside an element (times the steep through-thickness gradient: ~1e-10 of the peak)
    peak = np.abs(mode.shape[model.n_u:]).max()
    phi_bottom = mode.potential(np.array([[0.015, 0.001, 0.0]]))
    phi_inside = mode.potential(np.array([[0.015, 0.001, 0.00025]]))
    assert abs(phi_bottom[0]) < 1e-8 * peak
    assert abs(phi_inside[0]) > 1e-3 * peak  # a real field inside the poled bar


def test_near_moves_the_shift_not_the_mesh():
    scene = free_plate_scene()
    low = solve_modes(scene, near=5000.0, count=4, error_estimate=False)
    high = solve_modes(scene, near=20000.0, count=4, error_estimate=False)
    assert low.dofs == high.dofs  # same mesh: near only places the shift
    assert min(m.frequency for m in high) > max(m.frequency for m in low) * 0.99  # and the shift moved
    band = solve_modes(scene, band=(150e3, 160e3), error_estimate=False)  # 1.15 mm bending elements < the 1.25 mm cap
    assert band.dofs > low.dofs  # a band is a range the mesh must resolve
