"""Curve plots (matplotlib): each returns a Figure and never shows it."""

from __future__ import annotations

import textwrap

import numpy as np


def _figure(rows: int = 1, **kwargs):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.subplots(rows, 1, figsize=(7, 3.2 * rows), **kwargs)


def _mark(axes, marks: dict[str, float], scale: float) -> None:
    """Dotted vertical lines at ``marks`` (name -> frequency [Hz], e.g. fr and fa), named at the top of the first
    axes."""
    for k, (name, f) in enumerate(marks.items()):
        for ax in axes:
            ax.axvline(f / scale, color="grey", linestyle=":", linewidth=0.9)
        # names a line apart, so that fr and fa a few Hz apart stay readable
        axes[0].annotate(name, (f / scale, 1.0), xycoords=("data", "axes fraction"), xytext=(2, -10 - 10 * (k % 2)),
                         textcoords="offset points", fontsize=8, color="dimgrey")


def plot_frf(frequency, responses: dict[str, np.ndarray], *, ylabel: str = "amplitude [m/V]", title: str = "",
             marks: dict[str, float] | None = None):
    """|response| vs frequency [Hz] for each named curve, log scale; ``marks``: name -> frequency [Hz] (fr) drawn
    as dotted lines."""
    fig, ax = _figure()
    f = np.asarray(frequency, dtype=float)
    scale, unit = (1e3, "kHz") if f.max() >= 2e3 else (1.0, "Hz")  # the tile's 47 Hz heave reads as Hz
    for name, r in responses.items():
        ax.semilogy(f / scale, np.abs(r), label=name)
    _mark([ax], marks or {}, scale)
    ax.set_xlabel(f"frequency [{unit}]")
    ax.set_ylabel(ylabel)
    ax.legend()
    ax.set_title(textwrap.fill(title, 70), fontsize=10)  # long titles wrap instead of running off the figure
    fig.tight_layout()
    return fig


def plot_admittance(frequency, admittance, *, title: str = "", impedance: bool = False,
                    others: dict[str, np.ndarray] | None = None, label: str = "", marks: dict[str, float] | None = None,
                    circuits=()):
    """|Y| [S] and phase [deg] vs frequency [Hz]; ``impedance`` adds |Z| [ohm] and plots the phase of Z;
    ``others``: more named admittance curves (a closed form, the direct FE) on the same axes; ``marks``: name ->
    frequency [Hz] (fr, fa) drawn as dotted lines; ``circuits``: BVD circuits (``Admittance.bvd_circuits``), each
    drawn dashed from fr - 3 (fa - fr) to fa + 3 (fa - fr) (where one resonance's circuit describes Y)."""
    from modalfe.response.admittance import bvd_admittance

    f_all = np.asarray(frequency, dtype=float)
    curves = {label or "Y": np.asarray(admittance)}
    curves.update({k: np.asarray(v) for k, v in (others or {}).items()})
    fig, axes = _figure(3 if impedance else 2, sharex=True)
    f = np.asarray(frequency) / 1e3
    for i, (name, Y) in enumerate(curves.items()):
        style = "-" if i == 0 else "--"
        axes[0].semilogy(f, np.abs(Y), style, label=name)
        if impedance:
            axes[1].semilogy(f, 1.0 / np.abs(Y), style, label=name)
        axes[-1].plot(f, np.degrees(np.angle(1.0 / Y if impedance else Y)), style, label=name)
    axes[0].set_ylabel("|Y| [S]")
    if impedance:
        axes[1].set_ylabel("|Z| [ohm]")
    axes[-1].set_ylabel(f"phase of {'Z' if impedance else 'Y'} [deg]")
    axes[-1].set_xlabel("frequency [kHz]")
    for k, c in enumerate(circuits):
        gap = c["fa_hz"] - c["fr_hz"]
        f = f_all[(f_all >= c["fr_hz"] - 3 * gap) & (f_all <= c["fa_hz"] + 3 * gap)]
        Y = bvd_admittance(c, f)
        name = "fitted BVD" if k == 0 else None
        axes[0].semilogy(f / 1e3, np.abs(Y), "k--", linewidth=0.9, label=name)
        if impedance:
            axes[1].semilogy(f / 1e3, 1.0 / np.abs(Y), "k--", linewidth=0.9)
        axes[-1].plot(f / 1e3, np.degrees(np.angle(1.0 / Y if impedance else Y)), "k--", linewidth=0.9)
    _mark(axes, marks or {}, 1e3)
    if len(curves) > 1 or circuits:
        axes[0].legend(fontsize=8)
    axes[0].set_title(title)
    fig.tight_layout()
    return fig


def plot_convergence(dofs, error, *, label: str = "", order: float | None = None):
    """Relative error vs DOFs, log-log, with an optional reference slope -order/3."""
    fig, ax = _figure()
    dofs, error = np.asarray(dofs, float), np.abs(np.asarray(error, float))
    ax.loglog(dofs, error, "o-", label=label or "error")
    if order is not None:
        ax.loglog(dofs, error[0] * (dofs / dofs[0]) ** (-order / 3), "k--", label=f"h^{order:g}")
    ax.set_xlabel("DOFs")
    ax.set_ylabel("relative error")
    ax.legend()
    fig.tight_layout()
    return fig


def plot_time_vs_error(seconds: dict[str, np.ndarray], error: dict[str, np.ndarray]):
    """Wall time [s] vs relative error, one curve per named model or fidelity."""
    fig, ax = _figure()
    for name in seconds:
        ax.loglog(np.abs(error[name]), seconds[name], "o-", label=name)
    ax.set_xlabel("relative error")
    ax.set_ylabel("time [s]")
    ax.legend()
    fig.tight_layout()
    return fig


def plot_sweep(table: dict[str, np.ndarray], x: str, y: str, *, group: str | None = None):
    """Column ``y`` against column ``x`` of a results table (dict of columns), one curve per ``group``."""
    fig, ax = _figure()
    xs, ys = np.asarray(table[x]), np.asarray(table[y])
    if group is None:
        ax.plot(xs, ys, "o-")
    else:
        keys = np.asarray(table[group])
        for value in np.unique(keys):
            sel = keys == value
            ax.plot(xs[sel], ys[sel], "o-", label=f"{group} = {value}")
        ax.legend()
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    fig.tight_layout()
    return fig


def write_forced_plots(fig, path: str, volts: float) -> list[str]:
    """FRF (reduced model, and full FE when computed) at ``path``, and for a voltage drive the admittance beside it
    (``<stem>_admittance.<ext>``), fr and fa marked on both (fa: the open-circuit mode's, else the reduced model's BVD;
    a force, pressure or acceleration drive's FRF: fr);
    returns the paths written."""
    curves = {"reduced model": volts * fig.frf}
    if fig.frf_full is not None:
        curves["full FE"] = volts * fig.frf_full
    title = f"{fig.scene}: {fig.rom.label}, {fig.rom.damping_description}"
    unit = fig.load_unit
    if unit != "V":  # per unit force, pressure or base acceleration: no circuit to plot
        title = f"{fig.scene}: {fig.rom.label} driven by a {fig.load_description}, {fig.rom.damping_description}"
        plot_frf(fig.frequency, {k: c / volts for k, c in curves.items()}, marks={"fr": fig.rom.frequency},
                 ylabel=f"amplitude at {fig.rom.reference} [m/{unit}]", title=title).savefig(path, dpi=110)
        return [path]
    fa = fig.antiresonance or fig.rom.antiresonance  # where the open circuit would put the resonance
    frf = plot_frf(fig.frequency, curves, ylabel=f"amplitude at {fig.rom.reference} [m] at {volts:g} V", title=title,
                   marks={"fr": fig.rom.frequency, "fa": fa})
    stem, dot, ext = path.rpartition(".")
    frf.savefig(path, dpi=110)
    admittance = f"{stem}_admittance.{ext}" if dot else f"{path}_admittance"
    plot_admittance(fig.frequency, fig.admittance, title=title, label="reduced model (the working mode's BVD)",
                    marks={"fr": fig.rom.frequency, "fa": fa}).savefig(admittance, dpi=110)
    return [path, admittance]
