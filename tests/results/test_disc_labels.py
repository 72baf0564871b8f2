"""Disc and ring mode labels (issue 20): nodal diameters and circles of flexural modes, in-plane ring and disc
modes, thickness modes, and "?" for fields that are no disc mode. Synthetic fields on scattered point clouds
(random points over the disc, several layers through the thickness), rotated to an arbitrary axis and noisy:
analytic Kirchhoff modes of clamped and free discs (Leissa, NASA SP-160, 1969, eqs. 2.7 and 2.12, roots from
tests.oracles.discs), in-plane modes of a thin ring (Hoppe 1871) and the free disc's radial modes (Onoe 1956)."""

from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.special import jv

from modalfe.geometry.parts import Box
from modalfe.results.labels import _describe, axial_frame, base_label, disc_label, unique_labels
from tests.oracles import discs

NOISE = 0.02  # Gaussian noise, 2 % of the field's peak per sample: a coarse mesh's interpolation error
NU = 0.33  # Poisson ratio of Leissa's Table 2.5
ROTATION = Rotation.from_euler("xyz", [0.4, -0.9, 1.3]).as_matrix()  # an axis along no coordinate axis
CENTRE = np.array([0.02, -0.01, 0.005])


def _cloud(count: int = 1500, *, inner: float = 0.0, layers: int = 3, thickness: float = 0.05,
           seed: int = 0) -> np.ndarray:
    """Points (3, n) of a unit-radius disc (annulus from ``inner``), axis z, mid-plane z = 0: ``count`` random points
    uniform over the area and 120 on each edge circle, repeated on ``layers`` planes through the thickness."""
    rng = np.random.default_rng(seed)
    r = np.sqrt(rng.uniform(inner**2, 1.0, count))
    theta = rng.uniform(-np.pi, np.pi, count)
    edge = np.linspace(-np.pi, np.pi, 120, endpoint=False)
    radii = [1.0] + ([inner] if inner > 0 else [])
    r = np.concatenate([r, *[np.full(len(edge), a) for a in radii]])
    theta = np.concatenate([theta, *[edge for _ in radii]])
    z = np.linspace(-thickness / 2, thickness / 2, layers) if layers > 1 else np.zeros(1)
    return np.vstack([np.tile(r * np.cos(theta), len(z)), np.tile(r * np.sin(theta), len(z)),
                      np.repeat(z, len(r))])


def _flexural(points: np.ndarray, profile, n: int, theta0: float = 0.3) -> np.ndarray:
    """Kirchhoff field of w = W(r) cos(n (theta - theta0)): u = (-z dw/dx, -z dw/dy, w)."""

    def w(x, y):
        return profile(np.minimum(np.hypot(x, y), 1.0)) * np.cos(n * (np.arctan2(y, x) - theta0))

    x, y, z = points
    d = 1e-6
    return np.vstack([-z * (w(x + d, y) - w(x - d, y)) / (2 * d), -z * (w(x, y + d) - w(x, y - d)) / (2 * d), w(x, y)])


def _in_plane(points: np.ndarray, u_r, u_theta) -> np.ndarray:
    """Membrane field from polar components (functions of r, theta)."""
    x, y, _ = points
    r, theta = np.hypot(x, y), np.arctan2(y, x)
    ur, ut = u_r(r, theta), u_theta(r, theta)
    return np.vstack([ur * np.cos(theta) - ut * np.sin(theta), ur * np.sin(theta) + ut * np.cos(theta),
                      np.zeros_like(r)])


def _read(points: np.ndarray, u: np.ndarray, *, noise: float = NOISE, seed: int = 1) -> str:
    """The label of ``u`` at ``points`` after rotating both to the tilted axis, moving them to CENTRE and adding
    ``noise`` (fraction of the peak) to every component."""
    rng = np.random.default_rng(seed)
    u = u + noise * np.abs(u).max() * rng.standard_normal(u.shape)
    return disc_label(ROTATION @ points + CENTRE[:, None], ROTATION @ u, axis=ROTATION[:, 2], centre=CENTRE)


@pytest.mark.parametrize(("n", "s"), [(0, 0), (1, 0), (2, 0), (3, 0), (0, 1), (1, 1), (2, 1), (0, 2)])
def test_clamped_disc_modes(n, s):
    # Leissa eq. 2.7: s nodal circles inside the clamped edge (the edge itself is not counted)
    lam = discs.clamped_disc_roots(n, s + 1)[s]
    points = _cloud()
    assert _read(points, _flexural(points, discs.clamped_disc_shape(n, lam), n)) == f"({n},{s})"


@pytest.mark.parametrize(("n", "s"), [(2, 0), (0, 1), (3, 0), (1, 1), (4, 0), (2, 1), (0, 2), (5, 0)])
def test_free_disc_modes(n, s):
    # Leissa eq. 2.12 (Table 2.5 order of the frequencies: (2,0), (0,1), (3,0), (1,1), (4,0), ...)
    lam = discs.free_disc_roots(n, 3, NU)[s - (n < 2)]  # n = 0, 1: s = 0 is a rigid motion, not a root
    points = _cloud()
    assert _read(points, _flexural(points, discs.free_disc_shape(n, lam, NU), n)) == f"({n},{s})"


def test_a_mid_surface_sample_and_a_coarse_cloud_give_the_same_labels():
    # one layer (a shell's mid-surface, no mirror partners) and 300 points: 12 per ring of r, enough for n <= 3
    lam = discs.free_disc_roots(2, 2, NU)[1]
    for points in (_cloud(layers=1), _cloud(300, seed=3)):
        assert _read(points, _flexural(points, discs.free_disc_shape(2, lam, NU), 2)) == "(2,1)"


def test_ring_in_plane_modes():
    # thin ring (inner radius 0.9): inextensional bending u_r = cos(n theta), u_theta = -sin(n theta) / n
    # (Hoppe 1871), and the breathing mode u_r = 1
    points = _cloud(inner=0.9)
    for n in (2, 3, 4):
        u = _in_plane(points, lambda r, t, n=n: np.cos(n * t), lambda r, t, n=n: -np.sin(n * t) / n)
        assert _read(points, u) == f"n={n}"
    assert _read(points, _in_plane(points, lambda r, t: np.ones_like(r), lambda r, t: 0 * r)) == "R1"


def test_disc_radial_and_torsional_modes():
    # free disc: radial u_r = J1(x r), x J0(x) = (1 - nu) J1(x) (Onoe 1956): R1 has no interior nodal circle of
    # u_r, R2 one; torsional u_theta = J1(k r) with J2(k) = 0 (k = 5.1356, zero edge shear): one nodal circle, T2
    # (T1 is the rigid rotation)
    points = _cloud()
    x1, x2 = discs.disc_radial_roots(0.3, 2)
    for x, name in ((x1, "R1"), (x2, "R2")):
        assert _read(points, _in_plane(points, lambda r, t, x=x: jv(1, x * r), lambda r, t: 0 * r)) == name
    assert _read(points, _in_plane(points, lambda r, t: 0 * r, lambda r, t: jv(1, 5.1356 * r))) == "T2"
    # in-plane n = 2 of a disc with one radial sign change of u_r: second radial order
    u = _in_plane(points, lambda r, t: r**2 * (1 - 2 * r**2) * np.cos(2 * t), lambda r, t: 0.3 * r**2 * np.sin(2 * t))
    assert _read(points, u) == "n=2 k=2"


def test_a_thick_cylinders_twist_odd_through_the_thickness_is_torsional():
    # the first elastic torsion mode of a free cylinder, u_theta = r sin(pi z / h) (ends twisting against each other,
    # f = sqrt(c44 / rho) / 2h): odd through the thickness like a bending mode, but with no motion along the axis;
    # before, the flexural branch read the harmonics of its (noise) u_z: "(3,0)" on a D/t = 2 PZT-4 disc
    points = _cloud(layers=5, thickness=1.0)
    u = _in_plane(points, lambda r, t: 0 * r, lambda r, t: r * np.sin(np.pi * points[2]))
    assert _read(points, u) == "T1"
    # a bending mode of the same thick cloud keeps its flexural label: u_z carries most of its motion
    lam = discs.clamped_disc_roots(2, 1)[0]
    assert _read(points, _flexural(points, discs.clamped_disc_shape(2, lam), 2)) == "(2,0)"


def test_thickness_mode():
    # u along the axis odd through the thickness and uniform over the disc (thickness-extensional), with a 20 %
    # radial Poisson motion
    points = _cloud(layers=5)
    x, y, z = points
    u = np.vstack([0.2 * x, 0.2 * y, np.sin(np.pi * z / 0.05)])
    assert _read(points, u) == "thickness"


def test_fields_that_are_no_disc_mode_get_a_question_mark():
    points = _cloud()
    lam2, lam3 = discs.free_disc_roots(2, 1, NU)[0], discs.free_disc_roots(3, 1, NU)[0]
    mixed = (_flexural(points, discs.free_disc_shape(2, lam2, NU), 2)
             + _flexural(points, discs.free_disc_shape(3, lam3, NU), 3))
    assert _read(points, mixed) == "?"  # two harmonics of equal energy: 50 % each, below the 70 % of a mode
    x, y, _ = points
    bump = np.exp(-((x - 0.6) ** 2 + y**2) / 0.02)  # a local mode under a mass off the centre
    assert _read(points, np.vstack([0 * x, 0 * x, bump])) == "?"


@dataclass(frozen=True)
class _Disc(Box):
    """A box standing in for the cylinder part of issue 20: it exposes ``axis`` and ``centre``."""

    axis: str = "z"
    centre: tuple = (0.0, 0.0, 0.0)


@dataclass
class _Scene:
    main: Box
    clamps: dict = field(default_factory=lambda: {"edge": "xyz"})
    kind: str = "plate"

    def assembly(self):
        return SimpleNamespace(main_part=self.main)


class _DiscModel:
    """A stand-in model whose DOF vector is the flexural field itself at a disc's points."""

    def __init__(self, scene) -> None:
        self.scene, self.points = scene, _cloud()

    def label_field(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.points, x.reshape(3, -1)


def test_axial_frame_only_for_parts_with_an_axis():
    box = Box("plate", "plate", "steel", (0, 0, 0), (1, 1, 0.1))
    assert axial_frame(_Scene(box)) is None
    assert axial_frame(SimpleNamespace(clamps={}, kind="plate")) is None  # no assembly at all
    axis, centre = axial_frame(_Scene(_Disc("disc", "disc", "steel", (-1, -1, 0), (1, 1, 0.1), centre=(0, 0, 0.05))))
    assert np.allclose(axis, [0, 0, 1]) and np.allclose(centre, [0, 0, 0.05])


def test_a_degenerate_pair_gets_one_label_and_the_repeat_suffix():
    # the cos / sin 2 theta pair of a clamped disc, mixed by an arbitrary rotation of the span (as an eigen solver
    # returns it), then a clean (0,1): labels by the hook of unique_labels, the pair's second member "#2"
    model = _DiscModel(_Scene(_Disc("disc", "disc", "steel", (-1, -1, -0.025), (1, 1, 0.025))))
    lam = discs.clamped_disc_roots(2, 1)[0]
    shape = discs.clamped_disc_shape(2, lam)
    a, b = (_flexural(model.points, shape, 2, theta0) for theta0 in (0.0, np.pi / 4))
    c, s = np.cos(0.5), np.sin(0.5)
    circle = _flexural(model.points, discs.clamped_disc_shape(0, discs.clamped_disc_roots(0, 2)[1]), 0)
    shapes = np.column_stack([(c * a + s * b).ravel(), (-s * a + c * b).ravel(), circle.ravel()])
    names = [name for name, _ in unique_labels(model, shapes, [100.0, 100.0, 150.0])]
    assert sorted(names[:2]) == ["(2,0)", "(2,0)#2"] and names[2] == "(0,1)"  # the clearer one keeps it plain


def test_close_modes_of_a_model_solving_pair_members_apart_are_labelled_each_as_it_is(monkeypatch):
    # an axisymmetric model's modes each lie in one harmonic (``pairs_apart``): a (2,0) and a (0,1) within the 0.1 %
    # of a degenerate pair keep their own labels, each described once (a 3-D model's pair would be turned through
    # 36 angles, two descriptions each)
    import modalfe.results.labels as labels

    model = _DiscModel(_Scene(_Disc("disc", "disc", "steel", (-1, -1, -0.025), (1, 1, 0.025))))
    model.pairs_apart = True
    pair = _flexural(model.points, discs.clamped_disc_shape(2, discs.clamped_disc_roots(2, 1)[0]), 2, 0.0)
    circle = _flexural(model.points, discs.clamped_disc_shape(0, discs.clamped_disc_roots(0, 2)[1]), 0)
    described = []
    monkeypatch.setattr(labels, "_describe", lambda *a, **k: described.append(1) or _describe(*a, **k))
    names = [name for name, _ in unique_labels(model, np.column_stack([pair.ravel(), circle.ravel()]), [100.0, 100.05])]
    assert names == ["(2,0)", "(0,1)"] and len(described) == 2


@pytest.mark.slow
def test_fe_modes_of_a_free_steel_disc_get_leissa_labels(tmp_path):
    # a free steel disc, radius 10 mm, 0.4 mm thick (h/a = 0.04), meshed from a .geo cylinder by read_geometry with
    # curved 10-node tetrahedra and solved with scikit-fem's 3-D elasticity (~24k DOFs, ~40 s): every elastic mode
    # up to (0,2) gets Leissa's label at its Kirchhoff frequency (eq. 2.14, nu = 0.3). The 3 % band identifies
    # each mode: Kirchhoff theory leaves out shear and rotary inertia, which lower the 3-D frequencies by < 1 % at
    # h/a = 0.04 and these orders (Mindlin 1951), and the one-layer P2 mesh adds ~1 %; neighbouring disc modes
    # differ by > 5 %
    import scipy.sparse.linalg as sla
    from skfem import Basis, BilinearForm, ElementTetP2, ElementVector, asm
    from skfem.helpers import dot
    from skfem.io.meshio import from_meshio
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    from modalfe.geometry.imported import read_geometry

    radius, h, E, nu, rho = 0.01, 0.0004, 200e9, 0.3, 7800.0
    script = tmp_path / "disc.geo"
    script.write_text(f'SetFactory("OpenCASCADE");\nCylinder(1) = {{0, 0, 0, 0, 0, {h}, {radius}}};\n'
                      'Physical Volume("disc") = {1};\n')
    mesh = from_meshio(read_geometry(script, volumes={"disc": {}}, faces=(), size=2 * h, order=2))
    basis = Basis(mesh, ElementVector(ElementTetP2()))
    K = asm(linear_elasticity(*lame_parameters(E, nu)), basis)
    M = asm(BilinearForm(lambda u, v, w: rho * dot(u, v)), basis)
    omega2, X = sla.eigsh(K, k=20, M=M, sigma=-((2 * np.pi * 100) ** 2))  # below the 6 rigid-body modes
    frequencies = np.sqrt(np.abs(omega2)) / (2 * np.pi)
    vertices = np.unique(mesh.t)

    class Model:
        scene = _Scene(_Disc("disc", "disc", "steel", (-radius, -radius, 0), (radius, radius, h),
                             centre=(0, 0, h / 2)), clamps={})

        def label_field(self, x):
            return mesh.p[:, vertices], x[basis.nodal_dofs[:, vertices]]

    names = [name for name, _ in unique_labels(Model(), X[:, 6:], frequencies[6:])]
    expected = ["(2,0)", "(2,0)", "(0,1)", "(3,0)", "(3,0)", "(1,1)", "(1,1)", "(4,0)", "(4,0)", "(5,0)", "(5,0)",
                "(2,1)", "(2,1)", "(0,2)"]
    assert [name.split("#")[0] for name in names] == expected
    assert sum("#2" in name for name in names) == 6  # one of each degenerate pair
    for name, f in zip(names, frequencies[6:]):
        n, s = (int(c) for c in name.split("#")[0].strip("()").split(","))
        lam = discs.free_disc_roots(n, 3, nu)[s - (n < 2)]
        kirchhoff = discs.kirchhoff_disc_frequency(lam, radius=radius, h=h, E=E, nu=nu, rho=rho)
        assert f == pytest.approx(kirchhoff, rel=0.03)


@pytest.mark.parametrize("element", ["hex", "tet"])  # swept hexahedra (the default) and curved tetrahedra
def test_a_free_disc_scene_is_labelled_through_the_solve(element):
    # the whole path: a cylinder part in a scene, solve_modes, Model.label_field, axial_frame of the real Scene and
    # unique_labels: a free thin steel disc's first elastic modes are Leissa's (2,0) pair (Leissa 1969, Table 2.5),
    # labelled (2,0) and (2,0)#2
    from modalfe.scene import scene_from_dict
    from modalfe.solve.api import solve_modes

    scene = scene_from_dict({
        "units": "mm", "name": "free-disc", "analysis": {"near": 3000.0, "count": 8},
        "materials": {"steel": {"E": 200e9, "nu": 0.3, "rho": 7850.0}},
        "mesh": {"max_size": 3, "min_layers": 1, "element": element},
        "parts": [{"name": "disc", "shape": "cylinder", "material": "steel", "centre": [0, 0, 0], "axis": "z",
                   "radius": 10, "height": 1}]})
    modes = solve_modes(scene, error_estimate=False)
    elastic = [m for m in modes if m.frequency > 100.0]
    assert sorted(m.label for m in elastic[:2]) == ["(2,0)", "(2,0)#2"]  # the plain label goes to the clearer
    # and they are that mode: Kirchhoff's frequency within 5 % (h / a = 0.1: shear and rotary inertia lower a
    # thick disc's (2,0) by ~(h/a)^2 ~ 1-3 %, and one coarse P2 layer stiffens it by about as much)
    lam = discs.free_disc_roots(2, 1, 0.3)[0]
    kirchhoff = discs.kirchhoff_disc_frequency(lam, radius=0.01, h=0.001, E=200e9, nu=0.3, rho=7850.0)
    assert elastic[0].frequency == pytest.approx(kirchhoff, rel=0.05)


@pytest.mark.parametrize("shape, inner, outer, height, axis, near, expected", [
    # a thick ring: out-of-plane (2,0) and (3,0) pairs and the in-plane n=2 pair between them
    ("ring", 15, 20, 3, "z", 5e3, ["(2,0)", "(2,0)#2", "n=2", "n=2#2", "(3,0)", "(3,0)#2"]),
    # a tube on the x axis, as long as its diameter: ovalling n=2, n=3 (in-plane, even along the axis) and the
    # same waves odd along the axis, (2,0) and (3,0) in the disc reading (the module docstring)
    ("tube", 9, 10, 12, "x", 8e3, ["n=2", "n=2#2", "(2,0)", "(2,0)#2", "n=3", "n=3#2", "(3,0)", "(3,0)#2"]),
])
def test_rings_and_tubes_get_labels_through_the_solve(shape, inner, outer, height, axis, near, expected):
    # issue 35: a body of revolution with a hole labelled every elastic mode "?": between its walls only the end
    # faces' few vertices sample the angle, so a ring of r resolved no harmonic and its energy counted against all
    from modalfe.scene import scene_from_dict
    from modalfe.solve.api import solve_modes

    scene = scene_from_dict({
        "units": "mm", "name": shape, "analysis": {"near": near, "count": 6 + len(expected)},
        "materials": {"steel": {"E": 200e9, "nu": 0.3, "rho": 7850.0}}, "mesh": {"max_size": 3, "min_layers": 1},
        "parts": [{"name": shape, "shape": "ring", "material": "steel", "centre": [0, 0, 0], "axis": axis,
                   "inner": inner, "outer": outer, "height": height}]})
    modes = solve_modes(scene, error_estimate=False)
    # the first elastic modes: the six rigid-body modes share one eigenvalue (0), of which a single-vector Lanczos
    # finds as many copies as rounding gives it, and a farther elastic mode takes a missing copy's place
    elastic = [m.label for m in modes if m.frequency > 100.0][:len(expected)]
    # each pattern in order of frequency; within a degenerate pair the plain label goes to the clearer shape
    assert [base_label(name) for name in elastic] == [base_label(name) for name in expected]
    assert sorted(elastic) == sorted(expected)
