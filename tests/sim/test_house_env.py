import pickle
import warnings

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import objsearch  # noqa: F401  (registers the env ids)
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.env import START_STEPS, HouseEnv
from objsearch.sim.navgraph import STOP
from objsearch.sim.wrappers import FrameHistory, TargetMaskDepth


@pytest.fixture(scope="module")
def env(cache_dir, small_house):
    env = HouseEnv([small_house], mode="cached", cache_dir=cache_dir)
    yield env
    env.close()


def test_passes_check_env(cache_dir, small_house):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        env = gymnasium.make("ObjSearch/House-v1", houses=[small_house], cache_dir=cache_dir)
        check_env(env.unwrapped)
        env.close()
        env.close()


def test_sampled_tasks_are_solvable_in_range(env):
    rng = np.random.default_rng(0)
    for _ in range(10):
        task = env.sample_task(rng)
        assert START_STEPS[0] <= task.min_steps <= START_STEPS[1]
        assert task.target in {o.category for o in env.world(task.house).spec.objects}
        assert task.goals


def rollout(env, task, actions):
    obs, info = env.reset(options={"task": task})
    out = [(obs, info)]
    for a in actions:
        obs, reward, terminated, truncated, info = env.step(int(a))
        out.append((obs, reward, terminated, truncated, info))
        if terminated or truncated:
            break
    return out


def test_live_and_cached_observations_are_identical(env, cache_dir, small_house):
    task = env.sample_task(np.random.default_rng(1))
    actions = np.random.default_rng(2).integers(6, size=50)
    live = HouseEnv([small_house], mode="live", cache_dir=cache_dir)
    cached, rendered = rollout(env, task, actions), rollout(live, task, actions)
    live.close()
    assert len(cached) == len(rendered)
    for a, b in zip(cached, rendered):
        for key in ("rgb", "depth", "semantic", "target", "pose", "collided"):
            assert np.array_equal(a[0][key], b[0][key]), key
        assert a[1:] == b[1:]


def test_pose_and_collided_follow_the_moves_and_the_camera_comes_with_the_reset(env):
    """``pose`` is (x forward, y left, heading) from the start, as Habitat's GPS+compass;
    ``collided`` says a move was blocked; ``info["camera"]`` gives the camera's parameters."""
    task = env.sample_task(np.random.default_rng(4))
    obs, info = env.reset(options={"task": task})
    assert np.array_equal(obs["pose"], [0, 0, 0]) and obs["collided"] == 0
    camera = info["camera"]
    assert (camera["width"], camera["height"], camera["vfov"], camera["hfov"]) == (64, 64, 90.0, 90.0)
    assert camera["fx"] == camera["fy"] == 32.0 and camera["camera_height"] == 1.0 and camera["depth"] == "planar"
    graph = env.world(task.house).graph
    forward = np.array([[1, 0], [0, 1], [-1, 0], [0, -1]])[task.start[2]]  # (dx, dy) of the start heading
    left = np.array([-forward[1], forward[0]])
    moves = collisions = 0
    for action in np.random.default_rng(5).integers(6, size=300):
        before = env.pose
        obs, _, terminated, truncated, info = env.step(int(action))
        row, col, heading = env.pose
        d = np.array([col - task.start[1], row - task.start[0]]) * 0.25
        expected_heading = ((heading - task.start[2] + 1) % 4 - 1) * np.pi / 2  # in (-pi, pi]
        assert np.allclose(obs["pose"], [d @ forward, d @ left, expected_heading], atol=1e-6), (obs["pose"], env.pose)
        blocked = action in (0, 3, 4, 5) and env.pose == before
        assert obs["collided"] == int(blocked)
        moves += action in (0, 3, 4, 5)
        collisions += blocked
        if terminated or truncated:
            break
    assert 0 < collisions < moves, "the walk both moved and bumped into something"
    assert graph.num_poses > 0


def test_oracle_path_reaches_a_goal_in_min_steps(env):
    task = env.sample_task(np.random.default_rng(3))
    env.reset(options={"task": task})
    world = env.world(task.house)
    graph = world.graph
    path = graph.shortest_path(graph.pose_id(*task.start), [graph.pose_id(*g) for g in task.goals])
    for i, action in enumerate(path):
        obs, reward, terminated, truncated, info = env.step(action)
        assert terminated == (i == len(path) - 1)
    assert info["success"] and reward == 1.0 and info["steps"] == task.min_steps
    assert info["pose"] in task.goals
    target_pixels = (obs["semantic"] == CATEGORY_IDS[task.target]).sum()
    assert target_pixels > 0, "a goal pose sees its target"


def test_stop_action_variant(cache_dir, small_house):
    env = HouseEnv([small_house], mode="cached", cache_dir=cache_dir, stop_action=True)
    assert env.action_space.n == 7
    task = env.sample_task(np.random.default_rng(4))
    env.reset(options={"task": task})
    _, reward, terminated, _, info = env.step(STOP)
    assert terminated and not info["success"] and reward == 0.0, "STOP away from the goal fails"
    env.reset(options={"task": task})
    graph = env.world(task.house).graph
    for action in graph.shortest_path(graph.pose_id(*task.start), [graph.pose_id(*g) for g in task.goals]):
        _, _, terminated, _, _ = env.step(action)
        assert not terminated, "with STOP, reaching a goal pose does not end the episode"
    _, reward, terminated, _, info = env.step(STOP)
    assert terminated and info["success"] and reward == 1.0


def test_truncation_and_blocked_moves(cache_dir, small_house):
    env = HouseEnv([small_house], mode="cached", cache_dir=cache_dir, max_steps=5)
    task = env.sample_task(np.random.default_rng(5))
    env.reset(options={"task": task})
    graph = env.world(task.house).graph
    for _ in range(5):
        pose = graph.pose_id(*env.pose)
        _, _, terminated, truncated, info = env.step(0)
        if graph.next_pose[pose, 0] == pose:
            assert info["pose"] == graph.pose_of(pose), "a blocked move leaves the agent in place"
    assert truncated and not terminated and info["steps"] == 5
    with pytest.raises(RuntimeError, match="reset"):
        env.step(0)


def test_pickle_round_trip(env):
    task = env.sample_task(np.random.default_rng(6))
    env.reset(options={"task": task})
    clone = pickle.loads(pickle.dumps(env))
    for action in (0, 1, 0, 4):
        a, b = env.step(action), clone.step(action)
        assert np.array_equal(a[0]["rgb"], b[0]["rgb"]) and a[1:] == b[1:]
    clone.close()


def test_small_observation_wrappers(cache_dir, small_house):
    base = HouseEnv([small_house], mode="cached", cache_dir=cache_dir)
    env = FrameHistory(TargetMaskDepth(base, size=10), k=4)
    task = base.sample_task(np.random.default_rng(7))
    obs, _ = env.reset(options={"task": task})
    assert obs.shape == (4, 2, 10, 10) and obs.dtype == np.float32
    assert (obs[0] == obs[3]).all(), "the history starts filled with the first frame"
    raw = base._observe()
    mask = (raw["semantic"] == raw["target"]).mean()
    assert np.isclose(obs[-1, 0].mean(), mask, atol=1e-6), "block fractions average to the mask's"
    assert np.isclose(obs[-1, 1].mean(), raw["depth"].mean(), rtol=1e-4)
    first = obs[-1]
    obs, *_ = env.step(1)
    assert np.array_equal(obs[:3], np.repeat(first[None], 3, axis=0)), "the new frame enters at the end"


def test_vector_env(cache_dir, small_house):
    envs = gymnasium.make_vec(
        "ObjSearch/House-v1", num_envs=2, vectorization_mode="sync", houses=[small_house], cache_dir=cache_dir
    )
    obs, _ = envs.reset(seed=0)
    assert obs["rgb"].shape == (2, 64, 64, 3)
    obs, reward, terminated, truncated, _ = envs.step(np.array([0, 1]))
    assert reward.shape == (2,)
    envs.close()


def test_batched_vector_env(cache_dir, small_house):
    envs = gymnasium.make_vec(
        "ObjSearch/House-v1",
        num_envs=8,
        vectorization_mode="vector_entry_point",
        houses=[small_house],
        cache_dir=cache_dir,
        max_steps=30,
    )
    inner = envs.unwrapped if hasattr(envs, "unwrapped") else envs
    obs, _ = envs.reset(seed=0)
    assert envs.observation_space.contains(obs)
    cache = inner._caches[0]
    ended = np.zeros(8, bool)
    for actions in np.random.default_rng(0).integers(6, size=(40, 8)):
        before = inner.pose.copy()
        obs, reward, terminated, truncated, info = envs.step(actions)
        moved = inner._next[0][before, actions]
        done = terminated | truncated
        ended |= done
        # envs that did not end are where the transition table says, and see that pose
        assert (inner.pose[~done] == moved[~done]).all()
        assert np.array_equal(obs["rgb"][~done], cache.rgb[inner.pose[~done]])
        assert (reward == terminated).all() and (info["success"] == terminated).all()
        assert (inner.steps[done] == 0).all(), "ended episodes restart in the same step"
    assert ended.any()
    envs.close()


def test_cache_is_keyed_and_rebuilt_when_stale(small_world, tmp_path):
    from objsearch.sim.cache import HouseCache
    from objsearch.sim.camera import RenderSettings

    small = RenderSettings(width=16, height=16)
    cache = HouseCache.open(small_world, small, tmp_path, progress=False)
    assert cache.rgb.shape == (small_world.graph.num_poses, 16, 16, 3)
    first = np.array(cache.semantic)
    other = HouseCache.open(small_world, RenderSettings(width=16, height=16, fovy=60.0), tmp_path, progress=False)
    assert other.directory != cache.directory, "other camera settings, another cache"
    (cache.directory / "meta.json").write_text("{}")  # stale or half-written metadata
    rebuilt = HouseCache.open(small_world, small, tmp_path, progress=False)
    assert rebuilt.directory == cache.directory and np.array_equal(rebuilt.semantic, first)
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")], "no temp folder left behind"


def test_house_v0_keeps_the_keys_it_was_released_with(cache_dir, small_house):
    """``House-v1`` added ``pose`` and ``collided``; the v0 id gives v0's keys, the same values."""
    kwargs = {"houses": [small_house], "cache_dir": cache_dir}
    with pytest.warns(DeprecationWarning, match="upgrading to version `v1`"):  # Gymnasium says so of an old id
        old = gymnasium.make("ObjSearch/House-v0", **kwargs)
    new = gymnasium.make("ObjSearch/House-v1", **kwargs)
    assert set(old.observation_space) == {"rgb", "depth", "semantic", "target"}
    assert set(new.observation_space) == {"rgb", "depth", "semantic", "target", "pose", "collided"}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(old.unwrapped)
    (a, _), (b, _) = old.reset(seed=3), new.reset(seed=3)
    for action in [0, 1, 0, 3, 2]:
        assert set(a) == set(old.observation_space) and a in old.observation_space
        assert all(np.array_equal(a[key], b[key]) for key in a)
        a, b = old.step(action)[0], new.step(action)[0]
    with pytest.warns(DeprecationWarning):
        envs = gymnasium.make_vec("ObjSearch/House-v0", num_envs=2, vectorization_mode="vector_entry_point", **kwargs)
    obs, _ = envs.reset(seed=0)
    assert set(obs) == {"rgb", "depth", "semantic", "target"} and envs.observation_space.contains(obs)
    assert envs.observation_space.contains(envs.step(np.array([0, 1]))[0])
    for env in (old, new, envs):
        env.close()
