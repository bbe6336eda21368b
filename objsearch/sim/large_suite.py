"""The large-house tier (``house-large``, ``house-large-roomwise``, ``house-large-shuffled``) and
its size sweep (``house-size-N`` and ``house-size-N-shuffled`` for N = 4, 7, 10, 14 rooms).

Search in houses where it decides (``docs/large_houses.md``). A ``Tier`` is a family of suites
drawn together, one per placement of the objects (``LARGE``, ``SWEEP``):

* **Houses.** ``house-gen-3`` houses of the tier's size class (``LARGE``: ``xlarge``, 9-14
  rooms): training houses (listed, no episodes), validation and test houses (generated as split
  ``test``: unseen object instances), the first seeds of the tier's seed ranges whose house is
  valid in all its placements (a roomwise or shuffled house that finds no valid arrangement
  skips the seed). A tier's suites have the same seeds; only the places of the objects differ.
* **Targets.** Small objects (``house-gen-3``'s ``SMALL_TARGETS``: a cup, a book, an alarm
  clock, ...), at most one of each per house, seen only from close by at the agent camera's
  64 x 64: those with goal poses in at least half of the evaluation houses in every placement (the
  sweep: six targets, each drawn in every house that has it).
* **Success.** The ObjectNav protocol (STOP at a goal pose, 500 steps) with the tier's goal
  rule ``RULE``: at least 5 target pixels of the 64 x 64 goal camera nearer than 1 m (a 10 cm
  cup 1 m away covers 5-15 of them; the 20 of ``house-gen-v2-objectnav`` are for furniture).
* **Episodes.** ``Tier.episodes`` per split, played with the one seed ``Tier.seeds_played``
  (the file's standard seeds), the same in all the tier's suites: a
  uniform house, a uniform target it has in every placement, and a start drawn uniformly
  among the poses that, in every placement, are free, reach the target's goal poses, lie at
  least ``Tier.min_geodesic`` metres (walking) from the nearest goal pose, and lie in a room at
  least ``Tier.min_room_hops`` doors from every room that holds the target. Each file records its
  own goal poses and ``min_steps`` (the STOP included), and every episode's ``geodesic``
  distance (m, in that file's placement) for results by distance bin.

``build_tier_suite`` makes a tier's files at once (``objsearch suite rebuild house-large``
builds the one asked for the same way). Rendering: the goal camera's cache of every
evaluation house in every placement (``objsearch.sim.cache``; about 10 s and 160 MB a house).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from objsearch.house.gen3.build import SMALL_TARGETS
from objsearch.house.validate import validate_house
from objsearch.sim.goals import PROTOCOLS, GoalRule
from objsearch.sim.start_rules import far_starts, room_hops
from objsearch.sim.world import HouseRef, World

RULE = GoalRule(kind="near_visible", min_pixels=5, max_distance=1.0)
PROTOCOL = replace(PROTOCOLS["objectnav"], goal_rule=RULE)


@dataclass(frozen=True)
class Tier:
    """A family of suites built together: the same houses, starts and targets, one suite per
    placement of the houses' objects (the module docstring).

    Attributes:
        placements: the suite names and their placement, the base (``functional``) first.
        size_class: the ``house-gen-3`` size class of the houses.
        seeds: the generator seeds tried, in order, for each part (``train``, ``val``, ``test``).
        counts: the houses of each part (``train``: listed, no episodes).
        episodes: the episodes of each evaluation split.
        min_geodesic: the fewest walking metres from a start to the nearest goal pose.
        min_room_hops: the fewest doors from a start's room to every room holding the target.
        build_seed: the seed of the draws.
        seeds_played: the standard seeds (the file's ``seeds``).
        targets: the small targets it may draw (None: all); of these, those with goal poses in
            at least ``target_share`` of the evaluation houses (and one) in every placement.
        target_share: see ``targets``.
        generator: the generator version of its houses.
        keep_goal_caches: whether the build renders the goal camera's caches into the cache
            folder (False: no cache, only the poses near a target are rendered, for a tier whose
            caches would fill a disk and whose suites render live; the same goal poses).
        min_targets: the fewest of ``targets`` an evaluation house must have starts for in every
            placement (a seed whose house has fewer is skipped, as an invalid one is), so that
            every evaluation house plays episodes; 0: not asked (the tiers built before it).
        version: the files' version number (``<suite>-v<version>``).
    """

    placements: dict[str, str]
    size_class: str
    seeds: dict[str, range]
    counts: dict[str, int]
    episodes: dict[str, int]
    min_geodesic: float
    min_room_hops: int
    build_seed: int
    seeds_played: tuple[int, ...] = (1,)
    targets: tuple[str, ...] | None = None
    target_share: float = 0.5
    generator: str = "house-gen-3"
    keep_goal_caches: bool = True
    min_targets: int = 0
    version: int = 1

    @property
    def names(self) -> tuple[str, ...]:
        """The tier's suites, the base first."""
        return tuple(self.placements)


#: The large-house tier. One standard seed: 300 long episodes carry the statistics, and the
#: paper's five would make a 20-minute evaluation of ``frontier`` on one core 100 minutes.
LARGE = Tier(
    placements={"house-large": "functional", "house-large-roomwise": "roomwise", "house-large-shuffled": "shuffled"},
    size_class="xlarge",
    seeds={"train": range(1000, 1200), "val": range(2000, 2100), "test": range(3000, 3100)},
    counts={"train": 60, "val": 5, "test": 10},
    episodes={"val": 100, "test": 200},
    min_geodesic=8.0,
    min_room_hops=2,
    build_seed=40,
)
#: The size sweep (``docs/large_houses.md``): the same generator at 4, 7, 10 and 14 rooms,
#: functional and shuffled, for the curve of a prior's gain against house size. Test houses
#: only (a prior is counted on ``house-large``'s training houses), a start rule every size can
#: meet (another room than every one holding the target, at least 4 m away walking) and the
#: targets of the rooms every size has (4 rooms: a living room, a kitchen, a bedroom, a
#: bathroom), each drawn in every house that has it.
SWEEP_ROOMS = (4, 7, 10, 14)
SWEEP_TARGETS = ("alarm_clock", "book", "pot", "remote_control", "soap", "toilet_paper")
SWEEP = {
    rooms: Tier(
        placements={f"house-size-{rooms}": "functional", f"house-size-{rooms}-shuffled": "shuffled"},
        size_class=f"rooms-{rooms}",
        seeds={"test": range(4000 + 100 * rooms, 4100 + 100 * rooms)},
        counts={"test": 8},
        episodes={"test": 150},
        min_geodesic=4.0,
        min_room_hops=1,
        build_seed=50 + rooms,
        targets=SWEEP_TARGETS,
        target_share=0.0,
    )
    for rooms in SWEEP_ROOMS
}
#: The targets ``LARGE`` drew (all its small targets in half its evaluation houses), and its second
#: version draws among, so that the two versions ask for the same things.
LARGE_TARGETS = (
    "alarm_clock",
    "book",
    "bottle",
    "candle",
    "cup",
    "plate",
    "pot",
    "remote_control",
    "soap",
    "toilet_paper",
    "vase",
)
#: The large-house tier, version 2 (``docs/large_houses.md``): ``house-gen-4`` houses, whose
#: floorplans vary (L, T, U, two hallways, open plans, rooms entered through rooms), enough of
#: them for intervals over houses (100 training, 10 validation, 50 test), and the fidelity dial
#: over the same floorplans, starts and targets: a share p of the objects moved anywhere
#: (p = 0.25, 0.5, 0.75, 1) or, at p = 1, within room types. Its goal caches (360 houses in six
#: placements, about 40 GB) are not kept: its suites are evaluated rendering live.
LARGE_V2 = Tier(
    placements={
        "house-large-v2": "functional",
        "house-large-v2-p25": "anywhere-25",
        "house-large-v2-p50": "anywhere-50",
        "house-large-v2-p75": "anywhere-75",
        "house-large-v2-shuffled": "anywhere-100",
        "house-large-v2-roomwise": "roomwise-100",
    },
    size_class="xlarge",
    seeds={"train": range(10000, 10400), "val": range(11000, 11100), "test": range(12000, 12200)},
    counts={"train": 100, "val": 10, "test": 50},
    episodes={"val": 200, "test": 500},
    min_geodesic=12.0,
    min_room_hops=3,
    build_seed=60,
    targets=LARGE_TARGETS,
    generator="house-gen-4",
    keep_goal_caches=False,
    min_targets=2,
    version=2,
)
TIERS = {name: tier for tier in (LARGE, *SWEEP.values(), LARGE_V2) for name in tier.names}
# The large tier's values, by the names the tests and docs use.
PLACEMENTS = LARGE.placements
MIN_GEODESIC, MIN_ROOM_HOPS = LARGE.min_geodesic, LARGE.min_room_hops


def house_ref(tier: Tier, seed: int, split: str, placement: str) -> HouseRef:
    """The reference of ``tier``'s house of ``seed`` in generator split ``split`` and ``placement``."""
    return HouseRef(
        seed=seed,
        split=split,
        size_class=tier.size_class,
        generator=tier.generator,
        placement=None if placement == "functional" else placement,
    )


def _valid_worlds(tier: Tier, seed: int, split: str) -> dict[str, World] | None:
    """The house of ``seed`` in every placement (by placement), or None if one is not valid."""
    from objsearch.house.generate import HouseGenerationError

    worlds = {}
    for placement in tier.placements.values():
        try:
            world = World.load(house_ref(tier, seed, split, placement))
        except HouseGenerationError:
            return None
        if not validate_house(world.spec, world.model).ok:
            return None
        worlds[placement] = world
    return worlds


def pick_houses(tier: Tier, part: str, playable=None) -> list[dict[str, World]]:
    """The first ``tier.counts[part]`` seeds of ``tier.seeds[part]`` valid in every placement of
    ``tier`` (and, given ``playable``, for which ``playable(worlds)`` holds), each as
    ``{placement: World}`` (generator split ``train`` for the training part, ``test``, unseen
    object instances, for the others)."""
    seeds, count, split = tier.seeds[part], tier.counts[part], "train" if part == "train" else "test"
    picked = []
    for seed in seeds:
        worlds = _valid_worlds(tier, seed, split)
        if worlds is not None and (playable is None or playable(worlds)):
            picked.append(worlds)
            if len(picked) == count:
                return picked
    raise RuntimeError(
        f"only {len(picked)} of {count} valid (and playable) {tier.generator} houses among seeds {seeds}"
    )


class _Placed:
    """One placement of one house: its world, goal poses by target, and what starts need."""

    def __init__(self, tier: Tier, world: World, goal_ids: dict[str, np.ndarray]):
        self.tier, self.world, self.goal_ids = tier, world, goal_ids
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
        rule = (self.tier.min_geodesic, self.tier.min_room_hops)
        return far_starts(self.world, target, ids, steps, metres, *rule, rooms=self.rooms, hops=self.hops)


def _common_targets(targets: tuple[str, ...], share: float, placed: dict[str, _Placed]) -> set[str]:
    """The ``targets`` with goal poses in at least ``share`` of the houses of ``placed``, and one."""
    least = max(share * len(placed), 1)
    return {t for t in targets if sum(t in here.goal_ids for here in placed.values()) >= least}


def build_tier_suite(name: str, cache_dir: str | None = None) -> dict:
    """The suite file ``name`` of a tier (``TIERS``), built with the other placements of its tier."""
    return _build_tier(TIERS[name].names[0], cache_dir)[name]


@lru_cache(maxsize=1)
def _build_tier(base: str, cache_dir: str | None) -> dict[str, dict]:
    """The suite files of the tier whose base suite is ``base`` (by name); once a process
    (``objsearch suite rebuild`` of a tier's names builds once)."""
    return build_tier(TIERS[base], cache_dir)


def _tier_goal_ids(tier: Tier, world: World, cache_dir: str | None) -> dict[str, np.ndarray]:
    """The goal poses of every small target in ``world`` by the tier's rule: from its goal
    camera's cache in ``cache_dir``, or (``keep_goal_caches`` False) rendering only the poses
    near a target (``suite_record._near_goal_ids``: the same poses, no cache)."""
    from objsearch.sim.suite_record import _goal_ids, _near_goal_ids

    if tier.keep_goal_caches:
        return _goal_ids(world, SMALL_TARGETS, cache_dir, RULE)
    return _near_goal_ids(world, SMALL_TARGETS, RULE)


class _Starts:
    """The poses that may start an episode for a target in a house, in every placement at once:
    every pose of the house's functional graph is a candidate, kept where ``_Placed.start_ok``
    holds in every placement."""

    def __init__(self):
        self.tuples: dict[str, np.ndarray] = {}  # house -> its functional (row, col, heading) poses
        self.pose_ids: dict[tuple[str, str], np.ndarray] = {}  # (placement, house) -> those poses' ids there
        self._ok: dict[tuple[str, str], np.ndarray] = {}  # (house, target) -> the candidates that may start

    def add(self, house: str, here: dict[str, _Placed]) -> None:
        """Take ``house`` in its placements ``here`` (by placement, the functional one among them)."""
        self.tuples[house] = np.array(here["functional"].world.graph.pose_tuples, dtype=np.int64)
        for p, placed in here.items():
            self.pose_ids[p, house] = placed.pose_ids(self.tuples[house])

    def of(self, house: str, target: str, here: dict[str, _Placed]) -> np.ndarray:
        """The candidates (indices into ``tuples[house]``) that may start ``target``'s episodes."""
        if (house, target) not in self._ok:
            ok = np.ones(len(self.tuples[house]), dtype=bool)
            for p, placed in here.items():
                ok &= placed.start_ok(target, self.pose_ids[p, house])
            self._ok[house, target] = np.flatnonzero(ok)
        return self._ok[house, target]


def build_tier(tier: Tier, cache_dir: str | None = None) -> dict[str, dict]:
    """The suite files of ``tier``, by name, built together from its fixed seeds (the module
    docstring)."""
    from objsearch.sim.suite_record import _suite_record, house_entry, steps_range

    candidates = tier.targets or SMALL_TARGETS
    parts = tuple(tier.episodes)  # the evaluation splits
    placed: dict[str, dict[str, _Placed]] = {p: {} for p in tier.placements.values()}  # placement -> house -> _Placed
    starts = _Starts()

    def place(worlds: dict[str, World]) -> dict[str, _Placed]:
        here = {p: _Placed(tier, world, _tier_goal_ids(tier, world, cache_dir)) for p, world in worlds.items()}
        starts.add(worlds["functional"].house_id, here)
        return here

    def playable(worlds: dict[str, World]) -> bool:
        """Whether the house has starts for ``tier.min_targets`` candidate targets in every
        placement (its placements kept for the draw when it has)."""
        house, here = worlds["functional"].house_id, place(worlds)
        have = [t for t in candidates if all(t in placed_p.goal_ids for placed_p in here.values())]
        if sum(len(starts.of(house, t, here)) > 0 for t in have) < tier.min_targets:
            return False
        for p, placed_p in here.items():
            placed[p][house] = placed_p
        return True

    groups = {
        part: pick_houses(tier, part, playable if tier.min_targets and part in parts else None) for part in tier.counts
    }
    for part in parts:
        for worlds in groups[part]:
            if worlds["functional"].house_id not in placed["functional"]:
                for p, placed_p in place(worlds).items():
                    placed[p][worlds["functional"].house_id] = placed_p
    targets = sorted(set.intersection(*(_common_targets(candidates, tier.target_share, placed[p]) for p in placed)))
    rng = np.random.default_rng(tier.build_seed)
    episodes = {p: {} for p in placed}
    for part in parts:
        ids = sorted(w["functional"].house_id for w in groups[part])
        for p in placed:
            episodes[p][part] = []
        while len(episodes["functional"][part]) < tier.episodes[part]:
            house = ids[int(rng.integers(len(ids)))]
            here = {p: placed[p][house] for p in placed}
            have = [t for t in targets if all(t in here[p].goal_ids for p in placed)]
            if not have:
                continue
            target = have[int(rng.integers(len(have)))]
            ok = starts.of(house, target, here)
            if len(ok) == 0:
                continue
            k = int(ok[rng.integers(len(ok))])
            start = starts.tuples[house][k]
            for p in placed:
                pose = int(starts.pose_ids[p, house][k])
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
    for name, p in tier.placements.items():
        entry = {
            part: {
                w[p].house_id: house_entry(w[p], house_ref(tier, w[p].spec.seed, w[p].spec.split, p))
                for w in groups[part]
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
            f"{name}-v{tier.version}",
            {"targets": targets},
            {house: info for part in parts for house, info in entry[part].items()},
            entry.get("train", {}),
            goals,
            episodes[p],
            PROTOCOL,
            start_steps=steps_range([e for items in episodes[p].values() for e in items], PROTOCOL.stop),
            seeds=tier.seeds_played,
        )
    return out
