"""Episode starts near the entrance (``starts="entrance"``): in the env's sampled tasks and
in a suite's episodes. Near the entrance, reachable, seeded, and a clear error for a house
without an entrance."""

import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.sim.env import ENTRANCE_STEPS, START_STEPS, HouseEnv, draw_start, entrance_poses
from objsearch.sim.navgraph import GRID
from objsearch.sim.suite_build import _episodes
from objsearch.sim.suites import load_houses, load_suite_file
from objsearch.sim.world import HouseRef, World

V2_HOUSE = HouseRef(seed=3, generator="house-gen-2")


@pytest.fixture(scope="module")
def v2_world():
    return World.load(V2_HOUSE)


def _metres_from_entrance(world, pose):
    row, col, _ = pose
    x, y = world.spec.entrance_point()
    return float(np.hypot((col + 0.5) * GRID - x, (row + 0.5) * GRID - y))


def test_entrance_poses_lie_within_steps_of_the_entrance(v2_world):
    near = entrance_poses(v2_world)
    graph = v2_world.graph
    ids = np.flatnonzero(near)
    assert 4 <= len(ids) < graph.num_poses / 4
    # ENTRANCE_STEPS steps move at most that many cells; the anchor is the cell nearest the point
    assert max(_metres_from_entrance(v2_world, graph.pose_of(int(i))) for i in ids) <= (ENTRANCE_STEPS + 1) * GRID
    assert near.sum() > entrance_poses(v2_world, steps=2).sum()


def test_house_without_entrance_is_a_clear_error(small_world):
    with pytest.raises(UserError, match=rf"house {small_world.house_id} .*house-gen-1.*no entrance.*house-gen-2"):
        entrance_poses(small_world)


def test_env_samples_starts_near_the_entrance(cache_dir, v2_world):
    env = HouseEnv([v2_world], cache_dir=cache_dir, starts="entrance")
    tasks = [env.sample_task(np.random.default_rng(7)) for _ in range(2)]
    assert tasks[0] == tasks[1]  # same seed, same task
    rng = np.random.default_rng(0)
    near = entrance_poses(v2_world)
    graph = v2_world.graph
    for _ in range(12):
        task = env.sample_task(rng)
        start = graph.pose_id(*task.start)
        assert near[start]
        dist = graph.shortest_steps([graph.pose_id(*g) for g in task.goals])
        assert dist[start] == task.min_steps >= START_STEPS[0]  # reachable, never at the goal
    obs, info = env.reset(seed=3)
    assert near[graph.pose_id(*env.pose)]
    env.close()


def test_env_entrance_starts_on_a_v1_house_fail_on_reset(cache_dir, small_house):
    env = HouseEnv([small_house], cache_dir=cache_dir, starts="entrance")
    with pytest.raises(UserError, match="no entrance"):
        env.reset(seed=0)
    with pytest.raises(ValueError, match="starts must be one of"):
        HouseEnv([small_house], starts="door")


def test_default_starts_are_the_old_draw():
    """``draw_start`` without ``near`` draws as the suite builder always drew (the suite files
    rely on it: same rng calls, same start)."""
    dist = np.array([-1, 3, 6, 10, 40, 41, 7, 0])
    a, b = np.random.default_rng(5), np.random.default_rng(5)
    starts = np.flatnonzero((dist >= START_STEPS[0]) & (dist <= START_STEPS[1]))
    assert draw_start(dist, a) == int(starts[b.integers(len(starts))])
    assert a.integers(1 << 30) == b.integers(1 << 30)
    near = np.array([True, True, False, False, False, True, False, True])
    assert draw_start(dist, np.random.default_rng(0), near) == 5  # no near pose in the window: beyond it
    assert draw_start(dist, np.random.default_rng(0), near & (dist < 6)) is None


def test_suite_episodes_near_the_entrance_are_seeded():
    suite = load_suite_file("house-multi-v2")
    worlds = load_houses(suite)
    worlds = {h: worlds[h] for h in sorted(worlds)[:2]}
    targets = suite["categories"]["targets"]
    first = _episodes(worlds, suite["goals"], targets, 30, np.random.default_rng(1), "entrance")
    assert first == _episodes(worlds, suite["goals"], targets, 30, np.random.default_rng(1), "entrance")
    near = {h: entrance_poses(w) for h, w in worlds.items()}
    for ep in first:
        graph = worlds[ep["house"]].graph
        start = graph.pose_id(*ep["start"])
        assert near[ep["house"]][start]
        dist = graph.shortest_steps([graph.pose_id(*g) for g in suite["goals"][ep["house"]][ep["target"]]])
        assert dist[start] == ep["min_steps"] >= START_STEPS[0]
    in_window = sum(START_STEPS[0] <= ep["min_steps"] <= START_STEPS[1] for ep in first)
    assert in_window >= len(first) // 2
    default = _episodes(worlds, suite["goals"], targets, 30, np.random.default_rng(1))
    assert default != first and all(START_STEPS[0] <= ep["min_steps"] <= START_STEPS[1] for ep in default)


def test_suite_episodes_near_the_entrance_of_a_v1_house_fail():
    suite = load_suite_file("house-multi")
    worlds = load_houses(suite)
    with pytest.raises(UserError, match="no entrance"):
        _episodes(worlds, suite["goals"], suite["categories"]["targets"], 5, np.random.default_rng(0), "entrance")
