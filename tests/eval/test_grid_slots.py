"""The grid world's lockstep slots (``GridWorldSuite.make_slots``: every slot in one
``BatchedGridWorld``) give what one ``GridWorldEnv`` per slot gives, and the suite's fast
task reading and oracle paths are those of ``tasks.load_tasks`` and
``maps.shortest_path_actions``."""

import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.eval.episode import run_episode
from objsearch.eval.lockstep import EnvSlots, play_lockstep
from objsearch.eval.suites import make_suite
from objsearch.gridworld import dataset
from objsearch.gridworld.maps import shortest_path_actions
from objsearch.gridworld.tasks import load_tasks
from objsearch_agents.baselines.random_agent import RandomAgent


class OddActionsAgent(RandomAgent):
    """Not batched; returns actions of every type a Discrete space meets: plain and numpy
    ints, 0-d arrays, bools, floats, out of range."""

    ODD = (np.int64(2), np.array(1), np.uint8(3), True, 4, -1, 2.0, np.int32(0), "up", None)

    def reset(self, task):
        super().reset(task)
        self._odd = task.episode_id % 3 == 0

    def act(self, observation):
        a = super().act(observation)
        if self._odd and self._rng.random() < 0.15:
            return self.ODD[int(self._rng.integers(len(self.ODD)))]
        return a


def test_slots_show_each_slot_what_its_own_env_would():
    suite = make_suite("gridworld", max_steps=12)
    episodes = suite.episodes("all-goals")
    n = 9
    fast, envs = suite.make_slots(n), EnvSlots([suite.make_env() for _ in range(n)])
    rng = np.random.default_rng(0)
    playing, next_ep = {}, 0
    for _ in range(200):
        free = [i for i in range(n) if i not in playing][: rng.integers(0, n + 1)]
        starts = {i: (episodes[(next_ep + k) % len(episodes)], 1) for k, i in enumerate(free)}
        next_ep += len(free)
        a, b = fast.start(starts), envs.start(starts)
        for i in starts:
            assert np.array_equal(a[i][0]["image"], b[i][0]["image"]) and a[i][0]["goal"] == b[i][0]["goal"]
            assert a[i][1] == b[i][1]
            playing[i] = True
        actions = {
            i: OddActionsAgent.ODD[rng.integers(10)] if rng.random() < 0.2 else int(rng.integers(4))
            for i in playing
            if rng.random() < 0.8
        }
        for i, action in actions.items():
            assert fast.valid(i, action) == envs.valid(i, action), action
        actions = {i: x for i, x in actions.items() if envs.valid(i, x)}
        a, b = fast.step(actions), envs.step(actions)
        assert list(a) == list(b)
        for i in actions:
            (oa, ta, ua, ia), (ob, tb, ub, ib) = a[i], b[i]
            assert np.array_equal(oa["image"], ob["image"]) and oa["image"].dtype == ob["image"].dtype
            assert oa["goal"] == ob["goal"] and (ta, ua, ia["success"]) == (tb, ub, ib["success"])
            assert type(ta) is type(tb) is bool and ia["steps"] == ib["steps"]
            if ta or ua:
                del playing[i]
    assert fast.action_space(0) == envs.action_space(0) and fast.observation_space(3) == envs.observation_space(3)


@pytest.mark.parametrize("agent", [RandomAgent, OddActionsAgent])
def test_lockstep_on_the_slots_gives_the_sequential_records(agent):
    suite = make_suite("gridworld", max_steps=15)
    episodes = {split: suite.episodes(split) for split in ("unseen-goals", "all-goals")}
    units = [(split, seed, e.episode_id) for split in episodes for seed in (1, 5) for e in episodes[split]]
    env = suite.make_env()
    sequential = [
        run_episode(agent(), env, suite.name, split, episodes[split][ep], seed, None) for split, seed, ep in units
    ]
    assert any("invalid action" in r.get("error", "") for r in sequential) == (agent is OddActionsAgent)
    for n in (1, 7, 64):
        records = list(play_lockstep(units, suite.make_slots(n), agent, lambda s, e: episodes[s][e], suite.name, None))
        by_unit = {(r["split"], r["seed"], r["episode_id"]): r for r in records}
        assert [by_unit[u] for u in units] == sequential, n


def test_fast_task_reading_and_oracle_paths_are_the_reference_ones(tmp_path):
    suite = make_suite("gridworld")
    maps = dataset.test_maps()
    for split in dataset.SPLIT_GOALS:
        episodes = suite.episodes(split)
        assert [e.task for e in episodes] == dataset.split_tasks(split)
        for e in episodes:
            grid_map, task = maps[e.task.map], e.task
            assert e.privileged.shortest_path() == shortest_path_actions(
                grid_map.obstacles, task.start, tuple(grid_map.goals[task.goal])
            )
    # a user's task file: the same tasks; a bad line still gets load_tasks' message
    lines = (dataset.DATA_DIR / "tasks" / "all-goals.jsonl").read_text().splitlines()
    good = tmp_path / "mine.jsonl"
    good.write_text("\n".join(lines[:10]) + "\n\n")
    test_dir = str(dataset.DATA_DIR / "test")
    mine = make_suite("gridworld", maps=test_dir, tasks=str(good))
    assert [e.task for e in mine.episodes("mine")] == load_tasks(good, maps)
    bad = tmp_path / "bad.jsonl"
    bad.write_text(lines[0] + '\n{"map": "map_0105", "start": [0, 0], "goal": 3}\n')
    with pytest.raises(UserError, match=r"bad.jsonl:2: start \[0, 0\] is not a free cell"):
        make_suite("gridworld", maps=test_dir, tasks=str(bad)).episodes("bad")
