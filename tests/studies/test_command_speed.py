"""studies/command_speed.py runs end to end and prints one ratio row per command that applies; no timing is asserted
beyond being positive (these machines are shared and noisy)."""

import pytest

from tests.helpers import load_study

STUDY = load_study("command_speed")


def test_an_admittance_needs_a_band_and_a_driven_electrode():
    assert STUDY.command_line("admittance", "honeycomb_tile", "/tmp") is None
    assert STUDY.command_line("forced", "honeycomb_tile", "/tmp") == ["forced", "honeycomb_tile"]
    assert STUDY.command_line("admittance", "ciliary_beam", "/tmp")[:4] == ["admittance", "ciliary_beam", "--band",
                                                                           "20500"]


@pytest.mark.slow
def test_command_speed_quick(capsys):
    assert STUDY.main(["--runs", "1", "--devices", "ciliary_beam", "--commands", "table"]) == 0
    _, row = capsys.readouterr().out.splitlines()
    device, command, *figures = row.split()
    assert (device, command) == ("ciliary_beam", "table") and all(float(x) > 0 for x in figures)
