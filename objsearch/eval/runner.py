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
import json
import multiprocessing
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable, Iterable

from tqdm import tqdm

from objsearch.cluster import EXECUTORS, one_math_thread
from objsearch.errors import UserError
from objsearch.eval.episode import episode_rng, run_episode  # noqa: F401  (episode_rng: part of this module's API)
from objsearch.eval.lockstep import play_lockstep
from objsearch.eval.registry import make_agent
from objsearch.eval.suites import Episode, check_splits, make_suite

PAPER_SEEDS = (1, 5, 13, 45, 99)
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


class Worker:
    """An agent, a suite and its env: built once per process (or Ray actor), then fed units.

    With ``video_dir``, each episode's pictures are written there by the suite's
    ``write_video(directory, record, episode, trajectory)``. With ``batch`` > 1, units are
    played ``batch`` at a time in lockstep (``objsearch.eval.lockstep``), one env per slot."""

    def __init__(self, config: EvalConfig, video_dir: str | None = None, batch: int = 1):
        self.config, self.video_dir, self.batch = config, video_dir, int(batch)
        self.suite = make_suite(config.suite, **config.suite_config)
        self.env = self.suite.make_env()
        self.agent = make_agent(config.agent, config.checkpoint, config.suite)
        self.episodes: dict[str, list[Episode]] = {}
        self._envs = [self.env]

    def episode(self, split: str, episode_id: int) -> Episode:
        if split not in self.episodes:
            self.episodes[split] = self.suite.episodes(split)
        return self.episodes[split][episode_id]

    def run(self, split: str, seed: int, episode_id: int) -> dict:
        episode = self.episode(split, episode_id)
        trajectory = [] if self.video_dir else None
        record = run_episode(self.agent, self.env, self.suite.name, split, episode, seed, self.config.step_time_limit, trajectory)
        if self.video_dir:
            self.suite.write_video(self.video_dir, record, episode, trajectory)
        return record

    def play(self, units: list[Unit]):
        """Records of ``units`` as they finish: in lockstep if ``batch`` > 1, else one by one."""
        if self.batch <= 1:
            yield from (self.run(*unit) for unit in units)
            return
        while len(self._envs) < self.batch:
            self._envs.append(self.suite.make_env())
        built = iter([self.agent])
        c = self.config
        make = lambda: next(built, None) or make_agent(c.agent, c.checkpoint, c.suite)
        yield from play_lockstep(units, self._envs, make, self.episode, self.suite.name, c.step_time_limit)

    def run_chunk(self, units: list[Unit]) -> list[dict]:
        return list(self.play(units))


_worker: Worker | None = None


def _init_worker(config: EvalConfig, video_dir: str | None, batch: int) -> None:
    global _worker
    one_math_thread()
    _worker = Worker(config, video_dir, batch)


def _run_chunk(units: list[Unit]) -> list[dict]:
    return _worker.run_chunk(units)


def _chunks(units: list[Unit], workers: int, batch: int = 1) -> list[list[Unit]]:
    size = max(1, min(50, len(units) // (workers * 4)))
    if batch > 1:  # a lockstep chunk keeps its slots busy for most of its length
        size = max(size, 4 * batch)
    return [units[i : i + size] for i in range(0, len(units), size)]


def _run_local(config: EvalConfig, units: list[Unit], workers: int, video_dir, done: Callable[[list[dict]], None],
               batch: int = 1) -> None:
    if workers <= 1:
        for record in Worker(config, video_dir, batch).play(units):
            done([record])
        return
    context = multiprocessing.get_context("spawn")  # no fork: torch and EGL dislike it
    with cf.ProcessPoolExecutor(workers, mp_context=context, initializer=_init_worker,
                                initargs=(config, video_dir, batch)) as pool:
        for part in pool.map(_run_chunk, _chunks(units, workers, batch)):
            done(part)


def _run_ray(
    config: EvalConfig, units: list[Unit], workers: int, address: str | None, video_dir, done: Callable[[list[dict]], None],
    batch: int = 1,
) -> None:
    from objsearch.cluster import ray_session

    with ray_session(address, num_cpus=workers) as ray:
        from ray.util import ActorPool

        if address:
            workers = max(workers, int(ray.cluster_resources().get("CPU", 1)))
        actors = [ray.remote(num_cpus=1)(Worker).remote(config, video_dir, batch) for _ in range(workers)]
        chunks = _chunks(units, workers, batch)
        for part in ActorPool(actors).map_unordered(lambda actor, chunk: actor.run_chunk.remote(chunk), chunks):
            done(part)


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
    batch: int = 1,
) -> list[dict]:
    """Run (split, seed, episode_id) units and return their records in the units' order.

    Units already in ``partial`` are not run again; new records are appended to it. With
    ``batch`` > 1 each worker plays that many episodes in lockstep."""
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
            _run_ray(config, todo, workers, address, video_dir, done, batch)
        elif todo:
            _run_local(config, todo, workers, video_dir, done, batch)
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
    batch: int = 1,
) -> dict:
    """Evaluate ``config.agent`` on ``config.suite`` and return the results dict.

    With ``out``, the results JSON is written there; until it is, finished episodes are
    kept in ``<out>.partial.jsonl`` and a rerun of the same configuration resumes from it.
    With ``video_dir``, every episode's pictures are written there (suites that have them).
    With ``batch`` > 1, each worker plays that many episodes in lockstep (same records).
    """
    from objsearch.eval.results import build_results
    from objsearch.fileio import write_json

    suite = make_suite(config.suite, **config.suite_config)
    splits = check_splits(suite, list(config.splits))
    if video_dir and not hasattr(suite, "write_video"):
        raise UserError(f"--video is not available for suite {config.suite!r} (house suites have it)")
    if video_dir and batch > 1:
        raise UserError("--video records episodes one at a time; drop --batch (or use --batch 1)")
    make_agent(config.agent, config.checkpoint, config.suite)  # fail fast on a bad agent, before any worker starts
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
        records = run_units(config, units, workers, executor, address, partial, progress, video_dir, batch)
    finally:
        if partial:
            partial.close()
    results = build_results(config, suite, records)
    if out:
        write_json(out, results)
        partial.path.unlink(missing_ok=True)
    return results
