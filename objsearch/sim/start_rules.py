"""The large-house tier's start rule, and suites made from one's own houses by its rules.

The tier (``objsearch.sim.large_suite``) starts an episode far from its target: at least a
walking distance from the nearest goal pose, in a room some doors from every room holding
the target (``far_starts``, on ``room_hops``). ``objsearch suite make`` takes the same rules,
with the tier's goal rule, step limit and seeds (``MadeRules``): ``far_tables`` finds each
house's targets with such starts, ``far_episodes`` draws the episodes among them.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from objsearch.errors import UserError
from objsearch.house.spec import OUTSIDE, HouseSpec
from objsearch.sim.goals import Protocol
from objsearch.sim.world import World


@dataclass(frozen=True)
class MadeRules:
    """The large-house tier's rules for a suite made from one's own houses (``objsearch suite
    make``; ``objsearch.sim.large_suite``): None or 0 where not set, and the file is made as
    without them.

    Attributes:
        goal_pixels, goal_distance: the ObjectNav goal rule's target pixels (of the 64 x 64 goal
            camera) and their depth limit in metres (the tier: 5 pixels within 1 m).
        min_distance, min_room_hops: far starts: walking metres from the nearest goal pose, and
            doors from every room holding the target (the tier: 12 m and 3 doors).
        max_steps: the step limit (None: the protocol's).
        seeds: the standard seeds a full evaluation plays (None: the paper's five).
    """

    goal_pixels: int | None = None
    goal_distance: float | None = None
    min_distance: float = 0.0
    min_room_hops: int = 0
    max_steps: int | None = None
    seeds: tuple[int, ...] | None = None

    @property
    def far(self) -> bool:
        """Whether starts are drawn by the far-start rule."""
        return self.min_distance > 0 or self.min_room_hops > 0

    def describe(self) -> str:
        """The far-start rule in words, e.g. ``12 m walking and 3 doors``."""
        return f"{self.min_distance:g} m walking and {self.min_room_hops} doors"

    def protocol(self, protocol: Protocol) -> Protocol:
        """``protocol`` with this goal rule's pixels and distance, where set; ``UserError`` for a
        rule of pixels under the paper's protocol (whose rule picks the largest views)."""
        if self.goal_pixels is None and self.goal_distance is None:
            return protocol
        if protocol.goal_rule.kind != "near_visible":
            raise UserError(
                f"--goal-pixels and --goal-distance set the ObjectNav goal rule; protocol {protocol.name} picks "
                "the views the target fills most: add --protocol objectnav"
            )
        rule = protocol.goal_rule
        rule = replace(
            rule,
            min_pixels=rule.min_pixels if self.goal_pixels is None else self.goal_pixels,
            max_distance=rule.max_distance if self.goal_distance is None else self.goal_distance,
        )
        return replace(protocol, goal_rule=rule)


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


def far_starts(
    world: World,
    target: str,
    ids: np.ndarray,
    steps: np.ndarray,
    metres: np.ndarray,
    min_geodesic: float,
    min_room_hops: int,
    rooms: np.ndarray | None = None,
    hops: np.ndarray | None = None,
) -> np.ndarray:
    """Which of the poses ``ids`` of ``world`` (-1: not free) may start an episode for
    ``target`` by the tier's start rule: they reach its goal poses (``steps``, ``metres``: moves
    and walking metres from every pose to them), at least ``min_geodesic`` metres away, from a
    room at least ``min_room_hops`` doors from every room that holds it. ``rooms`` (the room
    of every pose) and ``hops`` (``room_hops``) may be given, computed once a house."""
    rooms = np.repeat(world.cell_rooms, 4) if rooms is None else rooms
    hops = room_hops(world.spec) if hops is None else hops
    free = ids >= 0
    safe = np.where(free, ids, 0)
    holders = sorted({o.room for o in world.spec.objects if o.category == target})
    room = rooms[safe]
    doors = hops[np.maximum(room, 0)][:, holders]  # doors to each room holding the target
    far_rooms = (room >= 0) & np.all((doors >= min_room_hops) | (doors < 0), axis=1)
    return free & (steps[safe] >= 0) & (metres[safe] >= min_geodesic) & far_rooms


def far_tables(worlds: dict[str, World], targets: list[str], cache_dir, rule, made: MadeRules):
    """(goal poses by house and target, as ``_goal_table`` gives them; the far starts of each
    house and target, pose ids with their moves and metres), for the targets of each house
    with a pose that meets ``made``'s far-start rule."""
    from objsearch.sim.suite_record import _goal_ids

    tables, far = {}, {}
    for house, world in worlds.items():
        graph, tables[house] = world.graph, {}
        every = np.arange(graph.num_poses)
        for target, goal_ids in _goal_ids(world, targets, cache_dir, rule).items():
            steps, metres = graph.shortest_steps(goal_ids), graph.geodesic_metres(goal_ids)
            ok = np.flatnonzero(far_starts(world, target, every, steps, metres, made.min_distance, made.min_room_hops))
            if len(ok):
                tables[house][target] = [list(graph.pose_of(int(g))) for g in goal_ids]
                far[house, target] = (ok, steps, metres)
    return tables, far


def far_episodes(worlds: dict[str, World], far: dict, targets: list[str], count: int, rng, stop: bool) -> list[dict]:
    """``count`` episodes: house and target drawn uniformly (again while the house has no far
    start for it), the start uniformly among its far starts (``far_tables``)."""
    names, out = sorted(worlds), []
    while len(out) < count:
        house, target = names[rng.integers(len(names))], targets[rng.integers(len(targets))]
        if (house, target) not in far:
            continue
        ok, steps, metres = far[house, target]
        start = int(ok[rng.integers(len(ok))])
        out.append(
            {
                "house": house,
                "start": list(worlds[house].graph.pose_of(start)),
                "target": target,
                "min_steps": int(steps[start]) + stop,
                "geodesic": float(metres[start]),
            }
        )
    return out
