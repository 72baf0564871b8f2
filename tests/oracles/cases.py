"""Reference cases for verification against analytic theory, shared by tests/models/test_verification.py
and studies/verification.py: each scene is sized by ``max_size`` alone (one element per wavelength
never binds), so refinement by ``size_factor`` is uniform and element counts are exact."""

from __future__ import annotations

from pathlib import Path

from modalfe.scene import load_scene, scene_from_dict

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"  # the scene files and scripts a user starts from


def reference_mesh(max_size: float, min_layers: int) -> dict:
    """Mesh settings fixed by the element size: elements_per_wavelength never binds."""
    return {"elements_per_wavelength": 1.0, "max_size": max_size, "min_layers": min_layers}


def cantilever_scene(max_size: float):
    """Seed 003's beam made uniform: 100 x 5 x 5 mm brass, clamped (all components) at x = 0."""
    return scene_from_dict({
        "name": "uniform-cantilever", "units": "mm", "kind": "beam",
        "parts": [{"name": "beam", "region": "beam", "material": "brass-seed003",
                   "origin": [0, 0, 0], "size": [100, 5, 5]}],
        "faces": {"clamp": ["beam.xmin"]}, "clamps": {"clamp": "xyz"},
        "analysis": {"near": 11e3, "count": 18}, "mesh": reference_mesh(max_size, 2),
    })


def diaphragm_plate_scene(a: float, b: float, h: float, max_size: float):
    """CuBe plate a x b x h [m]: u_y = u_z = 0 on x = 0, a; u_x = u_z = 0 on y = 0, b."""
    return scene_from_dict({
        "name": "diaphragm-plate", "units": "m", "kind": "plate",
        "parts": [{"name": "plate", "region": "plate", "material": "CuBe",
                   "origin": [0, 0, 0], "size": [a, b, h]}],
        "faces": {"x_edges": ["plate.xmin", "plate.xmax"], "y_edges": ["plate.ymin", "plate.ymax"]},
        "clamps": {"x_edges": "yz", "y_edges": "xz"},
        "analysis": {"near": 1e3, "count": 8}, "mesh": reference_mesh(max_size, 1),
    })


def k31_bar_scene(max_size: float):
    """PZT-5A bar 30 x 2 x 1 mm, free, poled along z, electrodes on zmin (ground), zmax (drive)."""
    return scene_from_dict({
        "name": "k31-bar", "units": "mm", "kind": "beam",
        "parts": [{"name": "bar", "region": "piezo", "material": "PZT-5A",
                   "origin": [0, 0, 0], "size": [30, 2, 1], "poling": 1}],
        "faces": {"top": ["bar.zmax"], "bottom": ["bar.zmin"]},
        "electrodes": {"top": "drive", "bottom": "ground"},
        "analysis": {"near": 47e3, "count": 8}, "mesh": reference_mesh(max_size, 2),
    })


def free_plate_scene(**extra):
    """A free 40 x 10 x 1 mm Cu-Be plate meshed with 1.25 mm elements (even divisions across y)."""
    data = {
        "name": "plate", "kind": "plate",
        "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [0.04, 0.01, 0.001]}],
        "analysis": {"near": 5000.0, "count": 6},
        "mesh": {"max_size": 1.25e-3},
    }
    data.update(extra)
    return scene_from_dict(data)


def clamped_bar_scene(nu: float, max_size: float):
    """A 40 x 4 x 4 mm cantilever of E = 100 GPa, rho = 8000 kg/m^3 and Poisson ratio ``nu`` (up to
    nearly incompressible), meshed with elements of ``max_size`` [m], for the stability suite."""
    return scene_from_dict({
        "name": "bar", "units": "mm", "kind": "beam",
        "materials": {"m": {"E": 100e9, "nu": nu, "rho": 8000.0}},
        "parts": [{"name": "bar", "material": "m", "origin": [0, 0, 0], "size": [40, 4, 4]}],
        "faces": {"clamp": ["bar.xmin"]}, "clamps": {"clamp": "xyz"},
        "analysis": {"near": 1500.0, "count": 2}, "mesh": reference_mesh(max_size, 1),
    })


def two_patch_bar_scene(**extra):
    """Two PZT-5A patches 15 x 2 x 1 mm end to end, poled + and -, each under its own driven top electrode (two
    floating potentials in open circuit), one grounded bottom electrode; ``extra`` adds to the scene's fields."""
    data = {
        "name": "two-patch-bar", "units": "mm", "kind": "beam",
        "parts": [{"name": "left", "region": "piezo", "material": "PZT-5A", "origin": [0, 0, 0],
                   "size": [15, 2, 1], "poling": 1},
                  {"name": "right", "region": "piezo", "material": "PZT-5A", "origin": [15, 0, 0],
                   "size": [15, 2, 1], "poling": -1}],
        "faces": {"top_left": ["left.zmax"], "top_right": ["right.zmax"], "bottom": ["left.zmin", "right.zmin"]},
        "electrodes": {"top_left": "drive", "top_right": "drive", "bottom": "ground"},
        "analysis": {"near": 47e3, "count": 6}, "mesh": {"max_size": 1.0, "elements_per_wavelength": 1.0},
    }
    for key, value in extra.items():
        data[key] = {**data[key], **value} if isinstance(value, dict) and key in data else value
    return scene_from_dict(data)


def stack_scene(max_size: float = 0.75e-3, near: float = 191.8e3, count: int = 6):
    """examples/disc_stack.toml: a free aluminium disc (12 x 1.5 mm) with a PZT-5A disc (8 x 1.2 mm) bonded by 50 um of
    epoxy, on elements of ``max_size`` [m] (studies/level_coverage.py): at 0.75 mm the ceramic is 2 layers on the
    scene's grid and on the x1.5 estimate level, 1 on the x2.25 one; its torsion mode T2 near 192 kHz."""
    return load_scene(EXAMPLES / "disc_stack.toml",
                      **{"mesh.max_size": max_size, "analysis.near": near, "analysis.count": count})


def strip_scene(max_size: float = 1.2e-3, near: float = 20e3, count: int = 4):
    """A thick Cu-Be plate 20 x 16 x 2 mm clamped (all components) on a 2 mm strip across its lower face."""
    return scene_from_dict({
        "name": "strip-plate", "units": "mm", "kind": "plate",
        "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [20, 16, 2]}],
        "faces": {"strip": [{"face": "plate.zmin", "window": [[0, 7], [20, 9]]}]},
        "clamps": {"strip": "xyz"}, "analysis": {"near": near, "count": count},
        "mesh": {"max_size": max_size},
    })


def cantilever_plate_scene(max_size: float = 2.5e-3, near: float = 3e3, count: int = 4, thickness: float = 0.5):
    """A thin Cu-Be plate 30 x 10 x ``thickness`` mm clamped (all components) on its end xmin."""
    return scene_from_dict({
        "name": "cantilever-plate", "units": "mm", "kind": "plate",
        "parts": [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [30, 10, thickness]}],
        "faces": {"root": ["plate.xmin"]}, "clamps": {"root": "xyz"}, "analysis": {"near": near, "count": count},
        "mesh": {"max_size": max_size},
    })
