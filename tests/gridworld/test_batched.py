import numpy as np
import pytest

from objsearch.gridworld import dataset
from objsearch.gridworld.batched import WINDOW, BatchedGridWorld, GridTables
from objsearch.gridworld.env import GridWorldEnv
from objsearch.gridworld.maps import MOVES, bfs_distances
from objsearch.gridworld.tasks import GridTask


@pytest.fixture(scope="module")
def tables():
    return GridTables.build(list(dataset.test_maps().values()))


def test_tables_distances_match_bfs(tables):
    maps = list(dataset.test_maps().values())
    for mi in (0, 7, 19):
        for g in range(16):
            ref = bfs_distances(maps[mi].obstacles, tuple(maps[mi].goals[g])).ravel()
            assert np.array_equal(tables.goal_dist[mi, g], ref)


class Reference:
    """One episode played straight from a ``GridMap`` (its obstacle array and goal cells),
    without any of the simulator's tables: the grid world as the env's docstring defines it."""

    def __init__(self, grid_map, goal, start, max_steps, observation):
        self.map, self.goal, self.pos, self.steps, self.max_steps = grid_map, int(goal), tuple(start), 0, max_steps
        self.goal_cell = tuple(int(v) for v in grid_map.goals[self.goal])
        self.dist = bfs_distances(grid_map.obstacles, self.goal_cell)
        self.min_steps = int(self.dist[self.pos])
        h = WINDOW // 2
        layers = [np.pad(grid_map.obstacles.astype(np.uint8), h, constant_values=1)]  # off the map reads obstacle
        shown = [self.goal] if observation == "goal" else range(grid_map.num_goals)
        for g in shown:
            layer = np.zeros(grid_map.shape, np.uint8)
            layer[tuple(grid_map.goals[g])] = 1
            layers.append(np.pad(layer, h))
        self.layers = np.stack(layers)

    def image(self):
        r, c = self.pos
        return self.layers[:, r : r + WINDOW, c : c + WINDOW]

    def step(self, action):
        r, c = self.pos[0] + MOVES[action][0], self.pos[1] + MOVES[action][1]
        height, width = self.map.shape
        if 0 <= r < height and 0 <= c < width and not self.map.obstacles[r, c]:
            self.pos = (int(r), int(c))
        self.steps += 1
        success = self.pos == self.goal_cell
        return float(success), success, not success and self.steps >= self.max_steps

    def toward_goal(self):
        """The first action that brings the agent one step closer to the goal."""
        for a, (dr, dc) in enumerate(MOVES):
            r, c = self.pos[0] + dr, self.pos[1] + dc
            if 0 <= r < self.map.shape[0] and 0 <= c < self.map.shape[1] and self.dist[r, c] == self.dist[self.pos] - 1:
                return a
        raise AssertionError("no step toward the goal")


@pytest.mark.parametrize("autoreset", [False, True])
@pytest.mark.parametrize("observation", ["goal", "all_goals"])
def test_batched_equals_independent_single_envs(tables, observation, autoreset):
    """N = 8 batched episodes, stepped for 80 steps with ends and new episodes, against 8
    independent ``GridWorldEnv``s (their own tables, built from the same maps) reset to the
    same tasks, and against episodes played straight from the maps (``Reference``)."""
    maps = list(dataset.test_maps().values())
    n, max_steps = 8, 12
    world = BatchedGridWorld(
        tables,
        n,
        goals=None,
        observation=observation,
        max_steps=max_steps,
        autoreset=autoreset,
        rng=np.random.default_rng(0),
    )
    own_tables = GridTables.build(maps)  # not the batch's: nothing shared but the maps
    singles = [
        GridWorldEnv(maps=own_tables, goals=None, observation=observation, max_steps=max_steps) for _ in range(n)
    ]
    refs = [None] * n
    task_rng, act_rng = np.random.default_rng(1), np.random.default_rng(2)

    def start_single(i, m, goal, cell):
        """Reset single env ``i`` and its reference to the batch's episode; check the first observation."""
        start = divmod(int(cell), tables.width)
        refs[i] = Reference(maps[m], goal, start, max_steps, observation)
        task = GridTask(map=maps[m].name, start=start, goal=int(goal), min_steps=refs[i].min_steps)
        o, info = singles[i].reset(options={"task": task})
        assert np.array_equal(o["image"], world_obs["image"][i]) and np.array_equal(o["image"], refs[i].image())
        assert o["goal"] == world_obs["goal"][i] == goal
        assert info["position"] == tuple(world.positions()[i]) == start
        assert info["min_steps"] == world.min_steps[i] == refs[i].min_steps > 0
        assert info["map"] == maps[m].name and info["steps"] == 0 and info["success"] is False

    def new_tasks(ids):
        """Tasks for ``ids``: half start within 3 steps of their goal, so episodes also end in success."""
        m, g, s = world.sample_tasks(len(ids))
        for k in range(len(ids)):
            if task_rng.random() < 0.5:
                near = np.flatnonzero((tables.goal_dist[m[k], g[k]] > 0) & (tables.goal_dist[m[k], g[k]] <= 3))
                s[k] = task_rng.choice(near)
        return m, g, s

    m, g, s = new_tasks(range(n))
    world_obs = world.reset(maps=m, goals=g, starts=s)
    for i in range(n):
        start_single(i, m[i], g[i], s[i])
    ends = {"terminated": 0, "truncated": 0}
    for _ in range(80):
        # mostly random moves (into walls too), some toward the goal
        actions = [refs[i].toward_goal() if act_rng.random() < 0.3 else int(act_rng.integers(4)) for i in range(n)]
        world_obs, reward, terminated, truncated, info = world.step(np.array(actions))
        ended = []
        for i, env in enumerate(singles):
            o, r, te, tr, inf = env.step(actions[i])
            assert (r, te, tr) == refs[i].step(actions[i]) == (reward[i], terminated[i], truncated[i])
            assert inf["position"] == refs[i].pos and inf["steps"] == info["steps"][i] == refs[i].steps
            assert inf["success"] == info["success"][i] == te and inf["min_steps"] == info["min_steps"][i]
            if te or tr:
                ended.append(i)
                ends["terminated" if te else "truncated"] += 1
            if not (autoreset and (te or tr)):  # autoreset: the batch already shows the new episode
                assert np.array_equal(o["image"], world_obs["image"][i]) and np.array_equal(o["image"], refs[i].image())
                assert o["goal"] == world_obs["goal"][i] and inf["position"] == tuple(world.positions()[i])
        if autoreset:  # the batch drew the new episodes itself: play the same ones in the singles
            for i in ended:
                assert world.steps[i] == 0
                start_single(i, int(world.map_idx[i]), int(world.goal[i]), int(world.cell[i]))
        elif ended:
            m, g, s = new_tasks(ended)
            world_obs = world.reset(env_ids=ended, maps=m, goals=g, starts=s)
            for k, i in enumerate(ended):
                start_single(i, m[k], g[k], s[k])
    assert ends["terminated"] >= 5 and ends["truncated"] >= 5, ends  # both kinds of end were compared


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
