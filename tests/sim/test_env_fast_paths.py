"""The house env's scalar fast paths (issue 43) give the very bits of the straightforward
numpy computations they replaced: the pose observation, the depth read, the transition and
goal checks, the BFS and the goal-pose counts. A seeded rollout is compared, observation by
observation, with a reference built from the whole memory-mapped cache and numpy."""

import json

import numpy as np
import pytest

from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.cache import (
    RECORD_ORDER,
    HouseCache,
    millimetres_to_metres,
    quantize_depth,
    record_dtype,
)
from objsearch.sim.camera import AGENT_CAMERA
from objsearch.sim.env import MOVES, HouseEnv, relative_pose, relative_pose_of
from objsearch.sim.goals import GOAL_CAMERA, GoalRule, goal_poses, goal_poses_of
from objsearch.sim.navgraph import NUM_MOVE_ACTIONS, STOP, _backward_bfs


def same_bits(a, b) -> bool:
    """Equal dtype, shape and bytes (so -0.0 differs from 0.0, as it would in a record)."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.fixture(scope="module")
def graph(small_world):
    return small_world.graph


def test_scalar_relative_pose_matches_numpy_for_every_heading(graph):
    rng = np.random.default_rng(0)
    starts = rng.integers(graph.num_poses, size=400)
    poses = rng.integers(graph.num_poses, size=400)
    # every start heading against every pose heading of a few cells, and random pairs
    cells = rng.integers(graph.num_poses // 4, size=6) * 4
    pairs = [(c0 + h0, c + h) for c0 in cells for c in cells for h0 in range(4) for h in range(4)]
    pairs += list(zip(starts.tolist(), poses.tolist()))
    start_ids, pose_ids = np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])
    batched = relative_pose(graph, start_ids, pose_ids)  # the vector env's form
    for i, (start, pose) in enumerate(pairs):
        scalar = np.array(relative_pose_of(graph.pose_of(start), graph.pose_of(pose)), np.float32)
        assert same_bits(scalar, relative_pose(graph, start, pose)), (start, pose)
        assert same_bits(scalar, batched[i]), (start, pose)


def test_reader_gives_new_frames_of_one_record(tmp_path):
    record = record_dtype(RECORD_ORDER, 8, 8)
    rng = np.random.default_rng(0)
    frames = np.zeros(16, record)
    for name in RECORD_ORDER:
        frames[name] = rng.integers(0, 255, frames[name].shape).astype(frames[name].dtype) / (
            1 if name != "depth" else 7
        )
    np.save(tmp_path / "frames.npy", frames)
    layers = HouseCache(tmp_path, {"num_poses": len(frames)})
    read_all, read_two = layers.reader(("rgb", "depth", "semantic")), layers.reader(("depth", "semantic"))
    for pose in [0, 1, 15, 0, 7]:
        got = read_all(pose)
        for name, frame in zip(("rgb", "depth", "semantic"), got):
            assert same_bits(frame, frames[name][pose]) and same_bits(frame, getattr(layers, name)[pose])
            assert same_bits(frame, layers.frame(name, pose)) and same_bits(
                frame, layers.frames(name, pose, pose + 1)[0]
            )
        assert all(same_bits(a, b) for a, b in zip(read_two(pose), got[1:]))
        for frame in got:  # the caller owns what it was given: a new buffer each call
            frame[...] = 1
        assert same_bits(read_all(pose)[0], frames["rgb"][pose])
    with pytest.raises(IndexError):
        read_all(16)
    with pytest.raises(ValueError, match="holds layers"):
        layers.reader(("normals",))


def test_converted_millimetres_are_quantize_depths_metres_for_every_millimetre():
    mm = np.arange(65536, dtype=np.uint16)
    assert same_bits(millimetres_to_metres(mm), quantize_depth(mm / 1000.0))


def test_fast_bfs_and_goal_counts_match_the_reference(graph, small_world, cache_dir):
    rng = np.random.default_rng(1)
    for size in (1, 1, 3, 12, 40):
        goals = rng.choice(graph.num_poses, size=size, replace=False)
        assert same_bits(graph.shortest_steps(goals), _backward_bfs(graph.next_pose[:, :NUM_MOVE_ACTIONS], goals))
    assert same_bits(graph.shortest_steps([]), _backward_bfs(graph.next_pose[:, :NUM_MOVE_ACTIONS], []))
    cache = HouseCache.open(small_world, GOAL_CAMERA, cache_dir, progress=False)
    semantic, depth = cache.semantic, np.asarray(cache.depth)
    rules = (GoalRule(), GoalRule(top_k=1), GoalRule(kind="near_visible"))
    cids = sorted({CATEGORY_IDS[o.category] for o in small_world.spec.objects}) + [0, 255, 300, -1]
    for rule in rules:  # all categories at once (one pass over the frames with top_area): the same poses
        found = goal_poses_of(semantic, depth, cids, rule)
        assert list(found) == cids
        assert all(same_bits(found[cid], goal_poses(semantic, depth, cid, rule)) for cid in cids), rule
    for cid in cids:
        hits = semantic == cid
        area = hits.reshape(len(hits), -1).sum(axis=1)  # the sums goal_poses took before
        near = (hits & (depth <= 1.0)).reshape(len(hits), -1).sum(axis=1)
        for rule in rules:
            if rule.kind == "near_visible":
                expected = np.flatnonzero(near >= rule.min_pixels)
            elif not area.any():
                expected = np.zeros(0, dtype=np.int64)
            else:
                expected = np.flatnonzero(area >= max(1, np.sort(area)[::-1][min(rule.top_k, len(area)) - 1]))
            assert same_bits(goal_poses(semantic, depth, cid, rule), expected), (cid, rule)


def reference_step(ref: dict, action: int) -> tuple:
    """One step as the env computed it before issue 43: numpy scalars and arrays throughout."""
    graph = ref["graph"]
    before = ref["pose"]
    pose = ref["pose"] = int(graph.next_pose[before, action])
    ref["steps"] += 1
    at_goal = bool(ref["goal_mask"][pose])
    success = (action == STOP and at_goal) if ref["stop_action"] else at_goal
    terminated = success or (ref["stop_action"] and action == STOP)
    truncated = not terminated and ref["steps"] >= ref["limit"]
    obs = reference_observation(ref, int(pose == before and action in MOVES))
    info = {
        "success": success,
        "steps": ref["steps"],
        "min_steps": ref["task"].min_steps,
        "house": ref["task"].house,
        "pose": graph.pose_of(pose),
        "steps_to_goal": int(ref["dist"][pose]),
    }
    return obs, float(success), terminated, truncated, info


def reference_observation(ref: dict, collided: int) -> dict:
    graph, cache, pose = ref["graph"], ref["cache"], ref["pose"]
    return {
        "rgb": np.array(cache.rgb[pose]),
        "depth": np.array(cache.depth[pose]),
        "semantic": np.array(cache.semantic[pose]),
        "target": CATEGORY_IDS[ref["task"].target],
        "pose": relative_pose(graph, ref["start"], pose),
        "collided": collided,
    }


def reference_reset(env: HouseEnv, world, cache, task) -> dict:
    graph = world.graph
    goal_mask = np.zeros(graph.num_poses, dtype=bool)
    goal_mask[[graph.pose_id(*g) for g in task.goals]] = True
    start = graph.pose_id(*task.start)
    dist = _backward_bfs(graph.next_pose[:, :NUM_MOVE_ACTIONS], np.flatnonzero(goal_mask))
    return {
        "graph": graph,
        "cache": cache,
        "task": task,
        "goal_mask": goal_mask,
        "dist": dist,
        "start": start,
        "pose": start,
        "steps": 0,
        "limit": env.step_limit(world),
        "stop_action": env.stop_action,
    }


def assert_same_observation(got: dict, expected: dict) -> None:
    assert list(got) == list(expected)
    arrays = [value for value in got.values() if isinstance(value, np.ndarray)]
    for key, value in expected.items():
        if isinstance(value, np.ndarray):
            assert same_bits(got[key], value), key
            assert got[key].flags.writeable, key  # a new array (or a view of one), the caller's
            assert sum(np.shares_memory(got[key], other) for other in arrays) == 1, key  # no other key's bytes
        else:
            assert type(got[key]) is type(value) and got[key] == value, key
    for value in arrays:  # the caller may write into them: nothing the env reads again changes
        value[...] = 0


@pytest.mark.parametrize("stop_action", [False, True])
def test_seeded_rollout_equals_the_reference_computation(cache_dir, small_house, small_world, stop_action):
    env = HouseEnv([small_world], mode="cached", cache_dir=cache_dir, max_steps=150, stop_action=stop_action)
    cache = HouseCache.open(small_world, AGENT_CAMERA, cache_dir, progress=False)
    rng = np.random.default_rng(43)
    n = env.action_space.n
    obs, info = env.reset(seed=43)
    ref = reference_reset(env, small_world, cache, env._task)
    assert_same_observation(obs, reference_observation(ref, 0))
    episodes = steps = 0
    while steps < 3000:
        action = int(rng.integers(n))
        # actions as a caller may pass them: Python ints (the fast path) and numpy integers
        given = np.int64(action) if steps % 7 == 0 else action
        got, expected = env.step(given), reference_step(ref, action)
        assert_same_observation(got[0], expected[0])
        assert got[1:4] == expected[1:4] and json.dumps(got[4]) == json.dumps(expected[4]), steps
        steps += 1
        if got[2] or got[3]:
            episodes += 1
            obs, _ = env.reset()
            ref = reference_reset(env, small_world, cache, env._task)
            assert_same_observation(obs, reference_observation(ref, 0))
    assert episodes >= 10
    for bad in (n, -1, 1.0, True + 0.5, "1", None, np.array([1])):
        with pytest.raises(ValueError, match="invalid action"):
            env.step(bad)
    env.close()
