"""Antinode detection and feet placed on them (modalfe/response/placement.py) on made-up fields: no solve.

The field of a (0,n) mode is a standing wave along x whose ridges (antinodes across the plate) vary in strength
along y, as on the whole Cu-Be plate (docs/tuning.md): the ridge near x = 20 mm fell below half the face's peak on
the row of the feet, so the old single threshold over the face cut it there."""

from types import SimpleNamespace

import numpy as np
import pytest

from modalfe.response import placement
from modalfe.response.placement import Antinode, feet_on_antinodes, peaks, ridge_axis

LENGTH, WIDTH = 64e-3, 38e-3
WAVENUMBER = 6 * np.pi / LENGTH  # cos(kx): ridges at x = 0, L/6, ..., L (antinodes), sign alternating


def _field(spacing: float = 0.5e-3):
    """w = cos(k x) e(x) d(y): the free ends 1.8 times as strong as the interior ridges (e = 1 + 0.8 (2x/L - 1)^40,
    1 to 1e-7 at the interior ridges), and the ridges' strength dipping to 0.45 of itself around y = 32 mm (d):
    there an interior ridge is 0.45 / 1.8 = 0.25 of the face's peak, yet 0.56 of its own row's."""
    xs = np.linspace(0, LENGTH, round(LENGTH / spacing) + 1)
    ys = np.linspace(0, WIDTH, round(WIDTH / spacing) + 1)
    X, Y = np.meshgrid(xs, ys)
    ends = 1 + 0.8 * (2 * X / LENGTH - 1) ** 40  # the free ends' larger amplitude
    weak = 1 - 0.55 * np.exp(-(((Y - 32e-3) / 3e-3) ** 2))  # the ridges' dip along y
    return xs, ys, np.cos(WAVENUMBER * X) * ends * weak


def test_a_ridge_weaker_than_half_the_face_peak_is_still_found_on_every_row():
    """Every row of the grid has its interior ridges, at x = j L / 6 to the parabola's sub-grid accuracy (the grid
    step is 0.5 mm; the parabola through cos at three points around its peak is off it by < 1 um: tolerance 2 um);
    with one threshold over the face (the old rule, 2-D maxima at half the face's peak) the row y = 32 mm has no
    interior ridge."""
    xs, ys, W = _field()
    found = peaks(xs, ys, W, along=0)
    row = [a for a in found if a.y == pytest.approx(32e-3)]
    interior = sorted(a.x for a in row if 0 < a.x < LENGTH)
    assert interior == pytest.approx([j * LENGTH / 6 for j in range(1, 6)], abs=2e-6)
    assert np.abs(W).max() * 0.5 > max(abs(a.w) for a in row if 0 < a.x < LENGTH)  # the old rule's cut
    assert all(len([a for a in found if a.y == y]) == 7 for y in ys)  # 5 ridges and the 2 free ends per row
    two_d = peaks(xs, ys, W, along=None)  # 2-D maxima over the face: one threshold for all
    assert not any(abs(a.y - 32e-3) < 1e-9 and 0 < a.x < LENGTH for a in two_d)


def test_ridge_axis_of_the_labels():
    assert ridge_axis("(0,6)") == 0 and ridge_axis("(3,0)") == 1
    assert ridge_axis("(0,0)") is None and ridge_axis("(2,5)") is None and ridge_axis("bending-z 3") is None


def test_feet_move_across_the_ridges_only_and_stay_on_the_plate(monkeypatch):
    """Feet near the in-phase ridges x = L/6 and 5L/6 (cos(k x) = -1 there) keep their y: the foot at
    y = 32 mm goes to x = L/6 on its own row, not to a stronger ridge point rows away (the old weighted nearest
    point took it to y = 34.8 mm); a foot past the plate's edge is brought its half size inside."""
    xs, ys, W = _field()
    monkeypatch.setattr(placement, "antinodes", lambda mode, part: peaks(xs, ys, W, along=0))
    box = SimpleNamespace(lo=(0.0, 0.0, 0.0), hi=(LENGTH, WIDTH, 1e-3))
    scene = SimpleNamespace(full_assembly=lambda: SimpleNamespace(part=lambda name: box))
    mode = SimpleNamespace(label="(0,6)", model=SimpleNamespace(scene=scene))
    feet = [(11.5e-3, 6e-3), (52.0e-3, 6e-3), (11.5e-3, 32.1e-3), (52.0e-3, 32.1e-3), (31e-3, 37.9e-3)]
    placed = feet_on_antinodes(mode, feet, part="plate", foot_size=3e-3)
    assert [y for _, y in placed[:4]] == [y for _, y in feet[:4]]
    assert [x for x, _ in placed] == pytest.approx([LENGTH / 6, 5 * LENGTH / 6] * 2 + [LENGTH / 2], abs=2e-6)
    assert placed[4][1] == pytest.approx(WIDTH - 1.5e-3)


def test_a_two_d_mode_takes_the_nearest_in_phase_peak(monkeypatch):
    """Away from ridge modes the nearest antinode in phase with the first foot's, by distance in the plane."""
    found = [Antinode(10e-3, 10e-3, 2.0), Antinode(12e-3, 10e-3, -3.0), Antinode(30e-3, 20e-3, 1.5)]
    monkeypatch.setattr(placement, "antinodes", lambda mode, part: found)
    box = SimpleNamespace(lo=(0.0, 0.0, 0.0), hi=(LENGTH, WIDTH, 1e-3))
    scene = SimpleNamespace(full_assembly=lambda: SimpleNamespace(part=lambda name: box))
    mode = SimpleNamespace(label="(2,5)", model=SimpleNamespace(scene=scene))
    placed = feet_on_antinodes(mode, [(9e-3, 9e-3), (13e-3, 11e-3)], part="plate", foot_size=3e-3)
    assert placed == ((10e-3, 10e-3), (10e-3, 10e-3))  # the second skips the nearer out-of-phase peak
