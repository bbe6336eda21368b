"""Running an agent over a suite's fixed episodes: one process or a pool of workers.

Every (split, seed, episode) is an independent unit with its own random Generator derived
from those three values, and the agent is reset before each, so the records do not depend
on the order episodes run in or on the number of workers.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import zlib
from dataclasses import asdict, dataclass, field

import numpy as np
from tqdm import tqdm

from objsearch.eval.agent import AgentTask
from objsearch.eval.registry import make_agent
from objsearch.eval.suites import Episode, check_splits, make_suite

PAPER_SEEDS = (1, 5, 13, 45, 99)


@dataclass(frozen=True)
class EvalConfig:
    """Everything that determines an evaluation's results.

    Attributes:
        agent: registered agent name or ``package.module:Class``.
        suite: suite name.
        splits: splits to run (empty: all of the suite's).
        seeds: evaluation seeds; every episode is run once per seed.
        checkpoint: path passed to the agent's ``load``, if any.
        suite_config: arguments of the suite (e.g. ``maps``, ``tasks``, ``max_steps``).
    """

    agent: str
    suite: str = "gridworld"
    splits: tuple[str, ...] = ()
    seeds: tuple[int, ...] = PAPER_SEEDS
    checkpoint: str | None = None
    suite_config: dict = field(default_factory=dict)

    def to_json(self) -> dict:
        out = asdict(self)
        out["splits"], out["seeds"] = list(self.splits), list(self.seeds)
        return out


def episode_rng(seed: int, split: str, episode_id: int) -> np.random.Generator:
    """The Generator of one (seed, split, episode): independent of run order and workers."""
    return np.random.default_rng([seed, zlib.crc32(split.encode()), episode_id])


def run_episode(agent, env, suite_name: str, split: str, episode: Episode, seed: int) -> dict:
    """Play one episode and return its record."""
    obs, info = env.reset(seed=seed, options={"task": episode.task})
    if info.get("min_steps", episode.min_steps) != episode.min_steps:
        raise RuntimeError(f"env and suite disagree on min_steps of {split}/{episode.episode_id}")
    agent.reset(
        AgentTask(
            suite=suite_name,
            split=split,
            episode_id=episode.episode_id,
            goal=episode.goal,
            goal_name=episode.goal_name,
            observation_space=env.observation_space,
            action_space=env.action_space,
            rng=episode_rng(seed, split, episode.episode_id),
            privileged=episode.privileged,
        )
    )
    steps = 0
    while True:
        obs, _, terminated, truncated, info = env.step(agent.act(obs))
        steps += 1
        if terminated or truncated:
            break
    return {
        "split": split,
        "seed": seed,
        "episode_id": episode.episode_id,
        "goal": episode.goal_name,
        "success": bool(info["success"]),
        "steps": steps,
        "min_steps": episode.min_steps,
        "task": episode.describe,
    }


class _Worker:
    """An agent, a suite and its env: built once per process, then fed work units."""

    def __init__(self, config: EvalConfig):
        self.suite = make_suite(config.suite, **config.suite_config)
        self.env = self.suite.make_env()
        self.agent = make_agent(config.agent, config.checkpoint)
        self.episodes: dict[str, list[Episode]] = {}

    def run(self, split: str, seed: int, episode_id: int) -> dict:
        if split not in self.episodes:
            self.episodes[split] = self.suite.episodes(split)
        episode = self.episodes[split][episode_id]
        return run_episode(self.agent, self.env, self.suite.name, split, episode, seed)


_worker: _Worker | None = None


def _init_worker(config: EvalConfig) -> None:
    global _worker
    _worker = _Worker(config)


def _run_chunk(units: list[tuple[str, int, int]]) -> list[dict]:
    return [_worker.run(*unit) for unit in units]


def run_units(config: EvalConfig, units: list[tuple[str, int, int]], workers: int = 1, progress: bool = True) -> list[dict]:
    """Run (split, seed, episode_id) units and return their records in the units' order."""
    bar = tqdm(total=len(units), desc=f"{config.agent} on {config.suite}", unit="ep", disable=not progress or None)
    records: list[dict] = []
    try:
        if workers <= 1:
            worker = _Worker(config)
            for unit in units:
                records.append(worker.run(*unit))
                bar.update()
        else:
            chunk = max(1, min(50, len(units) // (workers * 4)))
            chunks = [units[i : i + chunk] for i in range(0, len(units), chunk)]
            context = multiprocessing.get_context("spawn")  # no fork: torch and EGL dislike it
            with cf.ProcessPoolExecutor(workers, mp_context=context, initializer=_init_worker, initargs=(config,)) as pool:
                for part in pool.map(_run_chunk, chunks):
                    records.extend(part)
                    bar.update(len(part))
    finally:
        bar.close()
    return records


def plan_units(suite, splits: list[str], seeds: tuple[int, ...]) -> list[tuple[str, int, int]]:
    """Every (split, seed, episode_id), in report order."""
    return [(split, seed, ep.episode_id) for split in splits for seed in seeds for ep in suite.episodes(split)]


def evaluate(config: EvalConfig, workers: int = 1, progress: bool = True) -> dict:
    """Evaluate ``config.agent`` on ``config.suite`` and return the results dict."""
    from objsearch.eval.results import build_results

    suite = make_suite(config.suite, **config.suite_config)
    splits = check_splits(suite, list(config.splits))
    make_agent(config.agent, config.checkpoint)  # fail fast on a bad agent, before any worker starts
    config = EvalConfig(
        agent=config.agent,
        suite=config.suite,
        splits=tuple(splits),
        seeds=config.seeds,
        checkpoint=config.checkpoint,
        suite_config=suite.config(),
    )
    records = run_units(config, plan_units(suite, splits, config.seeds), workers=workers, progress=progress)
    return build_results(config, suite, records)
