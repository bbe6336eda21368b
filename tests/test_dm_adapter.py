"""``objsearch.dm_adapter``: the envs pass dm_env's own conformance tests
(``dm_env.test_utils.EnvironmentTestMixin``), with specs as dm_control's suites expose them."""

import numpy as np
import pytest
from absl.testing import absltest
from dm_env import StepType, specs, test_utils

from objsearch import dm_adapter
from objsearch.gridworld.maps import shortest_path_actions
from objsearch.sim.world import HouseRef

SMALL_HOUSE = HouseRef(seed=3)  # ~1700 poses: its cache builds in seconds


class _Episodes:
    """Action sequences that end episodes, so the mixin checks LAST and the FIRST after it."""

    def make_action_sequence(self):
        rng = np.random.default_rng(0)
        for _ in range(60):
            yield int(rng.integers(self.environment.action_spec().num_values))


class GridWorldConformance(_Episodes, test_utils.EnvironmentTestMixin, absltest.TestCase):
    def make_object_under_test(self):
        return dm_adapter.grid_world(seed=0, max_steps=10)


class SuiteConformance(_Episodes, test_utils.EnvironmentTestMixin, absltest.TestCase):
    def make_object_under_test(self):
        return dm_adapter.suite("gridworld", split="seen-goals", seeds=[1], episodes=3)


class HouseConformance(_Episodes, test_utils.EnvironmentTestMixin, absltest.TestCase):
    @pytest.fixture(autouse=True)
    def _cache(self, cache_dir):
        self.cache_dir = cache_dir

    def make_object_under_test(self):
        return dm_adapter.house(seed=0, houses=[SMALL_HOUSE], cache_dir=self.cache_dir, max_steps=10)


def test_house_specs_are_named_bounded_arrays_and_discrete_arrays(cache_dir):
    env = dm_adapter.house(seed=0, houses=[SMALL_HOUSE], cache_dir=cache_dir, stop_action=True)
    spec = env.observation_spec()
    assert spec["rgb"] == specs.BoundedArray((64, 64, 3), np.uint8, 0, 255, name="rgb")
    assert spec["depth"].shape == (64, 64) and spec["depth"].dtype == np.float32 and spec["depth"].maximum == 30.0
    assert spec["target"].num_values == 69 and spec["target"].shape == ()
    assert spec["pose"].minimum.shape == (3,)  # per-element bounds where they differ
    assert env.action_spec() == specs.DiscreteArray(7, dtype=np.int64, name="action")  # 6 = STOP
    env.close()


def test_termination_has_discount_0_and_truncation_discount_1():
    env = dm_adapter.grid_world(seed=0, max_steps=1)
    assert env.reset().first() and env.info["min_steps"] > 1  # one step cannot reach the goal
    last = env.step(0)
    assert last.step_type is StepType.LAST and last.discount == 1.0 and last.reward == 0.0  # truncated
    assert env.step(0).first()  # the step after LAST starts an episode

    env = dm_adapter.grid_world(seed=0)
    goal = int(env.reset().observation["goal"])
    tables = env.env.unwrapped.tables
    m = tables.map_index(env.info["map"])
    obstacles = ~tables.free[m].reshape(tables.height, tables.width)
    path = shortest_path_actions(obstacles, env.info["position"], divmod(int(tables.goal_cells[m, goal]), tables.width))
    steps = [env.step(a) for a in path]
    assert all(s.mid() and s.discount == 1.0 for s in steps[:-1])
    assert steps[-1].last() and steps[-1].discount == 0.0 and steps[-1].reward == 1.0 and env.info["success"]


def test_same_seed_same_episodes():
    def rollout(seed):
        env = dm_adapter.grid_world(seed=seed)
        steps = [env.reset()] + [env.step(a) for a in [0, 1, 2, 3] * 30]
        return [(s.step_type, s.reward, s.observation["goal"].item(), s.observation["image"].tobytes()) for s in steps]

    assert rollout(4) == rollout(4) != rollout(5)


def test_a_suite_is_one_call_and_the_old_module_name_still_answers():
    env = dm_adapter.suite("gridworld", split="unseen-goals", seeds=[5], episodes=2)
    ids = []
    for _ in range(3):
        assert env.reset().first()
        ids.append((env.info["seed"], env.info["episode_id"]))
    assert ids == [(5, 0), (5, 1), (5, 0)]  # the split's episodes in order, then again
    import objsearch

    with pytest.warns(DeprecationWarning, match="objsearch.dm_adapter"):
        from objsearch import dm_env as old
    assert old is dm_adapter and objsearch.dm_adapter is dm_adapter
