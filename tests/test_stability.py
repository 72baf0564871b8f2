"""Numerical stability: scaling of the potential unknowns, units, continuity, random valid scenes."""

import numpy as np
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from modalfe.linalg import condition_estimate, factorize
from modalfe.scene import load_scene, scene_from_dict
from modalfe.solvers import assembled_model, solve_modes


def _shifted(model, scale: float, frequency: float):
    """Short-circuit K - omega^2 M on the free unknowns, potentials scaled by ``scale`` instead of
    the model's own ``potential_scale()`` (the constraints carry that one: undo it)."""
    T = model.constraints("short").T
    A = (T.T @ model.K @ T).tocsr()
    B = (T.T @ model.M @ T).tocsr()
    n_u_free = model.n_u - len(model.clamped)
    rescale = sp.diags(np.r_[np.ones(n_u_free), np.full(A.shape[0] - n_u_free, scale / model.potential_scale())])
    return (rescale @ (A - (2 * np.pi * frequency) ** 2 * B) @ rescale).tocsr()


def test_scaling_the_potentials_improves_the_conditioning():
    scene = load_scene("ciliary_beam", **{"mesh.elements_per_wavelength": 4.0})
    model, _, _ = assembled_model(scene)
    scaled = _shifted(model, model.potential_scale(), 20e3)
    raw = _shifted(model, 1.0, 20e3)
    c_scaled = condition_estimate(scaled, factorize(scaled)[0])
    c_raw = condition_estimate(raw, factorize(raw)[0])
    # volts against metres: unscaled, the potential block is ~1e-8 of the elastic one
    assert c_raw > 100 * c_scaled
    assert c_scaled < 1e14  # leaves several digits in double precision


def test_same_device_in_metres_and_millimetres_has_the_same_frequencies():
    def bar(units, scale):
        return scene_from_dict({
            "name": "bar", "units": units, "kind": "beam",
            "parts": [{"name": "bar", "material": "CuBe", "origin": [0, 0, 0],
                       "size": [40 * scale, 4 * scale, 2 * scale]}],
            "faces": {"clamp": ["bar.xmin"]}, "clamps": {"clamp": "xyz"},
            "analysis": {"near": 5000.0, "count": 4},
        })

    a = solve_modes(bar("mm", 1.0), error_estimate=False).frequencies
    b = solve_modes(bar("m", 1e-3), error_estimate=False).frequencies
    # identical meshes and matrices up to round-off; ARPACK's tol = 1e-8 bounds the eigenvalues' agreement
    np.testing.assert_allclose(a, b, rtol=1e-7)


def test_frequency_moves_smoothly_with_a_small_parameter_change():
    base = solve_modes(load_scene("ciliary_beam"), near=22e3, count=4, error_estimate=True)
    mode = base.labelled("bending-z 6")
    moved = solve_modes(load_scene("ciliary_beam", x0=0.0681), near=22e3, count=4,
                        error_estimate=False).labelled("bending-z 6")
    # a 0.1 mm shift of the sheets remeshes the beam: the jump stays inside the stated error estimate
    assert abs(moved.frequency / mode.frequency - 1) < mode.error_estimate


@settings(max_examples=6, deadline=None)
@given(length=st.floats(0.02, 0.08), width=st.floats(0.002, 0.02), thickness=st.floats(0.0005, 0.004),
       E=st.floats(1e9, 4e11), nu=st.floats(0.0, 0.45), rho=st.floats(1000.0, 20000.0))
def test_random_valid_plates_have_spd_matrices_and_positive_frequencies(length, width, thickness, E, nu, rho):
    scene = scene_from_dict({
        "name": "random", "kind": "plate",
        "materials": {"m": {"E": E, "nu": nu, "rho": rho}},
        "parts": [{"name": "p", "material": "m", "origin": [0, 0, 0], "size": [length, width, thickness]}],
        "faces": {"clamp": ["p.xmin"]}, "clamps": {"clamp": "xyz"},
        "analysis": {"near": 1000.0, "count": 3}, "mesh": {"elements_per_wavelength": 3.0},
    })
    model, _, _ = assembled_model(scene)
    K, M = model.K, model.M
    for A in (K, M):
        assert abs(A - A.T).max() <= 1e-9 * abs(A).max()  # symmetric to round-off
    x = np.random.default_rng(0).standard_normal(K.shape[0])
    assert x @ (M @ x) > 0 and x @ (K @ x) > 0  # positive (semi)definite in a random direction
    modes = solve_modes(scene, near=1000.0, count=3, error_estimate=False)
    assert np.all(modes.frequencies > 0)
