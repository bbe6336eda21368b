"""``objsearch generate``: write procedurally generated MuJoCo houses.

Writes ``OUT/<house_id>/`` for seeds S .. S+N-1: ``house.xml`` (compiles in MuJoCo; meshes
under ``meshes/`` beside it), ``spec.json`` (the HouseSpec) and ``preview.png``, plus
``OUT/categories.json`` (the segmentation category table).

``--generator``: ``house-gen-2`` (the default: zoned floorplans with corridors and an
entrance) or ``house-gen-1`` (the generator of house-single, house-multi and house-gen).

``--room TYPE`` builds single rooms instead of houses (``objsearch.house.rooms``): one
kitchen, living_room, bedroom or bathroom each, sized and furnished by ``house-gen-2``'s room
rules, without doors, with more small objects (``OUT/<split>_<type>_<seed>/``).

``--generator house-gen-3`` builds large houses (9-14 rooms, 150-250 m^2, a long corridor,
repeated bedrooms and bathrooms, each small target at most once); ``--rooms N`` (4-14) fixes
the number of rooms, the tier's size knob.

A house folder is named by split and seed (``train_000042``), so houses of other generators,
placements or sizes go in another ``--out``: a folder holding another house is replaced only
with ``--overwrite``, one holding files objsearch did not write never.

``--placement shuffled`` builds the same houses (floorplan, rooms, objects) with every object
moved to a random place anywhere in the house, whatever the functional groups and room
priors say; ``--placement roomwise`` moves every object to a random place in a room of its
room's type (``objsearch.house.shuffle``): houses whose object relations are broken, room
priors kept.
"""

from __future__ import annotations

import argparse
import sys

from objsearch.cliargs import non_negative_int, positive_int
from objsearch.errors import UserError
from objsearch.house.generators import GENERATORS, get_generator
from objsearch.house.rooms import ROOM_TYPES, room_builder
from objsearch.house.spec import DEFAULT_GENERATOR, HOUSE_PLACEMENTS
from objsearch.house.stages import ROOM_COUNT_CLASSES, SIZE_CLASSES


def size_class_arg(text: str) -> str:
    """``--rooms``: a size class name, or a number of rooms N as the class ``rooms-N`` (house-gen-3)."""
    if text.isdigit():
        if f"rooms-{int(text)}" not in ROOM_COUNT_CLASSES:
            raise argparse.ArgumentTypeError(f"{text} rooms: house-gen-3 builds 4 to 14 rooms")
        return f"rooms-{int(text)}"
    if text not in SIZE_CLASSES and text not in ROOM_COUNT_CLASSES:
        raise argparse.ArgumentTypeError(f"{text!r}: use small, medium, large, xlarge or a number of rooms (4-14)")
    return text


def add_parser(subparsers) -> None:
    """Add ``objsearch generate`` to ``subparsers``."""
    p = subparsers.add_parser(
        "generate",
        help="generate MuJoCo houses (house.xml, spec.json, preview.png)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--seed", type=non_negative_int, default=0, help="first seed (default: 0)")
    p.add_argument("--num", type=positive_int, default=1, help="number of houses, seeds S..S+N-1 (default: 1)")
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument(
        "--rooms",
        type=size_class_arg,
        help="size class: small, medium or large (3-4, 4-6 or 6-9 rooms; default: drawn per seed); house-gen-3: "
        "a number of rooms, 4-14 (its size knob), or xlarge (9-14 rooms drawn per house, its default)",
    )
    p.add_argument(
        "--room",
        metavar="TYPE",
        help=f"build single rooms of this type instead of houses: one of {', '.join(ROOM_TYPES)} "
        "(house-gen-2's room rules, no doors, dense in small objects)",
    )
    p.add_argument(
        "--split", choices=("train", "test"), default="train", help="test houses use the reserved mesh variants"
    )
    p.add_argument(
        "--generator",
        choices=GENERATORS,
        default=DEFAULT_GENERATOR,
        help=f"generator version (default: {DEFAULT_GENERATOR}: zoned floorplans with corridors, L-shaped rooms, "
        "an entrance and fill that follows room area; house-gen-1: the older layouts of house-single, house-multi "
        "and house-gen, rooms cut from a rectangle, no entrance; house-gen-3: large houses, one hallway; house-gen-4: "
        "large houses in floorplan families, L, T, U, two hallways, open plans)",
    )
    p.add_argument(
        "--placement",
        choices=HOUSE_PLACEMENTS,
        default="functional",
        help="where objects go: functional (default: in functional groups, by room priors), shuffled (the "
        "functional house's objects, each moved to a random place anywhere in the house) or roomwise (each moved "
        "to a random place in a room of its room's type); anywhere-P, roomwise-P (P = 25, 50, 75, 100): the fidelity "
        "dial, a share P%% of the objects moved anywhere or within room types",
    )
    p.add_argument(
        "--overwrite",
        action="store_true",
        help="replace a house folder of the same name holding another house (another generator, placement or "
        "size; default: refuse); a folder holding files objsearch did not write is never replaced",
    )
    p.add_argument("--no-preview", action="store_true", help="skip preview.png")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """``objsearch generate``: write ``--num`` houses from ``--seed`` on; ``UserError`` listing those that failed."""
    from objsearch.fileio import check_writable, write_json
    from objsearch.house.categories import category_table
    from objsearch.house.generate import HouseGenerationError, generate_house, write_house
    from objsearch.progress import progress_bar

    if args.room is not None:
        room_builder(args.generator, args.room)  # an unknown type, or house-gen-1: exit 2 before writing
        if args.rooms is not None:
            raise UserError(
                f"--rooms (a house's size class) and --room (single rooms) exclude each other; drop --rooms {args.rooms}"
            )
    if args.rooms is not None and args.room is None and args.rooms not in get_generator(args.generator).size_classes:
        raise UserError(
            f"{args.generator} has no size --rooms {args.rooms.removeprefix('rooms-')}; use one of "
            f"{', '.join(c.removeprefix('rooms-') for c in get_generator(args.generator).size_classes)}"
        )
    check_writable(args.out, "--out", folder=True)
    _precheck(args)
    write_json(f"{args.out}/categories.json", category_table(), elsewhere="choose another --out")
    failed = []
    bar = progress_bar(args.num, "houses", "house", not args.quiet and args.num > 1)
    seed = args.seed
    try:
        for seed in range(args.seed, args.seed + args.num):
            try:
                house = generate_house(
                    seed, args.rooms, args.split, generator=args.generator, placement=args.placement, room=args.room
                )
            except HouseGenerationError as err:
                failed.append(str(err))
                bar.update()
                continue
            path = write_house(house, args.out, preview=not args.no_preview, overwrite=args.overwrite)
            bar.update()
            if args.num == 1 and not args.quiet:
                print(f"wrote {path}", file=sys.stderr)
    except KeyboardInterrupt as err:  # Ctrl-C or SIGTERM: whole houses only (write_house)
        rest = args.seed + args.num - seed
        raise type(err)(
            f"{seed - args.seed} of {args.num} seeds done in {args.out}; "
            f"the rest: rerun with --seed {seed} --num {rest}"
        ) from None
    finally:
        bar.close()
    if failed:
        raise UserError(f"{len(failed)} of {args.num} houses failed validation:\n" + "\n".join(failed))
    if not args.quiet:
        print(f"{args.num} house(s) written to {args.out}", file=sys.stderr)
    return 0


def _precheck(args: argparse.Namespace) -> None:
    """Refuse, before any house is generated, a folder of ``--out`` that holds a house of another
    generator, placement, size or room than asked (``house_folder.precheck``; without ``--overwrite``)."""
    from pathlib import Path

    from objsearch.house.house_folder import precheck
    from objsearch.house.rooms import room_house_id
    from objsearch.house.stages import house_id

    wanted = {"generator_version": args.generator, "placement": args.placement, "room": args.room}
    if args.rooms is not None:
        wanted["size_class"] = args.rooms
    for seed in range(args.seed, args.seed + args.num):
        name = room_house_id(seed, args.split, args.room) if args.room else house_id(seed, args.split)
        precheck(Path(args.out) / name, wanted, args.overwrite)
