"""studies/forecast_calibration.py sets where auto starts refining (``FORECAST_GRID``, ``FORECAST_FIRST_STEP``)
from scenes the report does not solve: the constants are what its cases give, the two cases that set them quickly,
every case on demand (slow, ~1 min)."""

import pytest

from modalfe.report.report import working_windows
from modalfe.scene import load_scene
from modalfe.scene.builtin import BUILTIN
from modalfe.solve import fidelity
from tests.helpers import load_study

STUDY = load_study("forecast_calibration")
SETTING_CASES = ("glass plate, near 150 kHz", "brass cantilever 60 x 4 x 4 mm, near 20 kHz")


def _rows(names):
    return [STUDY.calibrate(name, *STUDY.CALIBRATION_CASES[name]) for name in names]


def test_the_cases_that_set_the_ratios_give_them():
    grid, step = STUDY.least_ratios(_rows(SETTING_CASES))
    assert (grid, step) == (fidelity.FORECAST_GRID, fidelity.FORECAST_FIRST_STEP)


@pytest.mark.slow
def test_every_case_gives_the_ratios():
    rows = _rows(STUDY.CALIBRATION_CASES)
    assert STUDY.least_ratios(rows) == (fidelity.FORECAST_GRID, fidelity.FORECAST_FIRST_STEP)
    assert sum(r.forecast > 0 for r in rows) >= 10  # the least of ten ratios at least


def test_no_case_is_a_report_window():
    windows = {(w.scene, w.near) for name in BUILTIN for w in working_windows(load_scene(name))}
    for factory, near in STUDY.CALIBRATION_CASES.values():
        scene = factory()
        assert all(scene != s or (n is not None and abs(near - n) > 0.05 * n) for s, n in windows)
