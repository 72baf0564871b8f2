"""Meshes: part volumes, conformity of bonded parts, named faces, the cache, tetrahedra."""

import numpy as np
import pytest
from skfem import Basis, ElementHex1, ElementTetP1, Functional

from modalfe.errors import MeshError
from modalfe.geometry import BUILDERS
from modalfe.models.mesh import build_mesh, element_sizes
from modalfe.scene import load_scene
from modalfe.scene.builtin import BUILTIN

_volume = Functional(lambda w: 1.0 + 0.0 * w.x[0])


def _default_mesh(name):
    scene = load_scene(name)
    return scene, scene.assembly(), build_mesh(scene.assembly(), size=element_sizes(scene))


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_part_volumes_equal_box_volumes(name):
    _, assembly, dm = _default_mesh(name)
    element = ElementHex1() if dm.element == "hex" else ElementTetP1()
    for part in assembly.parts:
        basis = Basis(dm.mesh, element, elements=dm.parts[part.name], intorder=2)
        # boxes are meshed exactly by straight-sided elements: only round-off remains
        assert _volume.assemble(basis) == pytest.approx(part.volume, rel=1e-9), part.name


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_bonded_parts_share_nodes(name):
    _, assembly, dm = _default_mesh(name)
    p = dm.mesh.p
    scale = np.ptp(p, axis=1).max()
    # no two mesh vertices at the same place: parts that touch use the same interface nodes
    rounded = np.round(p / (1e-9 * scale)).astype(np.int64)
    assert len(np.unique(rounded, axis=1).T) == p.shape[1]
    # and every touching pair of parts actually has elements on both sides of common vertices
    for i, a in enumerate(assembly.parts):
        va = set(np.unique(dm.mesh.t[:, dm.parts[a.name]]).tolist())
        for b in assembly.parts[i + 1:]:
            gap = [min(a.hi[k], b.hi[k]) - max(a.lo[k], b.lo[k]) for k in range(3)]
            touching = sum(abs(g) < 1e-12 for g in gap) == 1 and sum(g > 1e-12 for g in gap) == 2
            if touching:
                vb = set(np.unique(dm.mesh.t[:, dm.parts[b.name]]).tolist())
                assert va & vb, f"{a.name} and {b.name} touch but share no node"


def test_face_groups_have_the_right_area():
    _, assembly, dm = _default_mesh("cube_plate")
    from modalfe.models.solid import face_area

    ceramic_tops = sum(p.size[0] * p.size[1] for p in assembly.parts if p.region == "piezo")
    assert face_area(dm, "electrode_top") == pytest.approx(ceramic_tops, rel=1e-9)
    assert face_area(dm, "foot_1") == pytest.approx(3e-3 * 3e-3, rel=1e-9)
    _, _, tile = _default_mesh("honeycomb_tile")
    assert face_area(tile, "actuator") == pytest.approx(0.04**2, rel=1e-9)
    assert face_area(tile, "mount_1") == pytest.approx(0.02828**2, rel=1e-9)


def test_the_cache_returns_the_same_mesh_without_meshing(monkeypatch, tmp_path):
    monkeypatch.setenv("MODALFE_CACHE", str(tmp_path))
    from modalfe.models import mesh as mesh_module

    assembly = BUILDERS["ciliary_beam"]()
    first = build_mesh(assembly, size=4e-3)
    assert first.seconds > 0
    assert build_mesh(assembly, size=4e-3) is first  # in-process hit
    mesh_module._memory_cache.clear()

    def fail(*args, **kwargs):
        raise AssertionError("gmsh was called on a cached scene")

    monkeypatch.setattr(mesh_module, "_gmsh_mesh", fail)
    again = build_mesh(assembly, size=4e-3)  # read back from disk
    assert again.seconds == 0.0
    np.testing.assert_array_equal(again.mesh.t, first.mesh.t)
    for name in first.parts:
        np.testing.assert_array_equal(again.parts[name], first.parts[name])
    for name in first.faces:
        np.testing.assert_array_equal(np.sort(again.faces[name]), np.sort(first.faces[name]))


def test_tetrahedral_mesh_of_a_box_device():
    assembly = BUILDERS["ciliary_beam"]()
    dm = build_mesh(assembly, size=2e-3, element="tet", use_cache=False)
    assert dm.mesh.t.shape[0] == 4
    basis = Basis(dm.mesh, ElementTetP1(), elements=dm.parts["beam_1"], intorder=1)
    assert _volume.assemble(basis) == pytest.approx(assembly.part("beam_1").volume, rel=1e-9)
    assert len(dm.faces["clamp"]) > 0


def test_face_windows_need_hexahedra():
    with pytest.raises(MeshError) as info:
        build_mesh(BUILDERS["honeycomb_tile"](), size=0.03, element="tet", use_cache=False)
    assert "mesh.element" in str(info.value)


def test_element_size_follows_the_frequency():
    low = element_sizes(load_scene("glass_plate", **{"mesh.max_frequency": 70e3, "analysis.near": 50e3}))
    high = element_sizes(load_scene("glass_plate"))
    # bending wavelength ~ f^-1/2: 250 kHz vs 70 kHz asks for elements ~ sqrt(250/70) = 1.9x smaller
    assert low["glass"] / high["glass"] == pytest.approx(np.sqrt(250 / 70), rel=0.15)


def test_a_gmsh_failure_is_a_one_line_mesh_error(monkeypatch):
    import gmsh

    def broken(dim):
        raise Exception("Meshing failed in volume 3")

    monkeypatch.setattr(gmsh.model.mesh, "generate", broken)
    with pytest.raises(MeshError) as info:
        build_mesh(BUILDERS["ciliary_beam"](), size=4e-3, use_cache=False)
    assert "gmsh failed" in str(info.value) and "\n" not in str(info.value)
    assert not gmsh.isInitialized()  # gmsh is finalized even when it fails


def test_clamp_grading_adds_geometric_layers_toward_the_clamp():
    assembly = BUILDERS["ciliary_beam"]()
    plain = build_mesh(assembly, size=4e-3, use_cache=False)
    graded = build_mesh(assembly, size=4e-3, graded_faces=("clamp",), grading_layers=4, use_cache=False)
    x_plain, x_graded = (np.unique(np.round(dm.mesh.p[0], 12)) for dm in (plain, graded))
    # grid planes at h r^k from the clamp face x = 0 (h = 4 mm, r = 0.4, k = 1..4): 0.10, 0.26, 0.64, 1.6 mm
    np.testing.assert_allclose(x_graded[1:5], 4e-3 * 0.4 ** np.arange(4, 0, -1), rtol=1e-9)
    assert len(x_graded) == len(x_plain) + 4  # the rest of [0, 63 mm] still needs 16 elements of <= 4 mm
    assert np.diff(x_graded).max() <= 4e-3 + 1e-12
    # y and z are untouched: the clamped face's normal is x
    for k in (1, 2):
        np.testing.assert_array_equal(np.unique(np.round(graded.mesh.p[k], 12)),
                                      np.unique(np.round(plain.mesh.p[k], 12)))
    assert graded.key != plain.key  # the cache tells the two meshes apart


def test_clamp_grading_needs_a_known_face_group_and_a_small_integer():
    from modalfe.errors import SceneError

    with pytest.raises(MeshError) as info:
        build_mesh(BUILDERS["ciliary_beam"](), size=4e-3, graded_faces=("root",), grading_layers=4, use_cache=False)
    assert "graded_faces" in str(info.value) and "root" in str(info.value)
    for bad in (-1, 2.5, True, 13):
        with pytest.raises(SceneError) as info:
            load_scene("ciliary_beam", **{"mesh.clamp_grading": bad})
        assert "mesh.clamp_grading" in str(info.value)
