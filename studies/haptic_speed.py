"""Processes for timing the chain's outcome and map from outside: each prints what it computed and the in-process
seconds of the timed step; ``--skip`` does everything but that step (the baseline of a pair). Time each process whole,
A and B in turn, and take the median of A less the median of B, e.g. with ``/usr/bin/time -v``:

    /usr/bin/time -v python studies/haptic_speed.py outcome --rom ROM.json --voltage 12.7
    /usr/bin/time -v python studies/haptic_speed.py outcome --rom ROM.json --voltage 12.7 --skip
    /usr/bin/time -v python studies/haptic_speed.py map --scene glass_plate --voltage 23        # and --skip

``outcome``: a reduced model saved by ``modalfe forced --save-rom`` and the amplitude's stated error (``--error``)
joined to the foot at 3 N, 1 cm/s (seed 001) or the finger (``--finger``), the outcome at ``--voltage`` (three
contact states: the amplitude and its two error ends). ``map``: the scene's working mode (cached solve) and the
finger, the map over ``--points`` points of the top face.
"""

from __future__ import annotations

import argparse
import time

from modalfe.contact.chain import FingerContact, FootContact, chain_from_rom, haptic_chain, haptic_map, surface_points
from modalfe.response.forced import ReducedModel
from modalfe.scene import load_scene


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("what", choices=("outcome", "map"))
    parser.add_argument("--rom", help="reduced model JSON (outcome)")
    parser.add_argument("--error", type=float, default=0.0822, help="amplitude's stated relative error (outcome; "
                                                                     "default: the Cu-Be plate's foot_1, forced)")
    parser.add_argument("--finger", action="store_true", help="outcome: the finger (seed 004) instead of the foot")
    parser.add_argument("--scene", default="glass_plate")
    parser.add_argument("--near", type=float)
    parser.add_argument("--voltage", type=float, required=True)
    parser.add_argument("--points", type=int, default=400)
    parser.add_argument("--skip", action="store_true", help="all but the timed step")
    args = parser.parse_args(argv)
    if args.what == "outcome":
        rom = ReducedModel.load(args.rom)
        contact = FingerContact() if args.finger else FootContact(preload=3.0, speed=0.01)
        chain = chain_from_rom(rom, contact, errors={f"amplitude:{rom.reference}": args.error})
    else:
        scene = load_scene(args.scene)
        chain = haptic_chain(scene, FingerContact(), near=args.near)
        points, weights = surface_points(scene, count=args.points)
    if args.skip:
        return 0
    start = time.perf_counter()
    if args.what == "outcome":
        result = chain.outcome(args.voltage)
    else:
        result = haptic_map(chain, points, args.voltage, weights=weights)
    print(f"{args.what}: {time.perf_counter() - start:.3f} s in process")
    print(result if args.what == "outcome" else f"{len(result.points)} points, reduction up to "
          f"{result.reduction.max():.4f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
