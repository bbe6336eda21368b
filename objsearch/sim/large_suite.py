"""The large-house tier: ``house-large``, ``house-large-roomwise`` and ``house-large-shuffled``.

Search in houses where it decides (``docs/large_houses.md``):

* **Houses.** ``house-gen-3`` houses of 9-14 rooms (size class ``xlarge``): ``TRAIN_COUNT``
  training houses (listed, no episodes), ``VAL_COUNT`` validation and ``TEST_COUNT`` test houses
  (generated as split ``test``: unseen object instances), the first seeds of ``TRAIN_SEEDS``,
  ``VAL_SEEDS`` and ``TEST_SEEDS`` whose house is valid in all three placements
  (``PLACEMENTS``; a roomwise or shuffled house that finds no valid arrangement skips the seed).
  The three suites have the same seeds; only the places of the objects differ.
* **Targets.** Small objects (``house-gen-3``'s ``SMALL_TARGETS``: a cup, a book, an alarm
  clock, ...), at most one of each per house, seen only from close by at the agent camera's
  64 x 64: those with goal poses in at least half of the evaluation houses in every placement.
* **Success.** The ObjectNav protocol (STOP at a goal pose, 500 steps) with the tier's goal
  rule ``RULE``: at least 5 target pixels of the 64 x 64 goal camera nearer than 1 m (a 10 cm
  cup 1 m away covers 5-15 of them; the 20 of ``house-gen-v2-objectnav`` are for furniture).
* **Episodes.** ``EPISODES`` per split (``val``, ``test``), played with the one seed ``SEEDS``
  (the file's standard seeds), the same in all three suites: a
  uniform house, a uniform target it has in every placement, and a start drawn uniformly
  among the poses that, in every placement, are free, reach the target's goal poses, lie at
  least ``MIN_GEODESIC`` metres (walking) from the nearest goal pose, and lie in a room at
  least ``MIN_ROOM_HOPS`` doors from every room that holds the target. Each file records its
  own goal poses and ``min_steps`` (the STOP included), and every episode's ``geodesic``
  distance (m, in that file's placement) for results by distance bin.

``build_large_suites`` makes the three files at once (``objsearch suite rebuild house-large``
builds the one asked for the same way). Rendering: the goal camera's cache of every
evaluation house in every placement (``objsearch.sim.cache``; about 10 s and 160 MB a house).
"""

from __future__ import annotations

from collections import deque
from dataclasses import replace
from functools import lru_cache

import numpy as np

from objsearch.house.gen3.build import SMALL_TARGETS
from objsearch.house.spec import OUTSIDE, HouseSpec
from objsearch.house.validate import validate_house
from objsearch.sim.goals import PROTOCOLS, GoalRule
from objsearch.sim.world import HouseRef, World

GENERATOR = "house-gen-3"
SIZE_CLASS = "xlarge"
#: The suites of the tier by the placement of their houses' objects (the first is the base).
PLACEMENTS = {"house-large": "functional", "house-large-roomwise": "roomwise", "house-large-shuffled": "shuffled"}
TRAIN_SEEDS, VAL_SEEDS, TEST_SEEDS = range(1000, 1200), range(2000, 2100), range(3000, 3100)
TRAIN_COUNT, VAL_COUNT, TEST_COUNT = 60, 5, 10
RULE = GoalRule(kind="near_visible", min_pixels=5, max_distance=1.0)
PROTOCOL = replace(PROTOCOLS["objectnav"], goal_rule=RULE)
EPISODES = {"val": 100, "test": 200}
#: The standard seeds (the file's ``seeds``): one; 300 long episodes carry the statistics, and the
#: paper's five would make a 20-minute evaluation of ``frontier`` on one core 100 minutes.
SEEDS = (1,)
MIN_GEODESIC = 8.0
MIN_ROOM_HOPS = 2
BUILD_SEED = 40


def house_ref(seed: int, split: str, placement: str) -> HouseRef:
    """The reference of the tier's house of ``seed`` in generator split ``split`` and ``placement``."""
    return HouseRef(
        seed=seed,
        split=split,
        size_class=SIZE_CLASS,
        generator=GENERATOR,
        placement=None if placement == "functional" else placement,
    )


def _valid_worlds(seed: int, split: str) -> dict[str, World] | None:
    """The house of ``seed`` in every placement (by placement), or None if one is not valid."""
    from objsearch.house.generate import HouseGenerationError

    worlds = {}
    for placement in PLACEMENTS.values():
        try:
            world = World.load(house_ref(seed, split, placement))
        except HouseGenerationError:
            return None
        if not validate_house(world.spec, world.model).ok:
            return None
        worlds[placement] = world
    return worlds


def pick_houses(seeds: range, split: str, count: int) -> list[dict[str, World]]:
    """The first ``count`` seeds of ``seeds`` valid in every placement, each as ``{placement: World}``."""
    picked = []
    for seed in seeds:
        worlds = _valid_worlds(seed, split)
        if worlds is not None:
            picked.append(worlds)
            if len(picked) == count:
                return picked
    raise RuntimeError(f"only {len(picked)} of {count} valid {GENERATOR} houses among seeds {seeds}")


def room_hops(spec: HouseSpec) -> np.ndarray:
    """Doors between every pair of rooms (int (R, R), by room id; -1: not connected), the entrance ignored."""
    n = len(spec.rooms)
    neighbours: list[list[int]] = [[] for _ in range(n)]
    for door in spec.doors:
        a, b = door.rooms
        if OUTSIDE not in (a, b):
            neighbours[a].append(b)
            neighbours[b].append(a)
    hops = np.full((n, n), -1, dtype=np.int64)
    for start in range(n):
        hops[start, start] = 0
        todo = deque([start])
        while todo:
            room = todo.popleft()
            for nxt in neighbours[room]:
                if hops[start, nxt] < 0:
                    hops[start, nxt] = hops[start, room] + 1
                    todo.append(nxt)
    return hops


class _Placed:
    """One placement of one house: its world, goal poses by target, and what starts need."""

    def __init__(self, world: World, goal_ids: dict[str, np.ndarray]):
        self.world, self.goal_ids = world, goal_ids
        self.rooms = np.repeat(world.cell_rooms, 4)  # the room of every pose
        self.hops = room_hops(world.spec)
        self._tables: dict[str, tuple[np.ndarray, np.ndarray]] = {}

    def pose_ids(self, tuples: np.ndarray) -> np.ndarray:
        """Pose ids of (row, col, heading) rows in this placement's graph (-1 where the cell is not free)."""
        graph = self.world.graph
        cell = graph.cell_index[tuples[:, 0], tuples[:, 1]]
        return np.where(cell >= 0, cell * 4 + tuples[:, 2], -1)

    def steps_and_metres(self, target: str) -> tuple[np.ndarray, np.ndarray]:
        """Minimal moves and walking metres from every pose to the target's goal poses."""
        if target not in self._tables:
            graph, goals = self.world.graph, self.goal_ids[target]
            self._tables[target] = (graph.shortest_steps(goals), graph.geodesic_metres(goals))
        return self._tables[target]

    def start_ok(self, target: str, ids: np.ndarray) -> np.ndarray:
        """Which of the poses ``ids`` (-1: not free here) may start an episode for ``target``."""
        steps, metres = self.steps_and_metres(target)
        free = ids >= 0
        safe = np.where(free, ids, 0)
        holders = sorted({o.room for o in self.world.spec.objects if o.category == target})
        room = self.rooms[safe]
        hops = self.hops[np.maximum(room, 0)][:, holders]  # doors to each room holding the target
        far_rooms = (room >= 0) & np.all((hops >= MIN_ROOM_HOPS) | (hops < 0), axis=1)
        return free & (steps[safe] >= 0) & (metres[safe] >= MIN_GEODESIC) & far_rooms


def _small_targets_in_half(placed: dict[str, _Placed]) -> set[str]:
    """The small targets with goal poses in at least half of the houses of ``placed``."""
    return {t for t in SMALL_TARGETS if sum(t in here.goal_ids for here in placed.values()) >= len(placed) / 2}


@lru_cache(maxsize=1)
def build_large_suites(cache_dir: str | None = None) -> dict[str, dict]:
    """The three suite files of the tier (by name), built together from their fixed seeds (the
    module docstring); once a process (``objsearch suite rebuild`` of the three names builds once)."""
    from objsearch.sim.suite_build import _goal_ids, _suite_record, house_entry

    groups = {
        "train": pick_houses(TRAIN_SEEDS, "train", TRAIN_COUNT),
        "val": pick_houses(VAL_SEEDS, "test", VAL_COUNT),
        "test": pick_houses(TEST_SEEDS, "test", TEST_COUNT),
    }
    placed: dict[str, dict[str, _Placed]] = {p: {} for p in PLACEMENTS.values()}  # placement -> house -> _Placed
    for part in ("val", "test"):
        for worlds in groups[part]:
            for placement, world in worlds.items():
                placed[placement][world.house_id] = _Placed(world, _goal_ids(world, SMALL_TARGETS, cache_dir, RULE))
    targets = sorted(set.intersection(*(_small_targets_in_half(placed[p]) for p in placed)))
    rng = np.random.default_rng(BUILD_SEED)
    # the start candidates: every pose of a house's functional graph, and where each is in every placement
    tuples = {h: np.array(here.world.graph.pose_tuples, dtype=np.int64) for h, here in placed["functional"].items()}
    pose_ids = {(p, h): placed[p][h].pose_ids(tuples[h]) for p in placed for h in tuples}
    starts_of: dict[tuple[str, str], np.ndarray] = {}  # (house, target) -> candidates that may start its episodes
    episodes = {p: {} for p in placed}
    for part in ("val", "test"):
        ids = sorted(w["functional"].house_id for w in groups[part])
        for p in placed:
            episodes[p][part] = []
        while len(episodes["functional"][part]) < EPISODES[part]:
            house = ids[int(rng.integers(len(ids)))]
            have = [t for t in targets if all(t in placed[p][house].goal_ids for p in placed)]
            if not have:
                continue
            target = have[int(rng.integers(len(have)))]
            if (house, target) not in starts_of:
                ok = np.ones(len(tuples[house]), dtype=bool)
                for p in placed:
                    ok &= placed[p][house].start_ok(target, pose_ids[p, house])
                starts_of[house, target] = np.flatnonzero(ok)
            starts = starts_of[house, target]
            if len(starts) == 0:
                continue
            k = int(starts[rng.integers(len(starts))])
            start = tuples[house][k]
            for p in placed:
                pose = int(pose_ids[p, house][k])
                steps, metres = placed[p][house].steps_and_metres(target)
                episodes[p][part].append(
                    {
                        "house": house,
                        "start": [int(v) for v in start],
                        "target": target,
                        "min_steps": int(steps[pose]) + PROTOCOL.stop,
                        "geodesic": float(metres[pose]),
                    }
                )
    out = {}
    for name, p in PLACEMENTS.items():
        entry = {
            part: {
                w[p].house_id: house_entry(w[p], house_ref(w[p].spec.seed, w[p].spec.split, p)) for w in groups[part]
            }
            for part in groups
        }
        goals = {
            house: {
                t: [list(here.world.graph.pose_of(int(g))) for g in here.goal_ids[t]]
                for t in targets
                if t in here.goal_ids
            }
            for house, here in placed[p].items()
        }
        out[name] = _suite_record(
            name,
            f"{name}-v1",
            {"targets": targets},
            {**entry["val"], **entry["test"]},
            entry["train"],
            goals,
            episodes[p],
            PROTOCOL,
            start_steps=_steps_range(episodes[p]),
            seeds=SEEDS,
        )
    return out


def _steps_range(splits: dict[str, list[dict]]) -> tuple[int, int]:
    """The fewest and most moves of the drawn starts from their goals (the file's ``start_steps``)."""
    moves = [e["min_steps"] - PROTOCOL.stop for items in splits.values() for e in items]
    return min(moves), max(moves)
