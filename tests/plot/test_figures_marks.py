"""The forced-response plots (``modalfe forced --plot``, the design page) mark fr and fa on the FRF of a voltage drive
and on its admittance (issue 37: "Admittance and FRF plots mark fr and fa")."""

from __future__ import annotations

import modalfe.plot.figures as figures
from modalfe.response.figures import forced_figures
from modalfe.scene import load_scene


class _Drawn:
    def __init__(self, marks):
        self.marks = marks

    def savefig(self, *_args, **_kwargs) -> None:
        pass


def test_the_frf_and_the_admittance_of_a_voltage_drive_mark_fr_and_fa(monkeypatch, tmp_path):
    drawn = []

    def record(*_args, marks=None, **_kwargs):
        drawn.append(marks)
        return _Drawn(marks)

    monkeypatch.setattr(figures, "plot_frf", record)
    monkeypatch.setattr(figures, "plot_admittance", record)
    fig = forced_figures(load_scene("ciliary_beam"), error_estimate=False)
    figures.write_forced_plots(fig, str(tmp_path / "f.png"), 1.0)
    fa = fig.antiresonance or fig.rom.antiresonance
    assert fa > fig.rom.frequency  # the open circuit stiffens the mode
    assert drawn == [{"fr": fig.rom.frequency, "fa": fa}] * 2
