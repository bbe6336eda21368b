"""Single functional rooms: one kitchen, living room, bedroom or bathroom as a house of its own
(``generate_house(seed, room=TYPE)``, ``objsearch generate --room TYPE``).

The rooms of the paper's AI2-THOR experiment (30 rooms of each of four types), rebuilt with
``house-gen-2``'s room rules and stages:

* **Size.** The room's area is drawn from ``house-gen-2``'s range for its type
  (``gen2.floorplan.AREA_RANGES``: a kitchen 7-13 m^2, a living room 16-28, a bedroom 9-15, a
  bathroom 3.5-7.5); the room is a rectangle whose long side is ``ASPECT`` times its short
  one, the short one at least ``gen2.floorplan.MIN_WIDTH`` of its type (a bathroom
  ``BATHROOM_MIN_SIDE``, 1.8 m, as ``house-gen-2``'s narrowest), snapped to its 0.1 m grid.
* **No doors.** A closed room, as AI2-THOR's are (their doors are shut): no entrance.
* **Furnishing.** ``house-gen-2``'s stages after the doors (``gen2.build.spec_of_plan``:
  materials, walls, the groups of its type, the fill, the top-up to 0.4 objects per m^2),
  then more small objects (``gen2.furnish.SMALL``: on receptacles and walls) up to
  ``SMALL_DENSITY`` objects per m^2, as AI2-THOR's rooms are dense.
* **Recorded.** ``generator_version`` is ``house-gen-2``, ``size_class`` is ``ROOM_SIZE_CLASS``
  (``room``), ``extra`` is ``{"room": TYPE}`` (``HouseSpec.single_room``) and the house id
  ``<split>_<type>_<seed>`` (``train_kitchen_000003``), so rooms of different types never
  share an id. Seed, split, type and attempt give the same bytes.
* **Randomness.** ``numpy.random.default_rng([seed, attempt, split, STREAM, type])``: rooms are
  independent of the houses of the same seed and of each other.
* **Validation.** ``validate_house``'s compile, overlap, reachability and visibility checks,
  and ``check_rules``: one room of its type filling the footprint, no doors, and
  ``gen2.rules``' ``area`` and ``fill`` rules (the others are about circulation between rooms).
"""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING

from objsearch.errors import UserError
from objsearch.house.spec import HouseSpec, r4

if TYPE_CHECKING:  # the CLI reads ROOM_TYPES: numpy and the stages load only to build a room
    import numpy as np

    from objsearch.house.gen2.floorplan import Plan

#: The types a single room can be (the four of the paper's AI2-THOR rooms), in this order for
#: good: a type's index seeds its rooms.
ROOM_TYPES = ("kitchen", "living_room", "bedroom", "bathroom")
#: The ``size_class`` a single room's spec records (and ``HouseRef`` passes back).
ROOM_SIZE_CLASS = "room"
#: The generator whose room rules single rooms follow (the one they can be built with).
ROOM_GENERATOR = "house-gen-2"
STREAM = 3
ASPECT = (1.0, 1.6)
BATHROOM_MIN_SIDE = 1.8  # house-gen-2's narrowest bathroom; the other types: gen2.floorplan.MIN_WIDTH
#: Objects per m^2 the small objects top a room up to (``house-gen-2``: 0.4 in all).
SMALL_DENSITY = 1.0
RULES = ("room", "area", "fill")


def room_house_id(seed: int, split: str, room: str) -> str:
    """The id of the single room of ``seed``, ``split`` and type ``room``: ``train_kitchen_000003``."""
    return f"{split}_{room}_{seed:06d}"


def check_room_type(room: str) -> str:
    """``room`` if it is one of ``ROOM_TYPES``, else ``UserError`` naming it and the valid types."""
    if room not in ROOM_TYPES:
        raise UserError(f"unknown room type {room!r}; use one of {', '.join(ROOM_TYPES)}")
    return room


def room_builder(generator: str, room: str):
    """The ``build_spec(seed, size_class, split, attempt)`` of single rooms of type ``room``;
    ``UserError`` for an unknown type or a generator other than ``ROOM_GENERATOR``."""
    check_room_type(room)
    if generator != ROOM_GENERATOR:
        raise UserError(
            f"single rooms follow {ROOM_GENERATOR}'s room rules; generate them with --generator {ROOM_GENERATOR} "
            f"(not {generator})"
        )
    return partial(build_room_spec, room=room)


def room_plan(room: str, rng: np.random.Generator) -> Plan:
    """The floorplan of one room of type ``room``: a rectangle at the origin (see the module docstring)."""
    from objsearch.house.gen2.floorplan import AREA_RANGES, GRID, MIN_WIDTH, Plan

    min_side = BATHROOM_MIN_SIDE if room == "bathroom" else MIN_WIDTH[room]
    area = rng.uniform(*AREA_RANGES[room])
    aspect = rng.uniform(*ASPECT)
    short = r4(round(max(math.sqrt(area / aspect), min_side) / GRID) * GRID)
    long = r4(round(max(area / short, short) / GRID) * GRID)
    width, depth = (long, short) if rng.random() < 0.5 else (short, long)
    polygon = ((0.0, 0.0), (width, 0.0), (width, depth), (0.0, depth))
    return Plan(width, depth, [room], [polygon])


def build_room_spec(seed: int, size_class: str, split: str, attempt: int, room: str) -> HouseSpec:
    """Build the single room of type ``room`` once (``size_class`` is ``ROOM_SIZE_CLASS``);
    raises ``StageFailure`` when a rule of the stages cannot be met."""
    import numpy as np

    from objsearch.house.gen2.build import spec_of_plan
    from objsearch.house.stages import SPLITS

    rng = np.random.default_rng([seed, attempt, SPLITS[split], STREAM, ROOM_TYPES.index(room)])
    plan = room_plan(room, rng)
    return spec_of_plan(
        plan,
        [],
        rng,
        room_house_id(seed, split, room),
        seed,
        ROOM_SIZE_CLASS,
        split,
        attempt,
        small_density=SMALL_DENSITY,
        extra={"room": room},
    )


def check_rules(spec: HouseSpec) -> list[str]:
    """Every problem of the single room ``spec`` by ``RULES`` (``validate_house`` appends them)."""
    from objsearch.house.gen2.rules import rule_problems

    room = spec.single_room
    problems = []
    if len(spec.rooms) != 1 or spec.rooms[0].type != room:
        problems.append(f"room: a single {room} holds rooms {[r.type for r in spec.rooms]}")
    elif abs(spec.rooms[0].area - spec.footprint[0] * spec.footprint[1]) > 1e-6:
        problems.append(f"room: the {room} does not fill its {spec.footprint[0]} x {spec.footprint[1]} m footprint")
    if spec.doors:
        problems.append(f"room: a single room has no doors, this one has {len(spec.doors)}")
    found = rule_problems(spec)
    return problems + [f"{rule}: {msg}" for rule in RULES[1:] for msg in found[rule]]
