"""Figures of the contact simulators.  Each function returns a matplotlib Figure and never shows it;
matplotlib is imported inside the functions."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from modalfe.contact.chain import HapticMap
from modalfe.contact.finger import EqualFriction, FingerCurve
from modalfe.contact.foot import ContactCurve, ContactOrbit
from modalfe.contact.texture import TextureRendering

CONTOUR_POINTS = 20  # a map of fewer points (a device's feet) is drawn point by point, not contoured


def _figure(rows: int = 1, cols: int = 1, size: tuple[float, float] = (6.4, 4.2)):
    from matplotlib.figure import Figure

    fig = Figure(figsize=size, layout="constrained")
    return fig, fig.subplots(rows, cols, squeeze=False)


def friction_figure(curves: ContactCurve | Sequence[ContactCurve]):
    """Friction force and flight ratio against amplitude (seed 000 Figs 13, 15; seed 001 Figs 9, 10)."""
    curves = [curves] if isinstance(curves, ContactCurve) else list(curves)
    fig, ax = _figure(1, 2, (10, 4))
    for c in curves:
        label = f"Fn = {c.preload:g} N, V = {100 * c.speed:g} cm/s, mu0 = {c.parameters.mu0:g}"
        ax[0, 0].plot(c.amplitude * 1e6, c.friction_force, label=label)
        ax[0, 1].plot(c.amplitude * 1e6, c.flight_ratio, label=label)
    ax[0, 0].set(xlabel="amplitude W [um, 0-peak]", ylabel="friction force n <Rt> [N]", ylim=(0, None))
    ax[0, 1].set(xlabel="amplitude W [um, 0-peak]", ylabel="flight ratio beta [%]", ylim=(0, 100))
    ax[0, 0].legend(fontsize="small")
    return fig


def orbit_figure(orbit: ContactOrbit, periods: float = 2.0, samples: int = 400):
    """Normal and tangential force of one foot over a few periods of the steady state (seed 000 Fig. 12)."""
    T = orbit.parameters.period
    t = orbit.t_start + np.linspace(0, periods * T, samples)
    fig, ax = _figure(2, 1, (7, 5))
    ax[0, 0].plot((t - t[0]) * 1e6, orbit.normal_force(t))
    ax[0, 0].set(ylabel="Rn [N]", title=f"W = {orbit.amplitude * 1e6:.2f} um, Fn = {orbit.preload:g} N, "
                                         f"beta = {orbit.flight_ratio:.1f} %")
    ax[1, 0].plot((t - t[0]) * 1e6, orbit.friction(t))
    ax[1, 0].set(xlabel="time from a touchdown [us]", ylabel="Rt [N]")
    return fig


def finger_figure(curves: Sequence[FingerCurve], equal: EqualFriction | None = None):
    """mu_US / mu against peak-to-peak amplitude per frequency (seed 004 Fig. 6) and, if given, the
    amplitudes of equal friction (Fig. 7) with the equal-velocity and equal-acceleration lines."""
    fig, ax = _figure(1, 2 if equal is not None else 1, (10, 4) if equal is not None else (6.4, 4.2))
    for c in curves:
        x = c.amplitude_pp * 1e6
        line = ax[0, 0].errorbar(x, c.friction_ratio, yerr=c.uncertainty, fmt=".-", capsize=2,
                                 label=f"{c.frequency / 1e3:g} kHz")
        sub = c.periodic & (c.periods > 1)  # periodic orbits of period k T > T, marked and labelled
        if sub.any():
            ax[0, 0].plot(x[sub], c.friction_ratio[sub], "s", mfc="none", color=line[0].get_color())
            for xi, ri, k in zip(x[sub], c.friction_ratio[sub], c.periods[sub]):
                ax[0, 0].annotate(f"{k}T", (xi, ri), textcoords="offset points", xytext=(3, 3), fontsize="x-small")
    ax[0, 0].set(xscale="log", xlabel="amplitude [um, peak-to-peak]", ylabel="mu_US / mu",
                 title="error bars: standard error of time averages (0 on periodic orbits)")
    ax[0, 0].legend()
    if equal is not None:
        a = ax[0, 1]
        lo = equal.amplitude_low * 1e6
        xe, ye = equal.amplitude_low_uncertainty, equal.amplitude_high_uncertainty
        a.errorbar(lo, equal.amplitude_high * 1e6, xerr=None if xe is None else xe * 1e6,
                   yerr=None if ye is None else ye * 1e6, fmt="o-", capsize=2, label="model (equal friction)")
        x = np.array([0, lo.max()])
        a.plot(x, equal.velocity_ratio * x, "--", label=f"equal velocity ({equal.velocity_ratio:.2f})")
        a.plot(x, equal.acceleration_ratio * x, ":", label=f"equal acceleration ({equal.acceleration_ratio:.3f})")
        lf, hf = (f / 1e3 for f in equal.frequencies)
        a.set(xlabel=f"amplitude at {lf:g} kHz [um pp]", ylabel=f"amplitude at {hf:g} kHz [um pp]")
        a.legend(fontsize="small")
    return fig


def texture_figure(rendering: TextureRendering):
    """Amplitude (commanded and reached) and friction against position along the track (seed 001 Figs 12-14)."""
    r = rendering
    fig, ax = _figure(2, 1, (8, 5))
    x = r.position * 1e3
    ax[0, 0].plot(x, r.reference * 1e6, label="reference")
    ax[0, 0].plot(x, r.amplitude * 1e6, label=f"reached (tau = {r.response_time * 1e3:g} ms)")
    ax[0, 0].set(ylabel="amplitude [um]", title=f"{r.control} control, period {r.texture.period * 1e3:g} mm, "
                                                 f"V = {r.speed * 100:g} cm/s ({r.modulation_frequency:.1f} Hz)")
    ax[0, 0].legend(fontsize="small")
    ax[1, 0].plot(x, r.friction_force)
    ax[1, 0].set(xlabel="position along the track [mm]", ylabel="friction force [N]")
    return fig


def haptic_map_figure(hmap: HapticMap, outline: Sequence[tuple[str, tuple[float, float], tuple[float, float]]] = (),
                      *, required: float | None = None, title: str = ""):
    """Friction reduction over the touched points in the x-y plane (mm), over the device's ``outline``: (name,
    (x0, y0), (x1, y1)) rectangles [m] of its parts; ``required``: the contour where the reduction reaches it."""
    from matplotlib.patches import Rectangle

    fig, ax = _figure(1, 1, (8, 4.2))
    a = ax[0, 0]
    for name, lo, hi in outline:
        a.add_patch(Rectangle((1e3 * lo[0], 1e3 * lo[1]), 1e3 * (hi[0] - lo[0]), 1e3 * (hi[1] - lo[1]), fill=False,
                              lw=0.8, color="0.3", zorder=3))
        a.annotate(name, (1e3 * lo[0], 1e3 * hi[1]), fontsize="x-small", color="0.3", va="bottom")
    x, y, r = 1e3 * hmap.points[:, 0], 1e3 * hmap.points[:, 1], 100 * hmap.reduction
    if len(r) >= CONTOUR_POINTS and np.ptp(x) > 0 and np.ptp(y) > 0:
        art = a.tricontourf(x, y, r, levels=20, cmap="viridis")
        if required is not None and r.min() < 100 * required < r.max():
            a.tricontour(x, y, r, levels=[100 * required], colors="w", linewidths=1.2)
    else:
        middle = (r.max() + r.min()) / 2  # equal feet differ by rounding: a colour scale of at least 1 % point
        half = max(np.ptp(r) / 2, 0.5)
        art = a.scatter(x, y, c=r, s=160, cmap="viridis", edgecolors="k", zorder=4, vmin=middle - half,
                        vmax=middle + half)
        for xi, yi, ri in zip(x, y, r):
            a.annotate(f"{ri:.1f} %", (xi, yi), textcoords="offset points", xytext=(10, -14), fontsize="small")
    fig.colorbar(art, ax=a, label="friction reduction [%]")
    a.set(xlabel="x [mm]", ylabel="y [mm]", aspect="equal",
          title=title or f"{hmap.voltage:g} V, {hmap.frequency / 1e3:.1f} kHz")
    return fig
