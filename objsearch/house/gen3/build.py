"""``build_spec`` of ``house-gen-3``: room program -> ``house-gen-2``'s floorplan (with this
version's limits) -> its doors and entrance -> walls, furniture and fill -> small targets
thinned to ``MAX_TARGET_INSTANCES`` per category.

Randomness: ``numpy.random.default_rng([seed, attempt, split, STREAM])``. Frozen once a suite
ships on it: a change that gives a seed another house is a new version.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import replace

import numpy as np

from objsearch.house.gen2.build import spec_of_plan
from objsearch.house.gen2.doors import place_doors
from objsearch.house.gen2.floorplan import AREA_LIMITS as GEN2_AREA_LIMITS
from objsearch.house.gen2.floorplan import plan_house
from objsearch.house.spec import HouseSpec
from objsearch.house.stages import ROOM_COUNT_CLASSES, SPLITS, WALL_THICKNESS, house_id

VERSION = "house-gen-3"
STREAM = 3
DEFAULT_SIZE_CLASS = "xlarge"
#: Rooms every house of 9 rooms or more has: a corridor, and repeated private room types.
LARGE_CORE = (
    "living_room",
    "kitchen",
    "bedroom",
    "bathroom",
    "hallway",
    "bedroom",
    "dining_room",
    "bathroom",
    "office",
)
EXTRA_WEIGHTS = {"bedroom": 3.0, "dining_room": 3.5, "office": 1.5, "bathroom": 1.5}
EXTRA_CAPS = {"bedroom": 5, "dining_room": 1, "office": 2, "bathroom": 3}
#: A private band this long (m) before rooms move across the corridor (``house-gen-2``: 13).
MAX_PRIVATE_RUN = 22.0
#: Target room areas (m^2): ``house-gen-2``'s times 1.3, the rooms of a large house.
AREA_RANGES = {
    "living_room": (20.8, 36.4),
    "kitchen": (9.1, 16.9),
    "dining_room": (13.0, 20.8),
    "bedroom": (11.7, 19.5),
    "office": (8.5, 13.0),
    "bathroom": (4.6, 9.8),
}
#: ``house-gen-2``'s limits with their upper ends times 1.3, and room for a long corridor.
AREA_LIMITS = {t: (lo, round(hi * 1.3, 1)) for t, (lo, hi) in GEN2_AREA_LIMITS.items()} | {"hallway": (2.5, 60.0)}
#: Small objects that are search targets of the large-house tier (10-40 cm; seen from close by).
SMALL_TARGETS = (
    "alarm_clock",
    "book",
    "bottle",
    "candle",
    "cup",
    "fruit_bowl",
    "kettle",
    "laptop",
    "plate",
    "pot",
    "remote_control",
    "soap",
    "toilet_paper",
    "vase",
)
MAX_TARGET_INSTANCES = 1


def default_size_class(seed: int) -> str:
    """The size class of a seed given none: ``xlarge`` (9-14 rooms, drawn in ``build_spec``)."""
    return DEFAULT_SIZE_CLASS


def room_program(num_rooms: int, rng: np.random.Generator) -> list[str]:
    """The room types of a house of ``num_rooms`` (4-14) rooms: ``house-gen-2``'s program below 9
    rooms (a hallway and a second bedroom from 6), ``LARGE_CORE`` from 9, then extras by weight."""
    if num_rooms >= len(LARGE_CORE):
        types = list(LARGE_CORE)
    else:
        types = ["living_room", "kitchen", "bedroom", "bathroom"] + (["hallway", "bedroom"] if num_rooms >= 6 else [])
    while len(types) < num_rooms:
        options = [t for t in EXTRA_WEIGHTS if types.count(t) < EXTRA_CAPS[t]]
        w = np.array([EXTRA_WEIGHTS[t] for t in options])
        types.append(options[int(rng.choice(len(options), p=w / w.sum()))])
    return types


def thin_targets(spec: HouseSpec, rng: np.random.Generator) -> HouseSpec:
    """``spec`` with at most ``MAX_TARGET_INSTANCES`` objects of each ``SMALL_TARGETS`` category,
    the ones kept drawn uniformly (small targets hold nothing, so no other object moves)."""
    by_cat: dict[str, list[str]] = defaultdict(list)
    for o in spec.objects:
        if o.category in SMALL_TARGETS:
            by_cat[o.category].append(o.name)
    drop = set()
    for cat in sorted(by_cat):
        names = by_cat[cat]
        if len(names) > MAX_TARGET_INSTANCES:
            keep = set(rng.choice(len(names), size=MAX_TARGET_INSTANCES, replace=False).tolist())
            drop |= {n for k, n in enumerate(names) if k not in keep}
    return replace(spec, objects=tuple(o for o in spec.objects if o.name not in drop))


def build_spec(seed: int, size_class: str, split: str, attempt: int) -> HouseSpec:
    """Run the ``house-gen-3`` stages once; raises ``StageFailure`` when a rule cannot be met."""
    rng = np.random.default_rng([seed, attempt, SPLITS[split], STREAM])
    lo, hi = ROOM_COUNT_CLASSES[size_class]
    types = room_program(int(rng.integers(lo, hi + 1)), rng)
    plan = plan_house(types, rng, MAX_PRIVATE_RUN, AREA_LIMITS, AREA_RANGES)
    doors = place_doors(plan, rng, WALL_THICKNESS)
    spec = spec_of_plan(plan, doors, rng, house_id(seed, split), seed, size_class, split, attempt, version=VERSION)
    return thin_targets(spec, rng)
