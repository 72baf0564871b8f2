"""Laws every curved device obeys (issue 35, curved parts): its mesh and spectrum do not depend on the axis it stands
on, on the way its outline is listed, or on the process (hash seed, the user's gmsh option files) that meshed it."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from modalfe.geometry.shapes import Extrusion
from modalfe.models.mesh import element_sizes
from modalfe.results.labels import RIGID_FRACTION
from modalfe.scene.loading import scene_from_dict
from modalfe.solve.api import solve_modes

ROOT = Path(__file__).resolve().parents[2]


def _disc(axis: str, radius: float, height: float, material: str, near: float = 1.0) -> dict:
    part = {"name": "disc", "shape": "cylinder", "material": material, "centre": [0, 0, 0], "axis": axis,
            "radius": radius, "height": height}
    scene = {"units": "mm", "parts": [part], "analysis": {"near": near, "count": 10}}
    if material.startswith("PZT"):  # poled through its thickness, electrodes on its faces
        part["poling"] = f"+{axis}"
        scene |= {"faces": {"top": ["disc.top"], "bottom": ["disc.bottom"]},
                  "electrodes": {"top": "drive", "bottom": "ground"}}
    return scene


@settings(max_examples=4, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(radius=st.floats(6.0, 12.0), height=st.floats(0.6, 2.0), axis=st.sampled_from("xy"),
       material=st.sampled_from(["CuBe", "PZT-5A"]))
def test_a_free_disc_on_any_axis_gets_the_z_discs_mesh_and_spectrum(radius, height, axis, material):
    # issue 35: the mesh size read the thickness along z, so the same disc on axis x got 2,368 DOFs instead of
    # 10,008 and its modes 3.4 % off. The element sizes follow the device's thickness axis: the x and y discs' meshes
    # are the z disc's with its coordinates permuted, so DOFs agree exactly and frequencies to the eigen solver's
    # round-off (1e-6 covers ARPACK's tolerance on a permuted matrix; the discretization error itself is ~1e-3).
    # The band: the first elastic modes and up, the mesh sized for 3x the (2,0) mode
    near = 3 * _first_flexural(scene_from_dict(_disc("z", radius, height, material)))
    upright = scene_from_dict(_disc("z", radius, height, material, near))
    lying = scene_from_dict(_disc(axis, radius, height, material, near))
    assert element_sizes(lying) == element_sizes(upright)
    a = solve_modes(upright, near=near / 3, count=10, error_estimate=False)
    b = solve_modes(lying, near=near / 3, count=10, error_estimate=False)
    assert a.dofs == b.dofs
    fa, fb = a.frequencies[_elastic(a)], b.frequencies[_elastic(b)]
    n = min(len(fa), len(fb))  # a band of 10 modes may hold one rigid-body mode more or less (their round-off)
    assert n >= 3 and np.allclose(fb[:n], fa[:n], rtol=1e-6)


def _elastic(modes) -> np.ndarray:
    """Which modes are elastic: the rigid-body modes (~0 Hz) are either solve's round-off."""
    f2 = modes.frequencies**2
    return f2 > RIGID_FRACTION * f2.max()


def _first_flexural(scene) -> float:
    """Free thin disc's (2,0) mode [Hz], Leissa (NASA SP-160, 1969, table 2.2: lambda^2 = 5.25 at nu = 0.3), to
    centre the band on the first elastic modes."""
    part = scene.assembly().main_part
    material = scene.material(part.material)
    C = material.C
    E_plate = C[0, 0] - C[0, 2] ** 2 / C[2, 2]  # the plane-stress modulus E / (1 - nu^2) of the mesh's own sizing
    D = E_plate * part.height**3 / 12
    return float(5.25 / (2 * np.pi * part.radius**2) * np.sqrt(D / (material.rho * part.height)))


@st.composite
def _star_polygons(draw):
    """A simple polygon: n vertices round a centre, each at its own radius [m] and within a sector of its own."""
    n = draw(st.integers(3, 9))
    radii = draw(st.lists(st.floats(0.004, 0.02), min_size=n, max_size=n))
    jitter = draw(st.lists(st.floats(-0.4, 0.4), min_size=n, max_size=n))
    angles = 2 * np.pi * (np.arange(n) + np.array(jitter)) / n
    return [(float(r * np.cos(t)), float(r * np.sin(t))) for r, t in zip(radii, angles)]


@settings(max_examples=200, deadline=None)
@given(outline=_star_polygons(), start=st.integers(0, 8), backwards=st.booleans())
def test_an_outline_listed_from_any_vertex_either_way_round_is_the_same_part(outline, start, backwards):
    # the part (and so the mesh's cache key and the gmsh input) is one listing per polygon
    listed = outline[start % len(outline):] + outline[: start % len(outline)]
    listed = listed[::-1] if backwards else listed
    reference = Extrusion("p", "p", "steel", tuple(outline), "z", 0.0, 0.001)
    assert Extrusion("p", "p", "steel", tuple(listed), "z", 0.0, 0.001) == reference


L_SHAPE = [[0, 0], [30, 0], [30, 12], [14, 12], [14, 25], [0, 25]]


def _l_plate(outline) -> dict:
    part = {"name": "plate", "shape": "extrusion", "material": "CuBe", "outline": outline, "axis": "z", "base": 0,
            "height": 1}
    return {"units": "mm", "parts": [part], "analysis": {"near": 100.0, "count": 9}}


def test_an_outline_listed_backwards_meshes_and_labels_as_listed_forwards():
    # issue 35: the L-shaped plate listed clockwise got 927 DOFs instead of 747 and other labels
    forwards = solve_modes(scene_from_dict(_l_plate(L_SHAPE)), near=100.0, count=9, error_estimate=False)
    backwards = solve_modes(scene_from_dict(_l_plate(L_SHAPE[::-1])), near=100.0, count=9, error_estimate=False)
    assert forwards.dofs == backwards.dofs
    elastic = _elastic(forwards)
    assert np.allclose(backwards.frequencies[elastic], forwards.frequencies[elastic], rtol=1e-6)
    assert [m.label for m, e in zip(backwards, elastic) if e] == [m.label for m, e in zip(forwards, elastic) if e]


# a 30 x 30 x 1 mm Cu-Be plate with a PZT-5A disc (radius 6 mm, 0.5 mm) on it, meshed by a fresh process
_MESH_DIGEST = """
import hashlib
from modalfe.models.mesh import build_mesh, element_sizes
from modalfe.scene.loading import scene_from_dict
scene = scene_from_dict({"units": "mm", "mesh": {"max_size": 6, "min_layers": 1}, "parts": [
    {"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [30, 30, 1]},
    {"name": "disc", "shape": "cylinder", "material": "PZT-5A", "centre": [15, 15, 1], "axis": "z", "radius": 6,
     "height": 0.5, "poling": "+z"}], "analysis": {"near": 20000.0, "count": 2}})
mesh = build_mesh(scene.assembly(), size=element_sizes(scene), element="hex", use_cache=False).mesh
print(hashlib.sha256(mesh.p.tobytes() + mesh.t.tobytes()).hexdigest())
"""


def _digest_in_fresh_process(tmp_path: Path, seed: str, home: Path) -> str:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONHASHSEED": seed, "HOME": str(home),
           "MODALFE_CACHE": str(tmp_path / "cache")}
    done = subprocess.run([sys.executable, "-c", _MESH_DIGEST], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.strip().splitlines()[-1]


def test_a_plate_with_a_disc_meshes_the_same_in_any_process(tmp_path):
    # issue 35: the plate with a disc meshed to different DOFs from fresh caches, and the cache kept whichever came
    # first. gmsh read the user's option files (~/.gmsh-options: here a size factor, as gmsh's GUI saves one), which
    # no cache key holds: two processes sharing a cache disagreed. Different hash seeds and homes, one mesh
    plain, configured = tmp_path / "plain", tmp_path / "configured"
    plain.mkdir()
    configured.mkdir()
    (configured / ".gmsh-options").write_text("Mesh.MeshSizeFactor = 0.5;\n")
    assert _digest_in_fresh_process(tmp_path, "1", plain) == _digest_in_fresh_process(tmp_path, "2", configured)


def test_element_sizes_of_a_disc_follow_its_axis_not_z():
    # the sizes alone, fast: issue 35's 20 x 1 mm PZT-5A disc near 100 kHz (1.23 mm elements on axis z; 2.75 mm on
    # axis x before: the bending wavelength of a 20 mm thick "plate")
    sizes = {axis: element_sizes(scene_from_dict(_disc(axis, 10.0, 1.0, "PZT-5A", 100e3)))["disc"] for axis in "xyz"}
    assert sizes["x"] == sizes["y"] == sizes["z"]
