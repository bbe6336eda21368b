"""The training-free ``frontier`` agent: its map against the true floor plan, success well
above random, and the worlds it refuses (records that do not depend on the batch:
``tests/eval/test_lockstep.py``)."""

import numpy as np

from objsearch.eval.episode import run_episode
from objsearch.eval.suites.house import HouseSuite
from objsearch.sim.env import HouseEnv
from objsearch.sim.navgraph import HEADING_VECTORS
from objsearch.sim.world import HouseRef
from objsearch_agents.baselines.frontier import RADIUS, FrontierAgent
from objsearch_agents.baselines.random_agent import RandomAgent

SMALL = HouseRef(seed=3)  # ~1700 poses


def test_the_map_never_blocks_a_cell_the_agent_can_stand_on(cache_dir):
    """Every cell the agent's map marks blocked is blocked in the true pose graph, after a
    long walk of a small house (the agent explores it all: the target never ends it)."""
    env = HouseEnv([SMALL], mode="cached", cache_dir=cache_dir, max_steps=250)
    rng = np.random.default_rng(0)
    task = env.sample_task(rng)
    graph = env.world(task.house).graph
    for seed in range(3):
        obs, info = env.reset(options={"task": task})
        agent = FrontierAgent()
        agent.reset(_task(info, seed))
        obs["target"] = 255  # an id no pixel has: explore, never approach
        for _ in range(250):
            obs, _, terminated, truncated, _ = env.step(agent.act(obs))
            obs["target"] = 255
            if terminated or truncated:
                break
        state = agent._slots[0]
        forward, left = HEADING_VECTORS[task.start[2]], HEADING_VECTORS[(task.start[2] + 1) % 4]
        blocked = np.argwhere(state.blocked) - RADIUS
        dx = blocked[:, 0:1] * forward[0] + blocked[:, 1:2] * left[0]
        dy = blocked[:, 0:1] * forward[1] + blocked[:, 1:2] * left[1]
        rows, cols = task.start[0] + dy[:, 0], task.start[1] + dx[:, 0]
        inside = (rows >= 0) & (rows < graph.rows) & (cols >= 0) & (cols < graph.cols)
        wrong = graph.cell_index[rows[inside], cols[inside]] >= 0
        assert inside.sum() > 50, "the walk mapped obstacles"
        assert not wrong.any(), f"free cells marked blocked: {list(zip(rows[inside][wrong], cols[inside][wrong]))}"
        seen = np.argwhere(state.seen & ~state.blocked)
        assert len(seen) > 0.5 * len(graph.cells), "the walk explored most of the house"
        task = env.sample_task(rng)
    env.close()


def _task(info, seed):
    from objsearch.eval.agent import AgentTask

    return AgentTask(
        suite="t", split="t", episode_id=0, goal=0, goal_name="t", observation_space=None, action_space=None,
        rng=np.random.default_rng(seed), camera=info["camera"],
    )  # fmt: skip


def test_frontier_finds_targets_far_more_often_than_random(cache_dir):
    suite = HouseSuite("house-single", cache_dir=cache_dir, max_steps=150)
    env = suite.make_env()
    episodes = suite.episodes("unseen-goals")[:16]
    sr = {}
    for name, agent in (("frontier", FrontierAgent()), ("random", RandomAgent())):
        records = [run_episode(agent, env, suite.name, "unseen-goals", e, 1) for e in episodes]
        assert not any("error" in r for r in records)
        sr[name] = np.mean([r["success"] for r in records])
    assert sr["frontier"] >= 0.8 and sr["random"] <= 0.25, sr


def test_frontier_on_the_grid_world_is_refused_in_one_line(tmp_path):
    import subprocess
    import sys
    from pathlib import Path

    out = subprocess.run(
        [str(Path(sys.executable).parent / "objsearch-eval"), "--agent", "frontier", "--suite", "gridworld"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and "frontier" in out.stderr and "house" in out.stderr, out.stderr


def test_voxel_memory_keeps_sorted_unique_rows():
    from objsearch_agents.baselines.frontier_geometry import unique_voxels

    rng = np.random.default_rng(0)
    for _ in range(50):
        voxels = rng.integers(-40, 600, (int(rng.integers(1, 300)), 3)).astype(np.int32)
        voxels = np.concatenate([voxels, voxels[: len(voxels) // 2]])  # repeats, as frames overlap
        got = unique_voxels(voxels)
        assert got.dtype == np.int32 and np.array_equal(got, np.unique(voxels, axis=0))


def test_view_scores_count_the_voxels_in_view_and_in_sight():
    """Against the textbook form: each voxel is traced on its own (view_scores traces each
    column once), hidden when a cell on the way, other than the target's own, is higher than the ray."""
    from objsearch_agents.baselines.frontier import CELL, STEPS, VOXEL, view_scores

    camera = {"cx": 32, "fx": 32.0, "cy": 32, "fy": 32.0, "camera_height": 1.0}
    rng = np.random.default_rng(1)
    for _ in range(10):
        top = (rng.random((241, 241)) * 1.3).astype(np.float32)
        base = rng.integers(60, 150, 2)
        i, j, k = np.mgrid[0:6, 0:4, 0:8]  # an object: several voxels a column
        voxels = np.stack([i.ravel() + base[0] * 2.5, j.ravel() + base[1] * 2.5, k.ravel() + 3], 1).astype(np.int32)
        voxels = voxels[rng.random(len(voxels)) < 0.7]
        cells = np.argwhere(np.ones((12, 12), bool)) + base - 6
        target_cells = {tuple(c) for c in np.rint((voxels[:, :2] + 0.5) * VOXEL / CELL).astype(int)}
        want = np.zeros((len(cells), 4))
        for c, cell in enumerate(cells):
            for vox in voxels:
                v = (vox + 0.5) * VOXEL
                rel, up = v[:2] - cell * CELL, v[2] - camera["camera_height"]
                t = np.linspace(0.1, 0.9, 8)
                on_way = np.rint((cell * CELL + t[:, None] * rel) / CELL).astype(int)
                own = np.array([tuple(c) in target_cells for c in on_way])
                if np.any((top[on_way[:, 0], on_way[:, 1]] > camera["camera_height"] + t * up + 0.05) & ~own):
                    continue
                for h, (di, dj) in enumerate(STEPS):
                    fwd, left = rel[0] * di + rel[1] * dj, -rel[0] * dj + rel[1] * di
                    if fwd > 0.1 and abs(left) <= fwd and abs(up) <= fwd:
                        want[c, h] += 1.0 / max(fwd, 0.2) ** 2
        assert np.allclose(view_scores(cells, voxels, top, camera), want)
        assert (want > 0).any() and (want == 0).any()
