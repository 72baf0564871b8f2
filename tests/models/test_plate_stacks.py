"""The plate model on plates built of several boxes: side-by-side strips are stack cells, not posts; a post
is recognised by its stacking (standing on another part, free at its sides, taller than wide)."""

import numpy as np
import pytest

from modalfe.errors import SceneError
from modalfe.geometry.parts import Assembly, Box
from modalfe.models.plate import is_post
from modalfe.scene import load_scene, scene_from_dict
from modalfe.solve.api import solve_modes


def _plate(parts, **extra):
    return scene_from_dict({"name": "strips", "units": "mm", "kind": "plate", "parts": parts,
                            "analysis": {"near": 8000.0, "count": 6}, "mesh": {"max_size": 0.001}, **extra})


def _frequencies(scene):
    """The elastic modes' frequencies [Hz] (a free plate's rigid-body modes, ~0 Hz, left out)."""
    modes = solve_modes(scene, near=8000.0, count=8, fidelity="plate", error_estimate=False)
    return np.array(sorted(m.frequency for m in modes if m.frequency > 100.0))


@pytest.mark.parametrize("axis", [0, 1])
def test_a_plate_of_narrow_strips_side_by_side_is_the_same_plate(axis):
    # 2 mm strips 3 mm thick (narrower than thick) along x or y: before, each was taken for a post and the
    # model crashed with a traceback (no structural layer in any cell)
    size = [40, 20, 3]
    n = size[axis] // 2
    strips = []
    for i in range(n):
        origin, box = [0, 0, 0], list(size)
        origin[axis], box[axis] = 2 * i, 2
        strips.append({"name": f"s{i}", "material": "CuBe", "origin": origin, "size": box})
    whole = _plate([{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": size}])
    # the 1 mm grid is the same for both (every strip edge is a grid line): equal to round-off
    expected = _frequencies(whole)
    assert len(expected) >= 3
    np.testing.assert_allclose(_frequencies(_plate(strips)), expected, rtol=1e-8)


def test_posts_are_recognised_by_their_stacking():
    cube = load_scene("cube_plate").full_assembly()
    assert [p.name for p in cube.parts if is_post(p, cube)] == ["foot_1", "foot_2", "foot_3", "foot_4"]
    strips = Assembly(tuple(Box(f"s{i}", "s", "CuBe", (2e-3 * i, 0, 0), (2e-3 * (i + 1), 0.02, 3e-3))
                            for i in range(3)))
    assert not any(is_post(p, strips) for p in strips.parts)


def test_a_post_reaching_beyond_its_support_is_refused_in_one_line():
    parts = [{"name": "plate", "material": "CuBe", "origin": [0, 0, 0], "size": [40, 20, 1]},
             {"name": "foot", "material": "CuBe", "origin": [38.5, 5, -4], "size": [3, 3, 4]}]
    with pytest.raises(SceneError) as info:
        _frequencies(_plate(parts))
    assert str(info.value).startswith("parts:") and "\n" not in str(info.value)
