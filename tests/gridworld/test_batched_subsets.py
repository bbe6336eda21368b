"""``BatchedGridWorld.start`` / ``step_envs`` / ``observe(env_ids)``: some envs moved, the
others left alone, and what they return is the rows of a whole-batch call."""

import numpy as np

from objsearch.gridworld import dataset
from objsearch.gridworld.batched import BatchedGridWorld, GridTables


def test_subset_calls_are_the_rows_of_whole_batch_calls():
    tables = GridTables.build(list(dataset.test_maps().values()))
    n = 12
    whole = BatchedGridWorld(
        tables, n, observation="all_goals", max_steps=9, autoreset=False, rng=np.random.default_rng(0)
    )
    part = BatchedGridWorld(tables, n, observation="all_goals", max_steps=9, autoreset=False)
    maps, goals, starts = whole.sample_tasks(n)
    obs = whole.reset(maps=maps, goals=goals, starts=starts)
    order = np.array([5, 0, 11, 3, 1, 2, 4, 6, 7, 8, 9, 10])
    sub = part.start(order, maps[order], goals[order], starts[order])
    assert np.array_equal(sub["image"], obs["image"][order]) and np.array_equal(sub["goal"], goals[order])
    rng = np.random.default_rng(1)
    for _ in range(12):
        actions = rng.integers(4, size=n)
        moving = np.sort(rng.choice(n, size=5, replace=False))[::-1]  # any order
        before = (part.cell.copy(), part.steps.copy())
        o, r, term, trunc, info = part.step_envs(moving, actions[moving])
        still = np.setdiff1d(np.arange(n), moving)
        assert np.array_equal(part.cell[still], before[0][still]) and np.array_equal(
            part.steps[still], before[1][still]
        )
        # the same envs, stepped one by one through whole-batch calls of a copy
        ref = BatchedGridWorld(tables, n, observation="all_goals", max_steps=9, autoreset=False)
        ref.reset(maps=part.map_idx, goals=part.goal, starts=before[0])
        ref.steps[:] = before[1]
        ref.min_steps[:] = part.min_steps
        wo, wr, wterm, wtrunc, winfo = ref.step(np.where(np.isin(np.arange(n), moving), actions, 0))
        assert np.array_equal(o["image"], wo["image"][moving]) and np.array_equal(o["goal"], wo["goal"][moving])
        assert (
            np.array_equal(r, wr[moving])
            and np.array_equal(term, wterm[moving])
            and np.array_equal(trunc, wtrunc[moving])
        )
        for key in ("success", "steps", "min_steps"):
            assert np.array_equal(info[key], winfo[key][moving])
        assert np.array_equal(part.observe(moving)["image"], o["image"])
    goal_obs = BatchedGridWorld(tables, n, observation="goal", autoreset=False)
    goal_obs.reset(maps=maps, goals=goals, starts=starts)
    assert np.array_equal(goal_obs.observe(order)["image"], goal_obs.observe()["image"][order])
