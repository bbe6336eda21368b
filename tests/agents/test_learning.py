"""DQN must learn: on a tiny map it beats random by a clear margin within ~30 s of CPU."""

from dataclasses import replace

import numpy as np
import torch

from objsearch.gridworld.batched import BatchedGridWorld, GridTables
from objsearch.gridworld.maps import GridMap
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.gridworld.train import TrainRun


def tiny_map() -> GridMap:
    obstacles = np.ones((8, 8), np.uint8)
    obstacles[1:-1, 1:-1] = 0
    obstacles[2, 2:5] = 1
    obstacles[4:6, 4] = 1
    obstacles[5, 2] = 1
    return GridMap("tiny", obstacles, np.array([[1, 6], [6, 1]]))


def success_rate(grid_map, act, episodes=512, max_steps=20, seed=123) -> float:
    env = BatchedGridWorld(
        GridTables.build([grid_map]),
        episodes,
        goals=(0, 1),
        observation="all_goals",
        max_steps=max_steps,
        autoreset=False,
        rng=np.random.default_rng(seed),
    )
    obs, rng = env.reset(), np.random.default_rng(seed + 1)
    alive, won = np.ones(episodes, bool), np.zeros(episodes, bool)
    for _ in range(max_steps):
        obs, _, term, trunc, _ = env.step(act(obs, rng))
        won |= term & alive
        alive &= ~(term | trunc)
    return float(won.mean())


def test_dqn_beats_random_on_a_tiny_map(tmp_path):
    torch.set_num_threads(1)
    grid_map = tiny_map()
    config = replace(
        GridAgentConfig(),
        method="dqn",
        seed=0,
        num_envs=16,
        max_steps=20,
        episodes=1200,
        lr=1e-3,
        gamma=0.9,
        learning_starts=256,
        batch_size=32,
        update_every=4,
        target_update=500,
        eps_anneal_episodes=600,
        curriculum_episodes=300,
        checkpoint_every=10**9,
        log_every=500,
    )
    run = TrainRun(config, tmp_path, [grid_map], goals=(0, 1))
    run.begin()
    run.run(progress=False)
    policy = run.policy
    policy.start(512)

    def dqn(obs, rng):  # evaluated as the authors did: epsilon 0.1
        policy.goal[:] = obs["goal"]
        return policy.actions(obs["image"], 0.1, rng)[0]

    learned = success_rate(grid_map, dqn)
    random = success_rate(grid_map, lambda obs, rng: rng.integers(4, size=len(obs["goal"])))
    print(f"learning test: DQN {learned:.3f} vs random {random:.3f}")
    assert learned >= random + 0.25, (learned, random)
