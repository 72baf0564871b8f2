"""`modalfe place SCENE`: feet moved onto in-phase antinodes of the working mode (wraps ``place_feet``)."""

from __future__ import annotations

import json
import logging
import time

from modalfe.cli.options import frequency, positive_float, solve_options
from modalfe.cli.page import add_html_option, scene_page

log = logging.getLogger(__name__)
DEFAULT_CONTACT_STIFFNESS = 9.7e6  # N/m per foot, seed 000 appendix (modalfe.contact.foot_model.KN)


def register(subparsers) -> None:
    p = subparsers.add_parser("place", help="put the feet on the working mode's antinodes and report the "
                                            "frequency without feet, with feet and in contact")
    p.add_argument("scene", help="built-in scene name or .toml scene file (its builder must take 'feet')")
    p.add_argument("--mode", help="mode label or family, e.g. '(0,6)' or '(0,n)' (default: the working mode)")
    p.add_argument("--near", type=frequency, help="frequency [Hz] to search near (default: the working mode's)")
    p.add_argument("--contact-stiffness", type=positive_float, default=DEFAULT_CONTACT_STIFFNESS,
                   help=f"normal contact stiffness under each foot [N/m] (default {DEFAULT_CONTACT_STIFFNESS:g}, "
                        "seed 000)")
    p.add_argument("--part", default="plate", help="part whose bottom face carries the feet (default plate)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene parameter")
    p.add_argument("--json", action="store_true", help="one JSON document on stdout")
    solve_options(p)
    add_html_option(p)
    p.set_defaults(func=_place)


def _place(args) -> int:
    from modalfe.cli.options import parse_overrides, solve_keywords
    from modalfe.errors import SceneError
    from modalfe.geometry import builder_parameters
    from modalfe.response.placement import place_feet
    from modalfe.results.labels import check_selector
    from modalfe.scene import load_scene
    from modalfe.solve.api import seek

    scene = load_scene(args.scene, **parse_overrides(args.set))
    if "feet" not in builder_parameters(scene.device):
        raise SceneError(f"scene: '{scene.name}' has no feet to place (device '{scene.device}' takes no 'feet')")
    if args.part not in {p.name for p in scene.full_assembly().parts}:
        raise SceneError(f"--part: no part '{args.part}' in '{scene.name}'")
    selector, near = seek(scene, None if args.mode is None else check_selector(args.mode, "--mode"), args.near)
    if selector is None or near is None:
        raise SceneError("--mode: the scene names no working mode; give --mode and --near")
    before = tuple(tuple(f) for f in scene.params.get("feet", builder_parameters(scene.device)["feet"].default))
    log.info("placing %d feet on %s near %g Hz: three solves (bare plate, with feet, in contact)",
             len(before), selector, near)
    start = time.perf_counter()
    placement = place_feet(scene, selector=selector, near=near, contact_stiffness=args.contact_stiffness,
                           part=args.part, **solve_keywords(args))
    seconds = time.perf_counter() - start
    log.info("placement done in %.1f s", seconds)
    feet = [{"foot": f"foot_{i}", "from_m": list(old), "to_m": list(new), "moved_m": moved}
            for i, (old, new, moved) in enumerate(zip(before, placement.feet, placement.moved_by), start=1)]
    result = {"scene": scene.name, "mode": selector, "near_hz": near, "feet": feet,
              "frequency_without_feet_hz": placement.frequency_without_feet,
              "frequency_with_feet_hz": placement.frequency_with_feet,
              "frequency_in_contact_hz": placement.frequency_in_contact,
              "shift_from_feet_hz": placement.shift_from_feet, "shift_from_contact_hz": placement.shift_from_contact,
              "contact_stiffness_n_per_m": placement.contact_stiffness, "seconds": seconds,
              "set": "--set feet=[" + ", ".join(f"[{x:.6g}, {y:.6g}]" for x, y in placement.feet) + "]"}
    scene_page(args, scene.with_overrides(feet=placement.feet))  # the placed design's
    if args.json:
        print(json.dumps(result, indent=2))
        return 0
    print(f"{scene.name}: feet on the in-phase antinodes of {selector} (search near {near:g} Hz)")
    for f in feet:
        (x0, y0), (x1, y1) = f["from_m"], f["to_m"]
        print(f"  {f['foot']}: ({1e3 * x0:.2f}, {1e3 * y0:.2f}) mm -> ({1e3 * x1:.2f}, {1e3 * y1:.2f}) mm, "
              f"moved {1e3 * f['moved_m']:.2f} mm")
    print(f"  without feet      {placement.frequency_without_feet:10.1f} Hz")
    print(f"  with feet         {placement.frequency_with_feet:10.1f} Hz  ({placement.shift_from_feet:+.1f} Hz)")
    print(f"  in contact        {placement.frequency_in_contact:10.1f} Hz  ({placement.shift_from_contact:+.1f} Hz, "
          f"{placement.contact_stiffness:.3g} N/m under each foot)")
    print(f"  to use them: {result['set']}")
    return 0
