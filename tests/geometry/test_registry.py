"""The registry of built-in scenes: every one meshes, with every named group it uses present and the
parts' meshed volumes adding up to the device."""

import numpy as np
import pytest
from skfem import Basis, ElementHex1, ElementTetP1, Functional

from modalfe.models.mesh import build_mesh, element_sizes
from modalfe.models.solid import face_area
from modalfe.response.loads import MEAN_PREFIX
from modalfe.scene import load_scene
from modalfe.scene.builtin import BUILTIN

_volume = Functional(lambda w: 1.0 + 0.0 * w.x[0])


def _coarse_mesh(scene):
    """The scene's mesh as ``modalfe.solve.solvers.assembled_model`` builds it, at 3 elements per wavelength."""
    fully_clamped = tuple(sorted(g for g, c in scene.clamps.items() if set(c) == set("xyz")))
    return build_mesh(scene.assembly(), size=element_sizes(scene), element=scene.mesh.element,
                      min_layers=scene.mesh.min_layers, graded_faces=fully_clamped,
                      grading_layers=scene.mesh.clamp_grading)


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_every_builtin_scene_meshes_with_its_named_groups(name):
    scene = load_scene(name, **{"mesh.elements_per_wavelength": 3})
    assembly, full = scene.assembly(), scene.full_assembly()
    dm = _coarse_mesh(scene)

    # every face group the scene gives a role, and every symmetry plane, is in the meshed assembly
    used = {**{f"electrodes.{g}": g for g in scene.electrodes}, **{f"clamps.{g}": g for g in scene.clamps},
            **{f"springs.{g}": g for g in scene.springs}, **{f"masses.{g}": g for g in scene.masses},
            **{f"symmetry.{g}": g for g in scene.symmetry_clamps}}
    for role, group in used.items():
        assert group in assembly.faces, f"{name}: {role} is not a face group of the meshed assembly"
    for output in scene.drive.outputs:
        if isinstance(output, str):  # a face group's centre, or "mean:GROUP", the mean over it
            group = output.removeprefix(MEAN_PREFIX)
            assert group in full.faces, f"{name}: drive output '{output}' is not a face group"
    # every face group of the meshed assembly is a non-empty mesh group of the right area
    for group in assembly.faces:
        assert len(dm.faces.get(group, ())) > 0, f"{name}: face group '{group}' is empty in the mesh"
        assert face_area(dm, group) == pytest.approx(assembly.face_area(group), rel=1e-9), group

    # every part is meshed, the parts share no element and together are the whole mesh
    n_elements = dm.mesh.t.shape[1]
    owner = np.zeros(n_elements, dtype=int)
    for part in assembly.parts:
        assert len(dm.parts.get(part.name, ())) > 0, f"{name}: part '{part.name}' has no elements"
        owner[dm.parts[part.name]] += 1
    assert set(dm.parts) == {p.name for p in assembly.parts}
    assert np.all(owner == 1), f"{name}: {np.sum(owner != 1)} elements in no part or in two"

    # the parts' meshed volumes sum to the assembly's (boxes are meshed exactly: round-off only)
    element = ElementHex1() if dm.element == "hex" else ElementTetP1()
    meshed = {p.name: _volume.assemble(Basis(dm.mesh, element, elements=dm.parts[p.name], intorder=2))
              for p in assembly.parts}
    for part in assembly.parts:
        assert meshed[part.name] == pytest.approx(part.volume, rel=1e-9), part.name
    total = sum(p.volume for p in assembly.parts)
    assert sum(meshed.values()) == pytest.approx(total, rel=1e-9)
    assert _volume.assemble(Basis(dm.mesh, element, intorder=2)) == pytest.approx(total, rel=1e-9)
