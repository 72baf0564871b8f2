"""Stress and field recovery: a bar under axial force (sigma = F / A), a free piezo bar under a voltage
(E = V / t, no stress), the peaks over a cycle, and the materials' strength limits."""

import numpy as np
import pytest

from modalfe.errors import SceneError
from modalfe.models.build import build_model
from modalfe.response.loads import Load, harmonic_state, load_vector, output_operators
from modalfe.response.stress import _NORM, _VM, _cycle_peak, _principal_peak, limit_loads, part_fields, part_peaks
from modalfe.response.superposition import static_response
from modalfe.scene import scene_from_dict
from modalfe.scene.materials import strength_limits
from tests.oracles.cases import cantilever_scene, k31_bar_scene


def test_axial_force_gives_f_over_a():
    scene = cantilever_scene(2.5e-3).with_overrides(faces={"clamp": ["beam.xmin"], "tip": ["beam.xmax"]})
    model, _ = build_model(scene)
    F, A, L, E = 3.0, 0.005**2, 0.1, 105e9
    x = F * static_response(model, load_vector(model, Load("force", "tip", (F, 0, 0)))[0])  # per N, times F
    fields = part_fields(model, x, "beam")
    points, stress, field = fields.points, fields.stress, fields.field
    middle = (points[0] > 0.03) & (points[0] < 0.07)  # > 6 widths from the clamp: Saint-Venant decay ~exp(-12)
    # a uniform traction gives a uniform stress, which quadratic elements hold exactly: only rounding remains
    np.testing.assert_allclose(stress[0][middle], F / A, rtol=1e-6)
    assert np.abs(stress[1:][:, middle]).max() < 1e-6 * F / A
    assert field is None
    # the clamp stops the root's Poisson contraction: the bar is 0.25 % stiffer than F L / E A, never softer
    tip = (output_operators(model, ["mean:tip"])["mean:tip"] @ x)[0]
    assert -0.005 < tip / (F * L / (E * A)) - 1 < 0


def test_free_piezo_bar_field_is_v_over_t():
    model, _ = build_model(k31_bar_scene(1e-3))
    # 100 Hz against the bar's first mode at ~47 kHz: the dynamic part is (100 / 47e3)^2 ~ 5e-6 of the response
    x = harmonic_state(model, Load(), 100.0)
    fields = part_fields(model, x, "bar")
    stress, field = fields.stress, fields.field
    t = 1e-3
    # uniform strain of a free bar leaves the field uniform: exactly representable, rounding only
    np.testing.assert_allclose(np.abs(field[2]), 1.0 / t, rtol=1e-6)
    assert np.abs(field[:2]).max() < 1e-6 / t
    # free expansion: sigma = c^E S - e^T E vanishes (to the dynamic 5e-6), a check of the e-form sign
    assert np.abs(stress).max() < 1e-4 * 15.8 / t
    peak = part_peaks(model, x)[0]
    assert peak.field.value == pytest.approx(1.0 / t, rel=1e-6)


def test_cycle_peaks_against_sampling():
    rng = np.random.default_rng(3)
    s = rng.normal(size=(6, 50)) + 1j * rng.normal(size=(6, 50))
    t = np.linspace(0, 2 * np.pi, 3601)
    real = s.real[..., None] * np.cos(t) - s.imag[..., None] * np.sin(t)  # (6, 50, 3601)
    for Q in (_VM, _NORM):
        sampled = np.sqrt(np.einsum("knt,kl,lnt->nt", real, Q, real).max(axis=1))
        # exact peak >= any sample, and within the 0.05 deg sampling (1 - cos 0.05 deg = 4e-7)
        assert np.all(_cycle_peak(s.real, s.imag, Q) >= sampled * (1 - 1e-12))
        np.testing.assert_allclose(_cycle_peak(s.real, s.imag, Q), sampled, rtol=1e-6)
    T = np.zeros((50, 3601, 3, 3))
    for (i, j), k in zip(((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)), range(6), strict=True):
        T[..., i, j] = T[..., j, i] = real[k]
    brute = np.linalg.eigvalsh(T)[..., -1].max()
    value, _ = _principal_peak(s)
    assert value == pytest.approx(brute, rel=1e-3)  # 72 phases: 1 - cos(2.5 deg) < 1e-3


def test_strength_limits_have_sources():
    pzt4 = strength_limits("PZT-4")
    assert pzt4.depolarising_field == 1.0e6 and pzt4.tensile_strength == 76e6 and "TP-226" in pzt4.source
    assert strength_limits("CuBe") is None  # no source, no limit
    data = {"name": "s", "parts": [{"name": "p", "material": "m", "origin": [0, 0, 0], "size": [0.01, 0.01, 0.001]}],
            "materials": {"m": {"E": 70e9, "nu": 0.3, "rho": 2700.0, "tensile_strength": 200e6,
                                "limits_source": "my datasheet"}},
            "faces": {"c": ["p.xmin"]}, "clamps": {"c": "xyz"}, "analysis": {"near": 1e3}}
    scene = scene_from_dict(data)
    mine = strength_limits("m", scene)
    assert mine.tensile_strength == 200e6 and mine.depolarising_field is None and mine.source == "my datasheet"
    from modalfe.response.stress import PartStress, Peak

    rows = limit_loads([PartStress("p", "m", Peak(1.0, (0, 0, 0)), Peak(4e6, (0, 0, 0)), None)], scene)
    assert rows == [{"part": "p", "material": "m", "limit": "tensile_strength", "limit_value": 200e6,
                     "source": "my datasheet", "peak_per_unit_load": 4e6, "load_to_limit": 50.0}]
    data["materials"]["m"]["tensile_strength"] = -1.0
    with pytest.raises(SceneError, match=r"^materials.m.tensile_strength"):
        scene_from_dict(data)


@pytest.mark.slow
def test_cube_plate_ceramics_stress_at_resonance():
    from modalfe.response.figures import forced_figures
    from modalfe.scene import load_scene

    fig = forced_figures(load_scene("cube_plate"), stress=["ceramic_1", "ceramic_5"])
    for p in fig.stress:
        # the applied 1 V / 1 mm is the floor of the peak field; the resonant strain adds its own
        assert p.field.value >= 0.99e3
    volts = [r["load_to_limit"] for r in fig.limits]
    assert all(v > 0 for v in volts) and len(volts) == 4


def _curved_piezo(shape: str) -> dict:
    """A PZT-4 disc poled along x (constant rotated tensors) or a ring poled radially (tensors per point)."""
    if shape == "disc":
        part = {"name": "p", "shape": "cylinder", "material": "PZT-4", "centre": [0, 0, 0], "axis": "x",
                "radius": 5, "height": 1, "poling": "+x"}
        faces = {"a": ["p.top"], "b": ["p.bottom"]}
    else:
        part = {"name": "p", "shape": "ring", "material": "PZT-4", "centre": [0, 0, 0], "axis": "z", "inner": 4,
                "outer": 5, "height": 1, "poling": "radial"}
        faces = {"a": ["p.outer"], "b": ["p.inner"]}
    return {"units": "mm", "parts": [part], "faces": faces, "electrodes": {"a": "drive", "b": "ground"},
            "analysis": {"near": 50e3, "count": 4}, "mesh": {"max_size": 2, "min_layers": 1}}


@pytest.mark.parametrize("shape", ["disc", "ring"])
def test_stress_of_a_curved_piezo_part_is_the_models_own(shape):
    # issue 35: `forced --stress` on a cylinder, ring or extrusion that is poled raised TypeError (the stress read a
    # box's +-1 poling). Law: the stress and field the part reports, integrated against the strain of every test
    # function, are the model's internal force, int B^T (c^E S - e^T E) dV = K_uu u + K_uphi phi, for any state x
    # (the model's own tensors: rotated along x, or per quadrature point about the ring's axis). 1e-9: round-off
    from skfem import Basis, ElementVector, LinearForm

    from modalfe.models.solid import element_for

    scene = scene_from_dict(_curved_piezo(shape))
    model, _ = build_model(scene)
    x = np.random.default_rng(1).standard_normal(model.n_u + model.n_phi)
    fields = part_fields(model, x, "p")
    stress, field = fields.stress, fields.field
    assert field is not None

    @LinearForm
    def internal(v, w):
        G = v.grad
        strain = (G[0, 0], G[1, 1], G[2, 2], G[1, 2] + G[2, 1], G[0, 2] + G[2, 0], G[0, 1] + G[1, 0])
        return sum(w[f"T{k}"] * strain[k] for k in range(6))

    basis = Basis(model.mesh.mesh, ElementVector(element_for(scene.mesh)), intorder=2 * scene.mesh.order)
    force = internal.assemble(basis, **{f"T{k}": stress[k] for k in range(6)})
    expected = model.K[: model.n_u] @ x
    assert np.abs(force - expected).max() <= 1e-9 * np.abs(expected).max()
