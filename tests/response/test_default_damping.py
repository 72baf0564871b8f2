"""The default damping comes from the device: each material's Qm weighted by the mode's strain energy (the
modal strain-energy method, Johnson & Kienholz 1982), the scene's fixed fallback for the rest, each stated
with its source; a device with no Qm in the table takes the fallback and says so."""

from __future__ import annotations

import numpy as np
import pytest

from modalfe.response.losses import mode_damping, resolve_losses
from modalfe.response.stress import part_fields
from modalfe.scene import load_scene
from modalfe.solve.api import solve_modes
from tests.hostile.cases import BIMORPH, TINY


@pytest.fixture(scope="module")
def bimorph(tmp_path_factory):
    path = tmp_path_factory.mktemp("bimorph") / "bimorph.toml"
    path.write_text(BIMORPH)
    scene = load_scene(str(path))
    modes = solve_modes(scene, band=(300.0, 900.0), fidelity="solid", error_estimate=False)
    return scene, modes.labelled("bending-z 1")


def _elastic_energy(mode, part: str) -> float:
    """u^T K_part u of the mode's displacement: the integral of S . c^E S over the part, from the strain and the
    stress of the displacement alone (potential set to 0, so sigma = c^E S), by quadrature."""
    x = np.array(mode.shape, dtype=float)
    x[mode.model.n_u:] = 0.0
    f = part_fields(mode.model, x, part)
    return float(np.sum(np.sum(f.strain * f.stress, axis=0) * f.weights))


def test_bimorph_damping_is_its_patchs_qm_and_the_steels_fallback_by_strain_energy(bimorph):
    # PZT-5A Qm = 75 (modalfe.scene.materials, Berlincourt 1964 via Sherman & Butler); the steel beam has none:
    # the scene's fallback Q = 150 (modalfe.scene.scene.Drive). eta = f / 75 + (1 - f) / 150, f the patch's share
    # of the strain energy, recomputed here from the stress module's quadrature (another route than the
    # assembled per-material stiffness): the two agree to the quadrature's rounding, 1e-9.
    scene, mode = bimorph
    losses = resolve_losses(scene)
    assert losses.mechanical == "material" and losses.fallback == "Q=150"
    damping, source = mode_damping(mode, losses)
    patch, beam = _elastic_energy(mode, "patch"), _elastic_energy(mode, "beam")
    share = patch / (patch + beam)
    assert 0.01 < share < 0.99  # both materials carry energy: the weighting is exercised
    quality = damping.Q
    assert quality == pytest.approx(1 / (share / 75 + (1 - share) / 150), rel=1e-9)
    assert "PZT-5A Qm 75" in source and "Q=150" in source and "assumption" in source


def test_device_without_qm_takes_the_fallback_and_says_so(tmp_path):
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    scene = load_scene(str(path))
    mode = solve_modes(scene, near=2000.0, count=2, fidelity="solid", error_estimate=False)[0]
    damping, source = mode_damping(mode, resolve_losses(scene))
    assert damping.Q == 150
    assert "no material of the scene has a sourced Qm" in source


def test_a_damping_the_user_gives_wins_over_the_materials(bimorph):
    scene, mode = bimorph
    damping, source = mode_damping(mode, resolve_losses(scene, damping="Q=40"))
    assert damping.Q == 40 and source == "set by the user"
    damping, _ = mode_damping(mode, resolve_losses(scene, damping="eta=0.01"))
    assert damping.zeta == pytest.approx(0.005, rel=1e-12)  # eta / 2 at resonance
