"""Device-level checks of a scene, run at the end of ``Scene.validate``: the parts form one bonded body,
and the electrodes can be driven (each on a poled part, none both driven and grounded, no drive face
touching a ground face, no poled part shorted by one group on both its faces).

A scene that fails one of them used to solve and give a wrong number (0.2 Hz "bending" modes of loose
parts, zero or wrong amplitudes); each now raises a one-line SceneError naming the parts or the group.
"""

from __future__ import annotations

from modalfe.errors import SceneError

_Rect = tuple[int, float, tuple[float, ...], tuple[float, ...]]  # normal axis, its coordinate, lo, hi


def check_device(scene) -> None:
    """Raise SceneError unless ``scene``'s parts are bonded into one body and its electrodes are
    consistent (see the module docstring)."""
    assembly = scene.full_assembly()
    assembly.check_connected()
    check_electrodes(assembly, dict(scene.electrodes))


def check_electrodes(assembly, roles: dict[str, str]) -> None:
    """Raise SceneError naming the electrode group at fault: a face of no poled part, a face both
    driven and grounded, a drive face touching a ground face, a poled part with one group on both faces its
    poling runs between (z faces of a box; top and bottom, or inner and outer when radial, of a shape).

    Electrode faces are compared as rectangles in space, so a ground electrode on a metal part's face
    under a piezo counts as touching that piezo (a legitimate design), and a face listed under another
    part's name (the plate's top under a ceramic's bottom) counts as the same face. A shape's planar end
    compares by its bounding rectangle, its walls by name (an approximation: a disc's top over a box
    electrode counts as overlapping where their rectangles do)."""
    tol = assembly.tolerance
    poled = [p for p in assembly.parts if p.poling]
    faces = {g: [(f"{f.part}.{f.side}", (f.part, f.side), assembly.face_rect(f)) for f in assembly.faces.get(g, ())]
             for g in roles}
    for group in roles:
        for name, key, r in faces[group]:
            if not any(_same(key, r, (p.name, side), p.planar_face(side), tol) for p in poled for side in p.sides):
                what = "the device has no poled part" if not poled else "an electrode must lie on a poled part's face"
                raise SceneError(f"electrodes.{group}: face '{name}' touches no poled piezo part ({what})")
    drive = [g for g, role in roles.items() if role == "drive"]
    ground = [g for g, role in roles.items() if role == "ground"]
    for g in drive:
        for h in ground:
            for name, key, r in faces[g]:
                for other, key2, s in faces[h]:
                    if _same(key, r, key2, s, tol):
                        raise SceneError(f"electrodes.{g}: face '{name}' is also in the ground electrode '{h}' "
                                         f"('{other}'): a face cannot be both driven and grounded")
                    if r is not None and s is not None and _touch(r, s, tol):
                        raise SceneError(f"electrodes.{g}: drive face '{name}' touches ground face '{other}' of "
                                         f"'{h}' along an edge or at a corner (a short circuit)")
    for p in poled:
        if p.poling_faces is None:
            continue  # poled across its axis: no pair of named faces to short
        covering = {side: {g for g in roles for _, key, r in faces[g]
                           if _same(key, r, (p.name, side), p.planar_face(side), tol)} for side in p.poling_faces}
        shorted = set.intersection(*covering.values())
        if shorted:
            g = sorted(shorted)[0]
            raise SceneError(f"electrodes.{g}: covers both {' and '.join(p.poling_faces)} faces of the poled part "
                             f"'{p.name}' (it shorts the part: no field through it)")
        low, high = ({roles[g]: g for g in sorted(covering[side])} for side in p.poling_faces)
        same = sorted(set(low) & set(high))  # two groups of one role: one potential on both faces
        if same:
            role = same[0]
            raise SceneError(f"electrodes.{high[role]}: on the {p.poling_faces[1]} face of the poled part '{p.name}' "
                             f"and '{low[role]}' on its {p.poling_faces[0]} face are both {role}: one potential on "
                             f"both faces, no field through it; make one of them the other role")


def check_ground(scene, field: str) -> None:
    """A voltage drives a field only against a ground: SceneError naming ``field`` when the scene's electrodes
    have none (the driven ones alone fix no potential difference: the response is zero, to round-off)."""
    if "drive" in scene.electrodes.values() and "ground" not in scene.electrodes.values():
        drives = sorted(g for g, role in scene.electrodes.items() if role == "drive")
        raise SceneError(f"{field}: the scene has no ground electrode: a voltage on {', '.join(drives)} alone "
                         f"drives no field through the piezo (its other faces float); make an electrode ground")


def _same(key, r: _Rect | None, key2, s: _Rect | None, tol: float) -> bool:
    """Two faces are one: the same part and side, or coplanar rectangles sharing a patch of positive area (walls
    that are not planar compare by name only)."""
    return key == key2 or (r is not None and s is not None and _overlap(r, s, tol))


def _overlap(a: _Rect, b: _Rect, tol: float) -> bool:
    """Coplanar face rectangles sharing a patch of positive area."""
    if a[0] != b[0] or abs(a[1] - b[1]) > tol:
        return False
    return all(min(a[3][k], b[3][k]) - max(a[2][k], b[2][k]) > tol for k in range(3) if k != a[0])


def _touch(a: _Rect, b: _Rect, tol: float) -> bool:
    """Face rectangles with a point in common (a shared edge, a corner, or more)."""
    def interval(r: _Rect, k: int) -> tuple[float, float]:
        return (r[1], r[1]) if k == r[0] else (r[2][k], r[3][k])

    return all(min(interval(a, k)[1], interval(b, k)[1]) - max(interval(a, k)[0], interval(b, k)[0]) >= -tol
               for k in range(3))
