"""Honeycomb tile study (seed 002, issue 8) at coarse resolution: suspension modes against the lumped
model, the antiresonance of the actuator-driven response, the suspension design and the inverse filter."""

import math

import numpy as np
import pytest
import tile_design as tile

from modalfe.errors import ModalfeError, SceneError
from modalfe.results.labels import RIGID_NAMES
from tests.helpers import assert_one_line_error, load_study

STUDY = load_study("tile_study")


@pytest.fixture(scope="module")
def study():
    return STUDY.run(coarse=True)


def test_six_suspension_modes_then_plate_modes(study):
    modes = study.modes
    rigid = tile.suspension_modes(modes)
    # the tile on four mounts has exactly six rigid-body modes, one per rigid-body motion (seed 002 sec. 4.4.1)
    assert sorted(m.label for m in rigid) == sorted(RIGID_NAMES)
    # and they sit far below the first elastic mode: the seed's 28-77 Hz against 896 Hz
    assert max(m.frequency for m in rigid) < 0.3 * min(m.frequency for m in tile.plate_modes(modes))


def test_heave_and_sway_match_the_lumped_suspension(study):
    scene = study.modes.model.scene
    M = tile.moving_mass(scene)
    kx, _, kz = scene.springs["mount_1"]
    lumped_heave = math.sqrt(4 * kz / M) / (2 * math.pi)  # seed 002 sec. 4.3, f0 = sqrt(4K / M) / 2 pi
    lumped_sway = math.sqrt(4 * kx / M) / (2 * math.pi)
    heave = study.modes.labelled("heave").frequency
    # The panel's bending between the mounts and the central mass, its core shear and the core's
    # compression under the actuator pad are springs in series with the mounts: they can only lower
    # the heave. Their compliance is a few % of the mounts' (a sandwich plate point-loaded at the centre
    # and held at four points, D ~ 17 kN m, is ~20 MN/m stiff against 4 x 64 kN/m), so f drops 1-3 %;
    # 5 % leaves room for the coarse mesh (4 elements per wavelength), which stiffens rather than softens.
    assert 0.95 * lumped_heave < heave < lumped_heave
    # sway: the springs act at the underside, 2.5 cm below the panel's centre of mass, so sway couples
    # to rocking (165 Hz here, 7x higher), which can only lower it, by at most ~(f_sway / f_rock)^2 ~ 2 %
    for name in ("sway-x", "sway-y"):
        assert 0.95 * lumped_sway < study.modes.labelled(name).frequency <= lumped_sway * (1 + 1e-6)


def test_only_the_symmetric_modes_are_driven(study):
    force = tile.face_force(study.modes.model)
    # the centred actuator is a node of every mode antisymmetric about a centre line (seed 002 eq. (9):
    # eta(r_i) = 0, so the mode is not excited); symmetry makes their modal forces zero to round-off
    # (1e-7 of the heave's, the eigensolver's tolerance on the shapes), so 1e-4 cannot be crossed by chance
    drive = tile.relative_drive(study.modes, force)
    for m in study.modes:
        if m.label in ("sway-x", "sway-y", "roll", "pitch", "yaw", "(1,1)"):
            assert drive[m.index] < 1e-4, (m.label, drive[m.index])
    assert study.first_driven > study.modes.labelled("heave").frequency


def test_the_force_is_the_total_asked_for(study):
    # the uniform traction integrates to the total force: the nodal loads (z entries only) sum to it
    f = tile.face_force(study.modes.model, total=3.0)
    assert f.sum() == pytest.approx(3.0, rel=1e-12)


def test_antiresonance_below_the_first_driven_plate_mode(study):
    heave = study.modes.labelled("heave").frequency
    twisting = study.modes.labelled("(1,1)").frequency
    centre = study.antiresonances["centre"]
    # above the actuator the response is (nearly) a driving-point FRF, whose poles and zeros alternate:
    # a zero must lie between the heave and the first driven elastic mode (seed 002 sec. 5.1: the
    # antiresonance near 775 Hz below the plate's first resonance); 6 dB within +-15 % in frequency
    # separates it from the flat mass line (local_extrema)
    inside = centre[(centre > heave) & (centre < study.first_driven)]
    assert len(inside) == 1, centre
    assert inside[0] < twisting


def test_response_is_uniform_below_the_plate_modes(study):
    # seed 002 Fig. 11: "below the first resonant mode the response is approximately constant over the
    # surface". At 200 Hz the elastic modes' quasi-static share is ~(200 / 850)^2 = 6 % of the rigid
    # mass line at most, i.e. < 0.5 dB between points; 1 dB keeps the bound loose but finite
    r = study.response
    i = int(np.argmin(np.abs(r.frequency - 200.0)))
    db = [r.magnitude_db(n)[i] for n in r.acceleration]
    assert max(db) - min(db) < 1.0


def test_lumped_suspension_design():
    seed = tile.suspension_design(E=tile.SEED_MOUNT_E)
    # the seed's own inputs in the seed's formula: f0 is printed as "~49 Hz" (two digits), so +-0.5 Hz
    assert seed.f0 == pytest.approx(tile.SEED_F0, abs=0.5)
    # Fig. 9: f0 rises and dz falls with E
    designs = [tile.suspension_design(E=e) for e in np.linspace(0.5e6, 5e6, 10)]
    assert np.all(np.diff([d.f0 for d in designs]) > 0)
    assert np.all(np.diff([d.deflection for d in designs]) < 0)
    chosen = tile.choose_design(tile.design_grid(STUDY.E_GRID, STUDY.H_GRID))
    assert chosen.f0 <= tile.F0_MAX and chosen.deflection < tile.DEFLECTION_MAX
    # the two constraints cannot both hold when one mount takes the whole load (dz = F / K): f0 <= 50 Hz
    # needs K <= 66.6 kN/m, dz < 5 mm needs K > 200 kN/m
    assert not any(d.f0 <= tile.F0_MAX and d.deflection_one < tile.DEFLECTION_MAX
                   for d in tile.design_grid(STUDY.E_GRID, STUDY.H_GRID))


def test_inverse_filter_flattens_the_passband(study):
    for order, flt in study.filters.items():
        assert flt.stable and flt.minimum_phase, order
        # seed 002 Fig. 14: the N = 14 correction is "flat" over 50-750 Hz; we ask for at least a 3x
        # (~10 dB on a 15 dB ripple) reduction of the ripple, which a filter that only shifted the
        # level or tracked the suspension peak alone could not give
        assert flt.ripple_after < flt.ripple_before / 3, (order, flt.ripple_before, flt.ripple_after)
    # the order-14 family contains the order-10 one (two pole-zero pairs that cancel), so a good fit is
    # no worse; 0.5 dB allows for the local optimiser
    assert study.filters[14].ripple_after <= study.filters[10].ripple_after + 0.5


def test_study_prints_and_plots(study, tmp_path, capsys):
    STUDY.print_tables(study)
    text = capsys.readouterr().out
    assert "heave" in text and "ripple" in text and "antiresonances" in text
    for path in STUDY.write_plots(study, tmp_path):
        assert path.suffix == ".png" and path.stat().st_size > 0


@pytest.mark.parametrize(("call", "field"), [
    (lambda: tile.suspension_design(E=-1.0), "suspension.E"),
    (lambda: tile.design_inverse_filter(np.geomspace(10, 2000, 50), np.ones(50), order=9), "filter.order"),
    (lambda: tile.local_extrema(np.geomspace(10, 2000, 50), np.ones(50), kind="peak"), "kind"),
])
def test_bad_input_gets_a_one_line_error(call, field):
    assert_one_line_error(call, field, ModalfeError)


def test_unknown_force_face_is_named(study):
    with pytest.raises(SceneError, match=r"^force: no face group 'shaker'"):
        tile.face_force(study.modes.model, "shaker")
