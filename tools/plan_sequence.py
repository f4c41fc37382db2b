"""Find a reconfiguration sequence in the lattice model and print it as an RDCD ``sequence``
(docs/reconfiguration.md "Finding a sequence").

    python tools/plan_sequence.py car7 --chain --move-entry --irreversible   # a flat chain
    python tools/plan_sequence.py eight7 car7             # the shape of car7, up to turns about z
    python tools/plan_sequence.py START TARGET [--max-states N] [--max-steps N] [--weight W]
                                  [--max-cut K] [--move-entry] [--irreversible]
    python tools/plan_sequence.py eight7 car7 --guide 3,4,1,4,6,0,1,0,1,3,1 \
        --guide-signs=-1,-1,-1,1,1,-1,1,1,1,1,1     # turns by these modules in this order (USSR's)

START and TARGET are configuration names or files (sim/configs). The steps name each acting
module by a role of its coordinates in START (``role M3 { ... }``): a module keeps the coordinates
it learned while it keeps a connection, and no step splits the robot. These roles are a sketch:
merge them by hand to stay within a module's ten program slots, e.g. one role with a key on the
coordinates (examples/car_to_snake.rdcd, the compact form).
Exit status 0 with a sequence, 1 when none was found (the reason on stderr), 2 on bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from sim.config import load_config  # noqa: E402
from vm import navigation  # noqa: E402
from vm.lattice.plan import FlatChain, Op, guided, plan, prune  # noqa: E402

AXIS_WORDS = {navigation.EAST_WEST: "EAST_WEST", navigation.NORTH_SOUTH: "NORTH_SOUTH",
              navigation.UP_DOWN: "UP_DOWN"}


def render(start, ops: list[Op], name: str, config: str) -> str:  # noqa: ANN001 - a Structure
    """The RDCD text: a role per acting module (its axis and cell in ``start``) and the sequence."""
    lines = []
    actors = sorted({op.module for op in ops})
    for m in actors:
        spec = start.modules[m]
        x, y, z = spec.position
        lines += [f"role M{m} {{", f"  self.center_position == {AXIS_WORDS[spec.axis]};",
                  f"  self.x() == {x};", f"  self.y() == {y};", f"  self.z() == {z};", "}", ""]
    lines.append(f"sequence {name}({config}) {{")
    lines += [f"  M{op.module}.{op.text()};" for op in ops]
    lines += ["}", "", "// give the modules that do not act a role too (docs/reconfiguration.md)",
              f"deployment {{ {', '.join(f'M{m}' for m in actors)} }}"]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("start")
    parser.add_argument("target", nargs="?", help="a configuration whose shape to reach")
    parser.add_argument("--chain", action="store_true", help="reach any chain lying flat instead")
    parser.add_argument("--max-states", type=int, default=3000)
    parser.add_argument("--max-steps", type=int, default=30)
    parser.add_argument("--max-cut", type=int, default=2)
    parser.add_argument("--weight", type=float, default=2.0)
    parser.add_argument("--move-entry", action="store_true",
                        help="let turns carry the entry module (the modules keep the coordinates they "
                             "learned in the start; one that learned its place afresh would learn "
                             "it in the moved entry's frame)")
    parser.add_argument("--irreversible", action="store_true",
                        help="let steps open links between two connectors of one sex (they cannot "
                             "close again: the sequence cannot be run backwards)")
    parser.add_argument("--guide", help="comma-separated modules that make the quarter turns, in "
                        "order (a known solution's skeleton; implies --move-entry, --max-cut 3 "
                        "unless given)")
    parser.add_argument("--guide-signs", help="comma-separated signs of those turns, tried first")
    parser.add_argument("--name", default="reconfigure")
    args = parser.parse_args(argv)
    if (args.target is None) == (not args.chain):
        parser.error("give a TARGET configuration or --chain (not both)")
    if not (1 <= args.max_states <= 1_000_000 and 1 <= args.max_steps <= 60
            and 0 <= args.max_cut <= 4 and args.weight >= 0):
        parser.error("--max-states 1..1000000, --max-steps 1..60, --max-cut 0..4, --weight >= 0")
    try:
        start = load_config(args.start)
        target = FlatChain(len(start.modules), reversible=not args.irreversible) if args.chain \
            else load_config(args.target)
    except (ValueError, OSError) as error:
        print(f"plan_sequence: {error}", file=sys.stderr)
        return 2
    if args.guide is not None:
        try:
            actors = [int(v) for v in args.guide.split(",")]
            signs = [int(v) for v in args.guide_signs.split(",")] if args.guide_signs else []
        except ValueError:
            parser.error("--guide and --guide-signs take comma-separated integers")
        if len(actors) > 60 or isinstance(target, FlatChain) or any(v not in (1, -1) for v in signs):
            parser.error("--guide: at most 60 turns, a TARGET configuration, signs 1 or -1")
        cut = args.max_cut if "--max-cut" in " ".join(argv or sys.argv) else 3
        found = guided(start, target, actors, skeleton_signs=signs, max_cut=cut,
                       max_states=args.max_states, reversible=not args.irreversible)
        if found.ok:
            found.ops = prune(start, found.ops, target)
    else:
        found = plan(start, target, max_states=args.max_states, max_steps=args.max_steps,
                     weight=args.weight, max_cut=args.max_cut, keep_entry=not args.move_entry,
                     reversible=not args.irreversible)
    if not found.ok:
        print(f"plan_sequence: {found.reason} ({found.expanded} states expanded)", file=sys.stderr)
        return 1
    print(f"// {len(found.ops)} steps, {found.expanded} states expanded")
    print(render(start, found.ops, args.name, Path(args.start).stem))
    return 0


def run() -> int:
    """``main`` with Ctrl-C said in one line (a long search is often stopped by hand)."""
    try:
        return main()
    except KeyboardInterrupt:
        print("plan_sequence: interrupted; no sequence printed", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(run())
