"""Pictures: offscreen renders that show the mode, the feet and the electrodes; VTU export; plots."""

import numpy as np
import pytest

from modalfe.scene import load_scene
from modalfe.solve.api import solve_modes

pv = pytest.importorskip("pyvista")


@pytest.fixture(scope="module")
def plate():
    scene = load_scene("cube_plate", **{"mesh.elements_per_wavelength": 4.0})
    return solve_modes(scene, near=40e3, count=6, error_estimate=False)


def _image(modes, mode, **kwargs):
    from modalfe.plot.render import render_mode

    plotter = render_mode(mode, window_size=(500, 350), **kwargs)
    image = plotter.screenshot(return_img=True)
    plotter.close()
    return image.astype(float)


def _green(image):
    """Fraction of pixels that are the feet's green under any shading (green well above red and blue);
    the RdBu colour map has no such pixels."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return float(np.mean((g > r + 50) & (g > b + 50)))


def _gold(image):
    """Fraction of the electrodes' gold pixels (red and green high, blue low) under any shading."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return float(np.mean((r > 120) & (g > 100) & (b < 0.5 * g) & (r > b + 80)))


def test_render_is_not_blank_and_marks_feet_and_electrodes(plate):
    working = plate.labelled("(0,6)")
    top = _image(plate, working, view="iso")
    assert top.std() > 20  # a white background alone has std 0
    # electrodes (gold) cover ~60 % of the top face: clearly visible from above
    assert _gold(top) > 0.01
    bottom = _image(plate, working, view="bottom")
    # the four 3 x 3 mm feet (green) are visible from below, and less (or not) from above
    assert _green(bottom) > 1e-4
    assert _green(top) < _green(bottom)


def test_two_modes_give_different_pictures(plate):
    working = plate.labelled("(0,6)")
    other = next(m for m in plate if m.label != working.label)
    a = _image(plate, other)
    b = _image(plate, working)
    assert np.mean(np.abs(a - b)) > 5  # mean absolute difference per pixel channel, 0-255 scale


def test_animation_writes_a_gif(plate, tmp_path):
    from modalfe.plot.render import animate_mode

    path = animate_mode(plate.labelled("(0,6)"), str(tmp_path / "mode.gif"), frames=4,
                        window_size=(300, 200))
    with open(path, "rb") as f:
        assert f.read(6) in (b"GIF89a", b"GIF87a")


def test_vtu_export_has_every_mode_and_the_parts(plate, tmp_path):
    import meshio

    from modalfe.report.export import export_vtu

    path = export_vtu(plate, tmp_path / "plate.vtu")
    mesh = meshio.read(path)
    assert len(mesh.point_data) == len(plate)
    assert "part" in mesh.cell_data
    # the half model is unfolded: the whole 64 x 38 mm plate is there
    assert np.ptp(mesh.points[:, 1]) == pytest.approx(38e-3, rel=1e-9)
    grid = pv.read(path)
    assert np.all(grid.compute_cell_sizes()["Volume"] > 0)  # mirrored cells keep a positive volume


def test_plots_return_figures(tmp_path):
    from modalfe.plot.figures import plot_admittance, plot_convergence, plot_frf, plot_sweep, plot_time_vs_error

    f = np.linspace(39e3, 41e3, 11)
    response = 1 / (40e3**2 - f**2 + 1j * 40e3 * f / 100)
    figures = [plot_frf(f, {"a": response}), plot_admittance(f, 1j * f * response),
               plot_convergence([1e3, 1e4, 1e5], [1e-2, 1e-3, 1e-4], order=2),
               plot_time_vs_error({"solid": np.array([1.0, 5.0])}, {"solid": np.array([1e-2, 1e-3])}),
               plot_sweep({"x": np.arange(4), "y": np.arange(4) ** 2, "g": np.array([0, 0, 1, 1])}, "x", "y",
                          group="g")]
    for fig in figures:
        assert fig.axes and fig.axes[0].lines
        fig.savefig(tmp_path / "f.png")
