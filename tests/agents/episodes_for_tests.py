"""Scoring house agents on trivial tasks, for the tests of the learned house agents."""

import numpy as np

from objsearch_agents.house.episodes import EpisodeBatch


def trivial_success(houses, act, episodes=256, max_steps=30, seed=5, pool="approach", curriculum=1000) -> float:
    """Success within ``max_steps`` of ``act(batch, rng) -> actions`` from starts of ``pool``
    drawn by ``TrainingHouses.sample`` with ``curriculum`` (1: the nearest starts only)."""
    rng = np.random.default_rng(seed)
    batch = EpisodeBatch(houses, episodes, max_steps)
    pairs, starts = houses.sample(pool, np.zeros(episodes, np.int64), curriculum, rng)
    batch.start(np.arange(episodes), pairs, starts)
    alive, won = np.ones(episodes, bool), np.zeros(episodes, bool)
    for _ in range(max_steps):
        success, truncated = batch.step(act(batch, rng))
        won |= success & alive
        alive &= ~(success | truncated)
    return float(won.mean())
