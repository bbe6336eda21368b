"""The parts of a house suite file that every builder of one makes the same way (``suite_build``'s
recipes and ``suite_from_houses``, ``rooms_suite``, ``large_suite``): a house's entry
(``house_entry``), the goal poses of its targets (``_goal_ids``, ``_goal_table``; ``_near_goal_ids``
without a cache), episodes drawn
with their starts (``_episodes``) and the file's record with the settings every suite records
(``_suite_record``). The names with ``_`` are the builders' own, not an API.
"""

from __future__ import annotations

import numpy as np

from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.goals import GOAL_CAMERA, PROTOCOLS, GoalRule, Protocol, goal_poses
from objsearch.sim.house_task import START_STEPS, draw_start, entrance_poses
from objsearch.sim.navgraph import NAVGRAPH_VERSION
from objsearch.sim.suite_schema import content_digest
from objsearch.sim.world import HouseRef, World


def _goal_ids(world: World, targets, cache_dir, rule: GoalRule) -> dict[str, np.ndarray]:
    """The goal pose ids of each of ``targets`` the house has goal poses for, by ``rule``
    (rendering the goal camera's cache)."""
    from objsearch.sim.cache import HouseCache

    cache = HouseCache.open(world, GOAL_CAMERA, cache_dir)
    semantic, depth = np.asarray(cache.semantic), np.asarray(cache.depth)
    found = {target: goal_poses(semantic, depth, CATEGORY_IDS[target], rule) for target in targets}
    return {target: ids for target, ids in found.items() if len(ids)}


def _near_goal_ids(world: World, targets, rule: GoalRule) -> dict[str, np.ndarray]:
    """``_goal_ids`` of a ``near_visible`` rule without a cache: only the poses that could see
    a target nearer than ``rule.max_distance`` are rendered (``candidate_poses``), with the
    goal camera and the cache's depth rounding, so the goal poses are the same."""
    from objsearch.sim.cache import BATCH, quantize_depth
    from objsearch.sim.renderer import HouseRenderer

    if rule.kind != "near_visible":
        raise ValueError(f"only a near_visible rule needs no cache, not {rule.kind!r}")
    candidates = {t: candidate_poses(world, t, rule.max_distance) for t in targets}
    ids = np.unique(np.concatenate([np.zeros(0, np.int64), *candidates.values()]))
    semantic = np.zeros((len(ids), GOAL_CAMERA.height, GOAL_CAMERA.width), np.uint8)
    depth = np.zeros(semantic.shape, np.float32)
    poses = world.graph.world_poses(ids)
    with HouseRenderer(world.model, GOAL_CAMERA) as renderer:
        for start in range(0, len(ids), BATCH):
            frames = renderer.render(poses[start : start + BATCH])
            semantic[start : start + BATCH], depth[start : start + BATCH] = (
                frames.semantic,
                quantize_depth(frames.depth),
            )
    found = {t: ids[goal_poses(semantic, depth, CATEGORY_IDS[t], rule)] for t in targets}
    return {t: found_ids for t, found_ids in found.items() if len(found_ids)}


def candidate_poses(world: World, target: str, max_distance: float) -> np.ndarray:
    """Pose ids (sorted) of ``world`` whose goal camera could see a point of a ``target`` object
    at depth ``max_distance`` or less: a point at that depth lies within ``max_distance`` times
    sqrt(1 + 2 tan^2(fov / 2)) of the camera (the corner of a square image), so the pose is
    that near an object's bounding sphere and, seen from above, faces it within half the field
    of view plus the sphere's angular radius. A superset of the goal poses, by geometry alone."""
    half = np.radians(GOAL_CAMERA.fovy) / 2
    reach = max_distance * np.sqrt(1 + 2 * np.tan(half) ** 2)
    graph = world.graph
    poses = graph.world_poses()
    keep = np.zeros(len(poses), dtype=bool)
    for obj in world.spec.objects:
        if obj.category != target:
            continue
        radius = float(np.linalg.norm(obj.size)) + 0.05  # size as full or half extents: a sphere holding the object
        dx, dy = obj.position[0] - poses[:, 0], obj.position[1] - poses[:, 1]
        dz = obj.position[2] - GOAL_CAMERA.camera_height
        near = np.sqrt(dx**2 + dy**2 + dz**2) <= reach + radius
        flat = np.hypot(dx, dy)
        off = np.abs((np.arctan2(dy, dx) - poses[:, 2] + np.pi) % (2 * np.pi) - np.pi)
        spread = np.arcsin(np.clip(radius / np.maximum(flat, 1e-9), 0.0, 1.0))
        keep |= near & ((flat <= radius) | (off <= half + spread))
    return np.flatnonzero(keep)


def _goal_table(world: World, targets, cache_dir, rule: GoalRule = PROTOCOLS["paper"].goal_rule) -> dict[str, list]:
    """The goal poses by ``rule`` of each of ``targets`` with a pose ``START_STEPS`` from them."""
    graph = world.graph
    table = {}
    for target, goals in _goal_ids(world, targets, cache_dir, rule).items():
        dist = graph.shortest_steps(goals)
        if ((dist >= START_STEPS[0]) & (dist <= START_STEPS[1])).any():
            table[target] = [list(graph.pose_of(int(g))) for g in goals]
    return table


def _episodes(
    worlds: dict[str, World],
    goals: dict,
    targets: list[str],
    count: int,
    rng,
    starts: str = "anywhere",
    stop: bool = False,
) -> list[dict]:
    """``count`` episodes: house and target drawn uniformly (again while the house lacks the
    target, or, with ``starts="entrance"``, while ``draw_start`` finds no start near its
    entrance), the start by ``draw_start``; ``min_steps`` counts the STOP with ``stop``."""
    names = sorted(worlds)
    near = {house: entrance_poses(world) for house, world in worlds.items()} if starts == "entrance" else {}

    def steps_to_goals(house, target):
        graph = worlds[house].graph
        return graph.shortest_steps([graph.pose_id(*g) for g in goals[house][target]])

    if near and not any(
        (near[h] & (steps_to_goals(h, t) >= START_STEPS[0])).any() for h in names for t in targets if t in goals[h]
    ):  # draw_start would find no start for any house and target: the loop below would not end
        raise UserError(
            f"no target ({', '.join(targets)}) has goal poses {START_STEPS[0]} steps or more from the entrance "
            f"of any of the houses {', '.join(names)}; draw the starts anywhere (starts='anywhere')"
        )
    out = []
    while len(out) < count:
        house = names[rng.integers(len(names))]
        target = targets[rng.integers(len(targets))]
        if target not in goals[house]:
            continue
        graph = worlds[house].graph
        dist = steps_to_goals(house, target)
        start = draw_start(dist, rng, near.get(house))
        if start is None:
            continue
        out.append(
            {
                "house": house,
                "start": list(graph.pose_of(start)),
                "target": target,
                "min_steps": int(dist[start]) + stop,
            }
        )
    return out


def steps_range(episodes, stop: bool) -> tuple[int, int]:
    """The fewest and most moves of the drawn starts of ``episodes`` from their goals (a file's
    ``start_steps``; ``stop``: their ``min_steps`` count the STOP)."""
    moves = [e["min_steps"] - stop for e in episodes]
    return min(moves), max(moves)


def house_entry(world: World, ref: HouseRef) -> dict:
    """The fields a suite file stores for a house (``HouseRef`` fields, with the spec hash):
    its generator seed, or its folder (``ref.path``)."""
    if ref.path is not None:
        return {"path": ref.path, "spec_sha256": world.spec_sha256}
    entry = {
        "seed": ref.seed,
        "split": ref.split,
        "size_class": world.spec.size_class,
        "spec_sha256": world.spec_sha256,
    }
    if ref.generator is not None:  # left out for house-gen-1 houses, so v1 suite files keep their bytes
        entry["generator"] = ref.generator
    if ref.placement is not None:  # left out for functional houses, so their suite files keep their bytes
        entry["placement"] = ref.placement
    if ref.room is not None:  # a single room (the rooms suite); left out for houses
        entry["room"] = ref.room
    return entry


def _suite_record(
    name: str,
    version: str | None,
    categories: dict,
    houses: dict,
    training: dict,
    goals: dict,
    splits: dict,
    protocol: Protocol = PROTOCOLS["paper"],
    starts: str = "anywhere",
    max_steps: int | None = None,
    start_steps: tuple[int, int] = START_STEPS,
    room_max_steps: dict[str, int] | None = None,
    seeds: tuple[int, ...] | None = None,
) -> dict:
    """A suite file's content: the given parts and the settings every suite records, those of
    ``protocol`` among them. The protocol's name and ``starts`` are recorded only when not the
    defaults (``paper``, ``anywhere``), and ``room_max_steps`` and ``seeds`` (the standard
    seeds, where not the paper's) only when given, so that other files keep their bytes. ``max_steps`` None: the protocol's. ``version`` None: ``custom:``
    and the content's digest."""
    record = {
        "suite": name,
        "version": version,
        **({"protocol": protocol.name} if protocol.name != "paper" else {}),
        "navgraph": NAVGRAPH_VERSION,
        "goal_rule": protocol.goal_rule.to_json(),
        "goal_camera": GOAL_CAMERA.to_json(),
        "start_steps": list(start_steps),
        "max_steps": protocol.max_steps if max_steps is None else max_steps,
        **({"room_max_steps": dict(room_max_steps)} if room_max_steps else {}),
        **({"seeds": list(seeds)} if seeds else {}),
        "categories": categories,
        "houses": houses,
        "training_houses": training,
        "goals": goals,
        "splits": splits,
        **({"starts": starts} if starts != "anywhere" else {}),
    }
    if version is None:
        record["version"] = f"custom:{content_digest(record)[:12]}"
    return record
