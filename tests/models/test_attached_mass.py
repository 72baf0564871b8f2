"""The attached masses' share of a mode's kinetic energy (``attached_share``), which the labeller reads to tell a
mass's own mode from the structure's pattern (``modalfe.results.labels.CARRIED``)."""

from __future__ import annotations

import numpy as np
import pytest

from modalfe.models.build import build_model
from modalfe.scene import load_scene
from modalfe.solve.api import OWN_MESH, solve_modes


def _heave(model, fidelity: str) -> np.ndarray:
    """The full DOF vector of a unit rigid translation along z."""
    x = np.zeros(model.ndofs)
    stride, component = (5, 2) if fidelity == "plate" else (3, 2)  # plate: (u, v, w, beta_x, beta_y) per node
    x[component : model.n_u : stride] = 1.0
    return x


@pytest.mark.parametrize("fidelity", ["solid", "plate"])
def test_a_rigid_translation_puts_the_attached_mass_ratio_in_the_mass(fidelity):
    # a rigid heave moves every kilogram alike: the share is m_attached / (m_attached + m_panel) exactly
    scene = load_scene("honeycomb_tile", **{"mesh.max_size": 0.05})
    model, _ = build_model(scene, fidelity)
    x = _heave(model, fidelity)
    panel = sum(scene.material(p.material).rho * np.prod(p.size) for p in scene.full_assembly().parts)
    attached = sum(scene.masses.values())
    assert x @ (model.M @ x) == pytest.approx(panel + attached, rel=1e-9)  # the translation is the one meant
    assert model.attached_share(x)[0] == pytest.approx(attached / (attached + panel), rel=1e-9)


def test_no_attached_mass_no_share():
    model, _ = build_model(load_scene("tile_eq5"), "solid")
    assert model.attached_mass is None
    assert np.all(model.attached_share(np.ones((model.ndofs, 2))) == 0.0)


@pytest.mark.slow
def test_the_tile_twisting_mode_keeps_its_label_when_the_pad_is_resolved():
    # on 27-node hexahedra the actuator pad's own twist (~972 Hz, 97 % of its kinetic energy in the pad) shows a
    # (1,1) on the facing as clearly as the plate's twisting mode (~1120 Hz): the label (1,1) stays with the plate's
    modes = solve_modes(load_scene("honeycomb_tile", **{"mesh.family": "lagrange"}), near=1000, count=12,
                        fidelity="solid", error_estimate=False)
    twist = modes.labelled("(1,1)")
    assert 1110 < twist.frequency < 1130
    pad = [m for m in modes if m.label.startswith("(1,1)#")]
    assert pad and all(modes.model.attached_share(m.shape)[0] > 0.9 for m in pad)


@pytest.mark.slow  # 16-21 s on a quiet 2-core machine: on demand (-m slow), the default run kept under 10 min
def test_the_tile_solid_states_an_error_covering_the_converged_twisting_mode():
    # the twisting mode converges to 1118.0647 Hz on quartic Lagrange hexahedra (its antisymmetric quarter at
    # max_size 0.02, 83k DOFs; 0.03 gives 1118.0734 Hz, 7.8e-6 apart: the reference's own uncertainty, added). With 2
    # elements across the actuator pad the 20-node solid stated 0.13 % at 1111.80 Hz, 0.56 % off; the mass patch rule
    # must give an estimate that covers, on the whole tile and on the quarter of its family
    reference, uncertainty = 1118.0647, 7.8e-6
    modes = solve_modes(load_scene("honeycomb_tile"), near=1000, count=12, fidelity="solid", tol=OWN_MESH)
    twist = modes.labelled("(1,1)")
    actual = abs(twist.frequency - reference) / reference
    # (on the whole tile the coarsest estimate grid does not resolve the twist: the estimate is large, and covers)
    assert actual <= twist.error_estimate + uncertainty
    # the report's row: the antisymmetric quarter under auto at 0.5 %. There the default grid's coarsest estimate
    # level pairs the twist with a pad mode 25 % higher (an "order" of 12): unresolved, so auto refines once
    scene = load_scene("honeycomb_tile")
    family, _ = next(w for w in scene.working_modes if w.selector == "(1,1)").family_scene(scene)
    modes = solve_modes(family, near=1100, count=6, fidelity="auto", tol=0.005, check=(("(1,1)", 896.0),))
    twist = modes.labelled("(1,1)")
    actual = abs(twist.frequency - reference) / reference
    assert actual <= twist.error_estimate + uncertainty and twist.error_estimate <= 0.005
