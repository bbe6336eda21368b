"""Running an agent over a suite's fixed episodes: in one process, a pool of worker
processes, or a Ray cluster.

Every (split, seed, episode) is an independent unit with its own random Generator derived
from those three values, and the agent is reset before each, so the records do not depend
on the order units run in, the number of workers or the executor. An agent that raises,
returns an invalid action or exceeds the per-step time limit fails that episode (the record
keeps the error) and the run goes on. With a partial-results file, finished units are
appended as they complete, and a rerun with the same configuration skips them.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import json
import multiprocessing
import signal
import threading
import time
import zlib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable, Iterable

import numpy as np
from tqdm import tqdm

from objsearch.errors import UserError
from objsearch.eval.agent import AgentTask
from objsearch.eval.registry import make_agent
from objsearch.eval.suites import Episode, check_splits, make_suite

PAPER_SEEDS = (1, 5, 13, 45, 99)
EXECUTORS = ("local", "ray")
Unit = tuple[str, int, int]  # (split, seed, episode_id)


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
        step_time_limit: seconds an agent may take for one ``act`` (or ``reset``); past it
            the episode fails. None: no limit.
    """

    agent: str
    suite: str = "gridworld"
    splits: tuple[str, ...] = ()
    seeds: tuple[int, ...] = PAPER_SEEDS
    checkpoint: str | None = None
    suite_config: dict = field(default_factory=dict)
    step_time_limit: float | None = 10.0

    def to_json(self) -> dict:
        out = asdict(self)
        out["splits"], out["seeds"] = list(self.splits), list(self.seeds)
        return out


def episode_rng(seed: int, split: str, episode_id: int) -> np.random.Generator:
    """The Generator of one (seed, split, episode): independent of run order and workers."""
    return np.random.default_rng([seed, zlib.crc32(split.encode()), episode_id])


class StepTimeLimit(Exception):
    """An agent call ran past the step time limit."""


@contextlib.contextmanager
def _time_limit(seconds: float | None):
    """Interrupt the block after ``seconds`` (SIGALRM, main thread only); elsewhere the
    limit is checked when the call returns."""
    if seconds is None:
        yield
        return
    use_alarm = threading.current_thread() is threading.main_thread() and hasattr(signal, "setitimer")
    if use_alarm:

        def on_alarm(signum, frame):
            raise StepTimeLimit

        previous = signal.signal(signal.SIGALRM, on_alarm)
        signal.setitimer(signal.ITIMER_REAL, seconds)
    start = time.monotonic()
    try:
        yield
    finally:
        if use_alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
    if time.monotonic() - start > seconds:
        raise StepTimeLimit


def run_episode(
    agent,
    env,
    suite_name: str,
    split: str,
    episode: Episode,
    seed: int,
    step_time_limit: float | None = None,
    trajectory: list | None = None,
) -> dict:
    """Play one episode and return its record (``error`` is set if the agent failed it).

    With ``trajectory`` (a list), every (observation, info) of the episode is appended to it.
    """
    obs, info = env.reset(seed=seed, options={"task": episode.task})
    if trajectory is not None:
        trajectory.append((obs, info))
    if info.get("min_steps", episode.min_steps) != episode.min_steps:
        raise RuntimeError(f"env and suite disagree on min_steps of {split}/{episode.episode_id}")
    task = AgentTask(
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
    steps, success, error = 0, False, None
    try:
        with _time_limit(step_time_limit):
            agent.reset(task)
        while True:
            with _time_limit(step_time_limit):
                action = agent.act(obs)
            if not env.action_space.contains(action):
                raise ValueError(f"invalid action {action!r} for action space {env.action_space}")
            obs, _, terminated, truncated, info = env.step(action)
            steps += 1
            if trajectory is not None:
                trajectory.append((obs, info))
            if terminated or truncated:
                success = bool(info["success"])
                break
    except StepTimeLimit:
        error = f"step time limit of {step_time_limit:g} s exceeded at step {steps}"
    except Exception as err:  # the agent's failure is the episode's, not the run's
        error = f"{type(err).__name__}: {err}"
    record = {
        "split": split,
        "seed": seed,
        "episode_id": episode.episode_id,
        "goal": episode.goal_name,
        "success": success,
        "steps": steps,
        "min_steps": episode.min_steps,
        "task": episode.describe,
    }
    if error is not None:
        record["error"] = error
    return record


class Worker:
    """An agent, a suite and its env: built once per process (or Ray actor), then fed units.

    With ``video_dir``, each episode's pictures are written there by the suite's
    ``write_video(directory, record, episode, trajectory)``."""

    def __init__(self, config: EvalConfig, video_dir: str | None = None):
        self.config, self.video_dir = config, video_dir
        self.suite = make_suite(config.suite, **config.suite_config)
        self.env = self.suite.make_env()
        self.agent = make_agent(config.agent, config.checkpoint)
        self.episodes: dict[str, list[Episode]] = {}

    def run(self, split: str, seed: int, episode_id: int) -> dict:
        if split not in self.episodes:
            self.episodes[split] = self.suite.episodes(split)
        episode = self.episodes[split][episode_id]
        trajectory = [] if self.video_dir else None
        record = run_episode(self.agent, self.env, self.suite.name, split, episode, seed, self.config.step_time_limit, trajectory)
        if self.video_dir:
            self.suite.write_video(self.video_dir, record, episode, trajectory)
        return record

    def run_chunk(self, units: list[Unit]) -> list[dict]:
        return [self.run(*unit) for unit in units]


_worker: Worker | None = None


def _init_worker(config: EvalConfig, video_dir: str | None) -> None:
    global _worker
    _worker = Worker(config, video_dir)


def _run_chunk(units: list[Unit]) -> list[dict]:
    return _worker.run_chunk(units)


def _chunks(units: list[Unit], workers: int) -> list[list[Unit]]:
    size = max(1, min(50, len(units) // (workers * 4)))
    return [units[i : i + size] for i in range(0, len(units), size)]


def _run_local(config: EvalConfig, units: list[Unit], workers: int, video_dir, done: Callable[[list[dict]], None]) -> None:
    if workers <= 1:
        worker = Worker(config, video_dir)
        for unit in units:
            done([worker.run(*unit)])
        return
    context = multiprocessing.get_context("spawn")  # no fork: torch and EGL dislike it
    with cf.ProcessPoolExecutor(workers, mp_context=context, initializer=_init_worker, initargs=(config, video_dir)) as pool:
        for part in pool.map(_run_chunk, _chunks(units, workers)):
            done(part)


def _run_ray(
    config: EvalConfig, units: list[Unit], workers: int, address: str | None, video_dir, done: Callable[[list[dict]], None]
) -> None:
    try:
        import ray
        from ray.util import ActorPool
    except ImportError:
        raise UserError("--executor ray needs Ray: pip install 'objsearch[ray]'") from None
    started_here = not ray.is_initialized()
    if started_here:
        init = {"address": address} if address else {"num_cpus": workers}
        ray.init(**init, include_dashboard=False, logging_level="ERROR", log_to_driver=False)
    try:
        if address:
            workers = max(workers, int(ray.cluster_resources().get("CPU", 1)))
        actors = [ray.remote(num_cpus=1)(Worker).remote(config, video_dir) for _ in range(workers)]
        chunks = _chunks(units, workers)
        for part in ActorPool(actors).map_unordered(lambda actor, chunk: actor.run_chunk.remote(chunk), chunks):
            done(part)
    finally:
        if started_here:
            ray.shutdown()


class PartialResults:
    """Finished records of an evaluation, appended to ``<out>.partial.jsonl`` as they come.

    The first line is the configuration; a rerun with the same configuration resumes, one
    with another is refused. A line cut short by an interruption is ignored.
    """

    def __init__(self, path: str | Path, config: EvalConfig):
        self.path = Path(path)
        header = {"partial_results_of": config.to_json()}
        self.records: list[dict] = []
        if self.path.exists():
            lines = self.path.read_text().splitlines()
            try:
                first = json.loads(lines[0]) if lines else None
            except json.JSONDecodeError:
                first = None
            if first != header:
                raise UserError(
                    f"{self.path} holds partial results of another evaluation; delete it or choose another --out"
                )
            for line in lines[1:]:
                try:
                    self.records.append(json.loads(line))
                except json.JSONDecodeError:
                    break  # the interrupted write
            self.path.write_text("".join(json.dumps(x) + "\n" for x in [header, *self.records]))
        else:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text(json.dumps(header) + "\n")
        self._file = open(self.path, "a")

    def done_units(self) -> set[Unit]:
        return {(r["split"], r["seed"], r["episode_id"]) for r in self.records}

    def add(self, records: Iterable[dict]) -> None:
        for record in records:
            self._file.write(json.dumps(record) + "\n")
        self._file.flush()

    def close(self) -> None:
        self._file.close()


def run_units(
    config: EvalConfig,
    units: list[Unit],
    workers: int = 1,
    executor: str = "local",
    address: str | None = None,
    partial: PartialResults | None = None,
    progress: bool = True,
    video_dir: str | None = None,
) -> list[dict]:
    """Run (split, seed, episode_id) units and return their records in the units' order.

    Units already in ``partial`` are not run again; new records are appended to it."""
    if executor not in EXECUTORS:
        raise UserError(f"unknown executor {executor!r}; choose one of {', '.join(EXECUTORS)}")
    finished = {(r["split"], r["seed"], r["episode_id"]): r for r in (partial.records if partial else [])}
    todo = [u for u in units if u not in finished]
    bar = tqdm(total=len(units), initial=len(units) - len(todo), desc=f"{config.agent} on {config.suite}", unit="ep", disable=not progress or None)

    def done(records: list[dict]) -> None:
        for r in records:
            finished[(r["split"], r["seed"], r["episode_id"])] = r
        if partial:
            partial.add(records)
        bar.update(len(records))

    try:
        if todo and executor == "ray":
            _run_ray(config, todo, workers, address, video_dir, done)
        elif todo:
            _run_local(config, todo, workers, video_dir, done)
    finally:
        bar.close()
    return [finished[u] for u in units]


def plan_units(suite, splits: list[str], seeds: tuple[int, ...]) -> list[Unit]:
    """Every (split, seed, episode_id), in report order."""
    return [(split, seed, ep.episode_id) for split in splits for seed in seeds for ep in suite.episodes(split)]


def evaluate(
    config: EvalConfig,
    workers: int = 1,
    progress: bool = True,
    executor: str = "local",
    address: str | None = None,
    out: str | Path | None = None,
    video_dir: str | None = None,
) -> dict:
    """Evaluate ``config.agent`` on ``config.suite`` and return the results dict.

    With ``out``, the results JSON is written there; until it is, finished episodes are
    kept in ``<out>.partial.jsonl`` and a rerun of the same configuration resumes from it.
    With ``video_dir``, every episode's pictures are written there (suites that have them).
    """
    from objsearch.eval.results import build_results
    from objsearch.fileio import write_json

    suite = make_suite(config.suite, **config.suite_config)
    splits = check_splits(suite, list(config.splits))
    if video_dir and not hasattr(suite, "write_video"):
        raise UserError(f"--video is not available for suite {config.suite!r} (house suites have it)")
    make_agent(config.agent, config.checkpoint)  # fail fast on a bad agent, before any worker starts
    config = EvalConfig(
        agent=config.agent,
        suite=config.suite,
        splits=tuple(splits),
        seeds=config.seeds,
        checkpoint=config.checkpoint,
        suite_config=suite.config(),
        step_time_limit=config.step_time_limit,
    )
    partial = PartialResults(f"{out}.partial.jsonl", config) if out else None
    try:
        units = plan_units(suite, splits, config.seeds)
        records = run_units(config, units, workers, executor, address, partial, progress, video_dir)
    finally:
        if partial:
            partial.close()
    results = build_results(config, suite, records)
    if out:
        write_json(out, results)
        partial.path.unlink(missing_ok=True)
    return results
