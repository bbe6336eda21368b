"""The ``rooms`` suite: the paper's AI2-THOR experiment (its Table 4) in single functional rooms.

The authors' protocol (their AI2-THOR code, summarised in ``docs/rooms.md``), translated to our
rooms (``objsearch.house.rooms``, ``HouseRef(seed, room=TYPE)``):

* **Rooms.** 30 of each type (``ROOM_TYPES``): 20 training rooms (seeds ``TRAIN_SEEDS``, generated
  as split ``train``), 5 validation and 5 test rooms (``VAL_SEEDS``, ``TEST_SEEDS``, generated as
  split ``test``: unseen object instances, as ``house-gen``'s evaluation houses). "Seen env" is
  the training rooms, "unseen env" the 10 validation and test rooms together. Every room is an
  evaluation house of the file (seen-env episodes play in the training rooms); the training
  rooms are also its ``training_houses``.
* **Goals.** The authors' seen and unseen goals of each room type (``AUTHORS_GOALS``), each
  mapped onto our category table (its nearest counterpart, or none). A mapped goal counts for
  a room type if it has goal poses, and starts that do not see it, in at least ``FOUND_IN`` of
  the type's training rooms and ``FOUND_IN`` of its unseen rooms. The file records the goals by
  type (``categories``: ``<type>-seen``, ``<type>-unseen``) and their unions (``seen``,
  ``unseen``: "unseen" holds only within a room type, as the authors' painting is seen in
  bedrooms and unseen in living rooms).
* **Episodes.** ``EPISODES_PER_ROOM_TYPE`` per room type in each of the four ``SPLITS``, drawn
  as the authors' ``random_walk.py`` drew theirs: a uniform room of the split's rooms of that
  type, a uniform target of the split's goals present in it (again while it has none), then a
  uniform start among the poses that do not see the target (no pixel of it in the goal
  camera's frame) and reach its goal poses; no minimal-steps floor (``START_STEPS``' 6 would
  not fit in bathrooms, whose starts are 1-6 steps from the goal). Every start is at least 1
  step from success.
* **Step limits.** 100 steps, 200 in living rooms (``ROOM_MAX_STEPS``, the file's
  ``room_max_steps``; its ``max_steps`` is their largest, the cap); no STOP: an episode succeeds
  on reaching a goal pose (the paper protocol and its goal rule).

``build_rooms_suite`` makes the file (``objsearch suite rebuild rooms``).
"""

from __future__ import annotations

import numpy as np

from objsearch.house.categories import CATEGORY_IDS
from objsearch.house.rooms import ROOM_TYPES
from objsearch.sim.goals import GOAL_CAMERA, PROTOCOLS, goal_poses
from objsearch.sim.suite_record import _suite_record, house_entry
from objsearch.sim.world import HouseRef, World

TRAIN_SEEDS = range(1000, 1020)
VAL_SEEDS = range(2000, 2005)
TEST_SEEDS = range(3000, 3005)
EPISODES_PER_ROOM_TYPE = 250
SPLITS = ("seen-env-seen-goals", "seen-env-unseen-goals", "unseen-env-seen-goals", "unseen-env-unseen-goals")
ROOM_MAX_STEPS = {"kitchen": 100, "living_room": 200, "bedroom": 100, "bathroom": 100}
FOUND_IN = 2  # a goal counts for a room type if found in this many of its training rooms and of its unseen rooms
START_RANGE = (1, max(ROOM_MAX_STEPS.values()))  # what the file records as start_steps: not visible, in the limit

# The authors' seen and unseen goals per room type (utils/constant.py), each with its counterpart
# in our category table (None: none near enough). Where two of theirs would share one of ours
# across the seen and unseen lists, the unseen goal keeps it. docs/rooms.md gives the reasons.
# fmt: off
AUTHORS_GOALS = {
    "kitchen": {
        "seen": (
            ("HousePlant", "plant"), ("StoveKnob", "stove"), ("Sink", "kitchen_sink"), ("TableTop", "counter"),
            ("Potato", None), ("Bread", None), ("Tomato", None), ("Knife", None), ("Cabinet", "counter"),
            ("Fridge", "fridge"), ("Container", "bottle"), ("ButterKnife", None), ("Lettuce", None), ("Pan", "pot"),
            ("Bowl", None), ("CoffeeMachine", "kettle"), ("StoveBurner", "stove"), ("Plate", "plate"),
        ),
        "unseen": (("Mug", "cup"), ("Apple", "fruit_bowl"), ("Microwave", "microwave"), ("Toaster", "toaster")),
    },
    "living_room": {
        "seen": (
            ("Television", "tv"), ("HousePlant", "plant"), ("Chair", "armchair"), ("TableTop", "coffee_table"),
            ("Box", None), ("Cloth", None), ("Newspaper", "book"), ("KeyChain", "remote_control"),
            ("WateringCan", None), ("PaintingHanger", None),
        ),
        "unseen": (("Painting", "painting"), ("Statue", "vase")),
    },
    "bedroom": {
        "seen": (
            ("Painting", "painting"), ("HousePlant", "plant"), ("CellPhone", None), ("LightSwitch", None),
            ("Candle", "candle"), ("TableTop", "nightstand"), ("Bed", "bed"), ("Lamp", "table_lamp"),
            ("Statue", "vase"), ("Book", "book"), ("CreditCard", None), ("KeyChain", "remote_control"),
            ("Bowl", "fruit_bowl"), ("Pen", None), ("Box", None), ("Pencil", None), ("Blinds", None),
            ("Laptop", "laptop"), ("AlarmClock", "alarm_clock"),
        ),
        "unseen": (("Television", "tv"), ("Mirror", "mirror"), ("Cabinet", "dresser")),
    },
    "bathroom": {
        "seen": (
            ("SprayBottle", None), ("Painting", "painting"), ("Candle", "candle"), ("LightSwitch", None),
            ("Sink", "sink"), ("Cabinet", "sink"), ("TowelHolder", None), ("Watch", None),
            ("ToiletPaper", "toilet_paper"), ("ShowerDoor", "bathtub"), ("SoapBottle", None),
        ),
        "unseen": (("SoapBar", "soap"), ("Towel", "towel")),
    },
}
# fmt: on
KINDS = ("seen", "unseen")


def mapped_goals(room: str, kind: str) -> list[str]:
    """Our categories of the authors' ``kind`` (seen or unseen) goals of room type ``room``, sorted."""
    return sorted({ours for _, ours in AUTHORS_GOALS[room][kind] if ours is not None})


def room_refs() -> dict[str, dict[str, list[HouseRef]]]:
    """The suite's rooms: room type -> ``train``, ``val``, ``test`` -> their ``HouseRef``s."""
    gen = "house-gen-2"
    return {
        room: {
            "train": [HouseRef(seed=s, generator=gen, room=room) for s in TRAIN_SEEDS],
            "val": [HouseRef(seed=s, split="test", generator=gen, room=room) for s in VAL_SEEDS],
            "test": [HouseRef(seed=s, split="test", generator=gen, room=room) for s in TEST_SEEDS],
        }
        for room in ROOM_TYPES
    }


def start_candidates(world: World, targets, cache_dir=None) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """For each of ``targets`` with goal poses in ``world`` (the paper's goal rule) and starts:
    (goal pose ids, start pose ids: the poses that do not see it, no pixel in the goal camera's
    frame, and reach a goal pose within the room's step limit), with the minimal steps of every pose."""
    from objsearch.sim.cache import HouseCache

    cache = HouseCache.open(world, GOAL_CAMERA, cache_dir, progress=False)
    semantic, depth = np.asarray(cache.semantic), np.asarray(cache.depth)
    limit = ROOM_MAX_STEPS[world.spec.single_room]
    out = {}
    for target in targets:
        hits = semantic == CATEGORY_IDS[target]
        goals = goal_poses(semantic, depth, CATEGORY_IDS[target], PROTOCOLS["paper"].goal_rule)
        if not len(goals):
            continue
        dist = world.graph.shortest_steps(goals)
        seen = hits.reshape(len(hits), -1).any(axis=1)
        starts = np.flatnonzero(~seen & (dist >= 1) & (dist <= limit))
        if len(starts):
            out[target] = (goals, starts, dist)
    return out


def build_rooms_suite(name: str, version: str, rng: np.random.Generator, cache_dir=None) -> dict:
    """The ``rooms`` suite file's content (see the module docstring), drawn with ``rng``; renders
    the goal camera's frames of every pose of every room (into the cache)."""
    refs = room_refs()
    houses, training, tables, worlds, sets = {}, {}, {}, {}, {}
    for room in ROOM_TYPES:
        wanted = sorted(set(mapped_goals(room, "seen")) | set(mapped_goals(room, "unseen")))
        for part in ("train", "val", "test"):
            for ref in refs[room][part]:
                world = World.load(ref)
                worlds[world.house_id] = world
                houses[world.house_id] = house_entry(world, ref)
                if part == "train":
                    training[world.house_id] = houses[world.house_id]
                tables[world.house_id] = start_candidates(world, wanted, cache_dir)
                sets.setdefault((room, "seen" if part == "train" else "unseen"), []).append(world.house_id)
    categories = {}
    for room in ROOM_TYPES:
        for kind in KINDS:
            categories[f"{room}-{kind}"] = [
                t
                for t in mapped_goals(room, kind)
                if all(sum(t in tables[h] for h in sets[room, env]) >= FOUND_IN for env in KINDS)
            ]
            if not categories[f"{room}-{kind}"]:
                raise RuntimeError(f"no {kind} goal of {room}s is found in {FOUND_IN} rooms of each set")
    categories = {
        "seen": sorted({t for room in ROOM_TYPES for t in categories[f"{room}-seen"]}),
        "unseen": sorted({t for room in ROOM_TYPES for t in categories[f"{room}-unseen"]}),
        **categories,
    }
    goals = {}
    for house, table in tables.items():
        room = worlds[house].spec.single_room
        counted = set(categories[f"{room}-seen"]) | set(categories[f"{room}-unseen"])
        graph = worlds[house].graph
        goals[house] = {t: [list(graph.pose_of(int(g))) for g in table[t][0]] for t in sorted(table) if t in counted}
    splits = {}
    for split in SPLITS:
        env, _, kind = split.partition("-env-")
        kind = kind.removesuffix("-goals")
        splits[split] = []
        for room in ROOM_TYPES:
            rooms, targets = sets[room, env], categories[f"{room}-{kind}"]
            drawn = 0
            while drawn < EPISODES_PER_ROOM_TYPE:
                house = rooms[rng.integers(len(rooms))]
                present = [t for t in targets if t in goals[house]]
                if not present:
                    continue  # a room without the split's goals: draw another
                target = present[rng.integers(len(present))]
                _, starts, dist = tables[house][target]
                start = int(starts[rng.integers(len(starts))])
                splits[split].append(
                    {
                        "house": house,
                        "start": list(worlds[house].graph.pose_of(start)),
                        "target": target,
                        "min_steps": int(dist[start]),
                    }
                )
                drawn += 1
    return _suite_record(
        name,
        version,
        categories,
        houses,
        training,
        goals,
        splits,
        starts="not_visible",
        max_steps=max(ROOM_MAX_STEPS.values()),
        start_steps=START_RANGE,
        room_max_steps=ROOM_MAX_STEPS,
    )
