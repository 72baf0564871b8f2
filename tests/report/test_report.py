"""The report's accuracy goals (issue 3), checked on the default report of every device."""

import pytest

from modalfe.report.report import run_report


@pytest.fixture(scope="module")
def rows():
    return {(r.scene, r.mode): r for r in run_report(progress=False)}


def _row(rows, scene):
    found = [r for (s, _), r in rows.items() if s == scene]
    assert found and all(r.mode != "FAILED" for r in found), found
    return found


def _deviation(row, name):
    return next(t["deviation"] for t in row.targets if t["name"] == name)


def test_cube_plate_within_three_percent_of_the_measurement(rows):
    (row,) = _row(rows, "cube_plate")
    assert row.mode == "(0,6)"
    # issue 3: within 3 % of the measured 40.7 kHz with sourced physics (the seed's Abaqus: +4.9 %)
    assert abs(_deviation(row, "f_measured")) < 0.03
    assert row.error_estimate is not None and row.error_estimate < 0.02


def test_glass_wavelengths_within_ten_percent(rows):
    low, high = sorted(_row(rows, "glass_plate"), key=lambda r: r.frequency_hz)
    for row in (low, high):
        assert row.mode.startswith("(0,")
        # issue 3: wavelengths within 10 % of the measured 15 mm and 7.5 mm
        assert abs(_deviation(row, "wavelength_measured")) < 0.10


def test_ciliary_beam_below_euler_bernoulli(rows):
    (row,) = _row(rows, "ciliary_beam")
    assert row.mode == "bending-z 6"
    # shear and rotary inertia lower mode 6 by ~11 % from Euler-Bernoulli (tests/models/test_verification.py)
    assert -0.15 < _deviation(row, "f_analytic") < -0.05


def test_tile_suspension_and_equivalent_plate(rows):
    heave, plate = sorted(_row(rows, "honeycomb_tile"), key=lambda r: r.frequency_hz)
    assert heave.mode == "heave"
    # lumped 4 EA / (h M0) gives 49 Hz; the plate's own bending softens it slightly: within 10 %
    assert abs(_deviation(heave, "f_lumped")) < 0.10
    assert plate.mode == "(1,1)"
    (eq5,) = _row(rows, "tile_eq5")
    # the equivalent plate reproduces eq. (5) up to shear and rotary inertia at h / L = 0.08 (~2 %)
    assert abs(_deviation(eq5, "f_analytic_eq5")) < 0.04


def test_devices_in_parallel_processes_give_the_sequential_rows():
    names = ["tile_eq5", "ciliary_beam"]
    sequential, parallel = (run_report(names, progress=False, jobs=jobs) for jobs in (1, 2))
    assert [(r.scene, r.mode, r.dofs, r.fidelity) for r in parallel] == \
        [(r.scene, r.mode, r.dofs, r.fidelity) for r in sequential]
    for a, b in zip(parallel, sequential):
        # same meshes, same solver: only ARPACK's start vector differs, so agreement is to its tolerance
        assert a.frequency_hz == pytest.approx(b.frequency_hz, rel=1e-8)


def test_bad_report_arguments_fail_before_any_solve():
    from modalfe.errors import SceneError

    with pytest.raises(ValueError, match="jobs"):
        run_report(["tile_eq5"], progress=False, jobs=0)
    with pytest.raises(SceneError):
        run_report(["tile_eq5", "no_such_device"], progress=False)


def test_the_largest_window_starts_first_and_the_rows_keep_the_order_asked():
    from modalfe.models.estimate import estimate_size
    from modalfe.report.report import solve_order, working_windows
    from modalfe.scene import load_scene

    scenes = {name: load_scene(name) for name in ("tile_eq5", "honeycomb_tile", "ciliary_beam")}
    # the report's solves: the tile's two working modes each on a quarter (their mirror families), the others one
    windows = {name: [round(estimate_size(w.scene).dofs, -3) for w in working_windows(s)] for name, s in scenes.items()}
    assert windows == {"tile_eq5": [1000], "honeycomb_tile": [16000, 16000], "ciliary_beam": [4000]}
    # each window a task of its own (the tile's two may run at once), the most work first: DOFs times the working
    # modes' frequency over the mesh's (the tile's twist near 896 Hz of 1.5 kHz, the beam's 24.2 of 30 kHz, the
    # tile's heave near 45 Hz, the equivalent plate's 845 Hz of 2 kHz on 1,000 DOFs)
    assert solve_order(scenes) == [("honeycomb_tile", 1), ("ciliary_beam", 0), ("honeycomb_tile", 0), ("tile_eq5", 0)]
    rows = run_report(["tile_eq5", "honeycomb_tile", "ciliary_beam"], progress=False, jobs=2, error_estimate=False)
    assert [(r.scene, r.mode) for r in rows] == [("tile_eq5", "(0,0)"), ("honeycomb_tile", "heave"),
                                                 ("honeycomb_tile", "(1,1)"), ("ciliary_beam", "bending-z 6")]


def test_workers_fork_only_from_a_process_without_mkl_threads():
    # a fork copies no thread: a parent that has loaded MKL (PARDISO's OpenMP threads) spawns fresh interpreters
    import json
    import subprocess
    import sys

    script = ("from modalfe.report.report import _start_method; a = _start_method(); "
              "from modalfe.solve.linalg import factorize; import scipy.sparse as sp; "
              "factorize(sp.identity(3, format='csr')); print(a, _start_method())")
    first, then = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                                 check=True).stdout.split()
    from modalfe.solve.linalg import available_solvers

    assert first == "fork"
    assert then == ("spawn" if "pardiso" in available_solvers() else "fork")
    # a fresh command's report forks its workers: the rows of the sequential report
    script = ("import json; from modalfe.report.report import _start_method, run_report; assert _start_method() == "
              "'fork'; rows = run_report(['tile_eq5', 'ciliary_beam'], progress=False, jobs=2); "
              "print(json.dumps([(r.scene, r.mode, r.dofs, r.frequency_hz) for r in rows]))")
    forked = json.loads(subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                                       check=True).stdout)
    sequential = run_report(["tile_eq5", "ciliary_beam"], progress=False, jobs=1)
    assert [tuple(r[:3]) for r in forked] == [(r.scene, r.mode, r.dofs) for r in sequential]
    assert [r[3] for r in forked] == pytest.approx([r.frequency_hz for r in sequential], rel=1e-8)
