import numpy as np
import pytest

from objsearch.gridworld import dataset
from objsearch.gridworld.batched import BatchedGridWorld, GridTables
from objsearch.gridworld.env import GridWorldEnv
from objsearch.gridworld.maps import bfs_distances


@pytest.fixture(scope="module")
def tables():
    return GridTables.build(list(dataset.test_maps().values()))


def test_tables_distances_match_bfs(tables):
    maps = list(dataset.test_maps().values())
    for mi in (0, 7, 19):
        for g in range(16):
            ref = bfs_distances(maps[mi].obstacles, tuple(maps[mi].goals[g])).ravel()
            assert np.array_equal(tables.goal_dist[mi, g], ref)


@pytest.mark.parametrize("observation", ["goal", "all_goals"])
def test_batched_equals_single_envs(tables, observation):
    n = 16
    world = BatchedGridWorld(tables, n, observation=observation, autoreset=False, rng=np.random.default_rng(0))
    maps, goals, starts = world.sample_tasks(n)
    obs = world.reset(maps=maps, goals=goals, starts=starts)
    singles = []
    for i in range(n):
        env = GridWorldEnv(maps=list(dataset.test_maps().values()), goals=None, observation=observation)
        from objsearch.gridworld.tasks import GridTask

        r, c = divmod(int(starts[i]), tables.width)
        task = GridTask(map=tables.names[maps[i]], start=(r, c), goal=int(goals[i]), min_steps=0)
        single_obs, _ = env.reset(options={"task": task})
        assert np.array_equal(single_obs["image"], obs["image"][i])
        singles.append(env)
    actions = np.random.default_rng(1).integers(4, size=(30, n))
    done = np.zeros(n, bool)
    for step_actions in actions:
        obs, reward, terminated, truncated, info = world.step(step_actions)
        for i, env in enumerate(singles):
            if done[i]:
                continue
            o, r, te, tr, inf = env.step(int(step_actions[i]))
            assert np.array_equal(o["image"], obs["image"][i])
            assert (r, te, tr) == (reward[i], terminated[i], truncated[i])
            done[i] = te or tr


def test_sampled_starts_can_reach_their_goal(tables):
    world = BatchedGridWorld(tables, 1000, goals=(2, 5), rng=np.random.default_rng(0))
    maps, goals, starts = world.sample_tasks(1000)
    assert set(goals) <= {2, 5}
    assert (tables.goal_dist[maps, goals, starts] > 0).all()


def test_autoreset_starts_new_episodes(tables):
    world = BatchedGridWorld(tables, 64, max_steps=3, rng=np.random.default_rng(0))
    world.reset()
    ended = np.zeros(64, bool)
    for _ in range(3):
        _, _, terminated, truncated, info = world.step(np.zeros(64, dtype=int))
        done = terminated | truncated
        ended |= done
        assert (world.steps[done] == 0).all(), "an ended env starts a new episode at once"
        assert (world.min_steps[done] > 0).all()
    assert ended.all(), "every episode ends within max_steps"
    assert (info["steps"][truncated] == 3).all()


def test_same_rng_seed_same_batch(tables):
    def run(seed):
        world = BatchedGridWorld(tables, 32, rng=np.random.default_rng(seed))
        out = [world.reset()["image"]]
        for a in np.random.default_rng(99).integers(4, size=(40, 32)):
            out.append(world.step(a)[0]["image"])
        return np.stack(out)

    assert np.array_equal(run(5), run(5))
    assert not np.array_equal(run(5), run(6))
