"""Running an agent over a suite's fixed episodes: in one process, a pool of worker
processes, or a Ray cluster.

Every (split, seed, episode) is an independent unit with its own random Generator derived
from those three values, and the agent is reset before each, so the records do not depend
on the order units run in, the number of workers or the executor. An agent that raises,
returns an invalid action or exceeds the per-step time limit fails that episode (the record
keeps the error) and the run goes on. With a partial-results file, finished units are
appended as they complete, and a rerun with the same configuration skips them. Local
worker processes die with the process that started them (``objsearch.cluster.local_pool``).
"""

from __future__ import annotations

import json
import os
import sys
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Callable, Iterable

from tqdm import tqdm

from objsearch.cluster import EXECUTORS, local_pool
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
        weights_sha256: the digest of the files the agent loaded (its ``weights_sha256``,
            ``objsearch.digests.of_files``), set by ``evaluate``; None for an agent without.
    """

    agent: str
    suite: str = "gridworld"
    splits: tuple[str, ...] = ()
    seeds: tuple[int, ...] = PAPER_SEEDS
    checkpoint: str | None = None
    suite_config: dict = field(default_factory=dict)
    step_time_limit: float | None = 10.0
    weights_sha256: str | None = None

    def to_json(self) -> dict:
        out = asdict(self)
        out["splits"], out["seeds"] = list(self.splits), list(self.seeds)
        return out


class Worker:
    """An agent, a suite and its env: built once per process (or Ray actor), then fed units.

    ``folder``: the folder the evaluation started in, where a ``module:Class`` or relative
    ``file.py:Class`` agent is also looked for (default: the current folder). With
    ``video_dir``, the pictures of each unit in ``video_units`` (None: every unit) are
    written there by the suite's ``write_video(directory, record, episode, trajectory)``;
    those units are played one by one, first. With ``batch`` > 1, the others are played ``batch`` at a time in
    lockstep (``objsearch.eval.lockstep``), one env per slot."""

    def __init__(self, config: EvalConfig, video_dir: str | None = None, batch: int = 1, folder: str | None = None,
                 video_units: Iterable[Unit] | None = None):
        self.config, self.video_dir, self.batch, self.folder = config, video_dir, int(batch), folder
        self.video_units = None if video_units is None else frozenset(map(tuple, video_units))
        self.suite = make_suite(config.suite, **config.suite_config)
        self.env = self.suite.make_env()
        self.agent = make_agent(config.agent, config.checkpoint, config.suite, folder)
        self.episodes: dict[str, list[Episode]] = {}
        self._envs = [self.env]

    def episode(self, split: str, episode_id: int) -> Episode:
        if split not in self.episodes:
            self.episodes[split] = self.suite.episodes(split)
        return self.episodes[split][episode_id]

    def run(self, split: str, seed: int, episode_id: int) -> dict:
        episode = self.episode(split, episode_id)
        video = self.wants_video((split, seed, episode_id))
        trajectory = [] if video else None
        record = run_episode(self.agent, self.env, self.suite.name, split, episode, seed, self.config.step_time_limit, trajectory)
        if video:
            self.suite.write_video(self.video_dir, record, episode, trajectory)
        return record

    def wants_video(self, unit: Unit) -> bool:
        return bool(self.video_dir) and (self.video_units is None or unit in self.video_units)

    def play(self, units: list[Unit]):
        """Records of ``units`` as they finish: the video units one by one, then the others
        in lockstep if ``batch`` > 1, else one by one."""
        yield from (self.run(*unit) for unit in units if self.wants_video(unit))
        units = [unit for unit in units if not self.wants_video(unit)]
        if self.batch <= 1:
            yield from (self.run(*unit) for unit in units)
            return
        if not units:
            return
        while len(self._envs) < self.batch:
            self._envs.append(self.suite.make_env())
        built = iter([self.agent])
        c = self.config
        make = lambda: next(built, None) or make_agent(c.agent, c.checkpoint, c.suite, self.folder)
        yield from play_lockstep(units, self._envs, make, self.episode, self.suite.name, c.step_time_limit)

    def run_chunk(self, units: list[Unit]) -> list[dict]:
        return list(self.play(units))


_worker: Worker | None = None


def _init_worker(config: EvalConfig, video_dir: str | None, batch: int, folder: str, video_units: frozenset | None) -> None:
    global _worker
    _worker = Worker(config, video_dir, batch, folder, video_units)


def _run_chunk(units: list[Unit]) -> list[dict]:
    return _worker.run_chunk(units)


def _chunks(units: list[Unit], workers: int, batch: int = 1) -> list[list[Unit]]:
    size = max(1, min(50, len(units) // (workers * 4)))
    if batch > 1:  # a lockstep chunk keeps its slots busy for most of its length
        size = max(size, 4 * batch)
    return [units[i : i + size] for i in range(0, len(units), size)]


def _run_local(config: EvalConfig, units: list[Unit], workers: int, video_dir, done: Callable[[list[dict]], None],
               batch: int = 1, folder: str | None = None, video_units: frozenset | None = None) -> None:
    if workers <= 1:
        for record in Worker(config, video_dir, batch, folder, video_units).play(units):
            done([record])
        return
    with local_pool(workers, _init_worker, (config, video_dir, batch, folder, video_units)) as pool:
        for part in pool.map(_run_chunk, _chunks(units, workers, batch)):
            done(part)


def _run_ray(
    config: EvalConfig, units: list[Unit], workers: int, address: str | None, video_dir, done: Callable[[list[dict]], None],
    batch: int = 1, folder: str | None = None, video_units: frozenset | None = None,
) -> None:
    from objsearch.cluster import ray_session

    with ray_session(address, num_cpus=workers) as ray:
        from ray.util import ActorPool

        if address:
            workers = max(workers, int(ray.cluster_resources().get("CPU", 1)))
        actors = [ray.remote(num_cpus=1)(Worker).remote(config, video_dir, batch, folder, video_units) for _ in range(workers)]
        chunks = _chunks(units, workers, batch)
        for part in ActorPool(actors).map_unordered(lambda actor, chunk: actor.run_chunk.remote(chunk), chunks):
            done(part)


class PartialResults:
    """Finished records of an evaluation, appended to ``<out>.partial.jsonl`` as they come.

    The first line is the configuration; a rerun with the same configuration resumes, one
    with another is refused, naming the settings that differ. A last line cut short by an
    interruption is dropped; any other line that is not an episode record is dropped with a
    warning (its episode runs again), so that the run stays resumable.
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
            stored = first.get("partial_results_of") if isinstance(first, dict) else None
            if not isinstance(stored, dict):
                raise UserError(f"{self.path} is not a partial-results file (its first line is not an evaluation's "
                                "settings); delete it or choose another --out")
            if stored != header["partial_results_of"]:
                raise UserError(
                    f"{self.path} holds partial results of another evaluation ({_differences(stored, header['partial_results_of'])}); "
                    "rerun with those settings to resume it, or delete it or choose another --out to start afresh"
                )
            for number, line in enumerate(lines[1:], start=2):
                try:
                    record = json.loads(line)
                except json.JSONDecodeError:
                    record = None
                    if number == len(lines):
                        break  # the write an interruption cut short
                if not (isinstance(record, dict) and RECORD_KEYS <= record.keys()):
                    print(f"warning: {self.path} line {number} is not an episode record ({line[:60]!r}); "
                          "dropped, its episode runs again", file=sys.stderr)
                    continue
                self.records.append(record)
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


RECORD_KEYS = frozenset(("split", "seed", "episode_id", "success", "steps", "min_steps"))


def _differences(stored: dict, now: dict, prefix: str = "") -> str:
    """The settings that differ between two configurations, e.g. ``agent: 'random' there,
    'oracle' now``."""
    parts = []
    for key in sorted(set(stored) | set(now), key=str):
        there, here = stored.get(key), now.get(key)
        if there == here:
            continue
        if isinstance(there, dict) and isinstance(here, dict):
            parts.append(_differences(there, here, f"{prefix}{key}."))
        else:
            parts.append(f"{prefix}{key}: {there!r} there, {here!r} now")
    return "; ".join(parts)


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
    folder: str | None = None,
    video_units: Iterable[Unit] | None = None,
) -> list[dict]:
    """Run (split, seed, episode_id) units and return their records in the units' order.

    Units already in ``partial`` are not run again; new records are appended to it. With
    ``batch`` > 1 each worker plays that many episodes in lockstep. ``folder``: where the
    agent's module or file is also looked for (default: the current folder). With
    ``video_dir``, the units of ``video_units`` (None: every unit) get pictures there."""
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

    folder = os.path.abspath(folder or os.getcwd())
    video_units = None if video_units is None else frozenset(video_units)
    try:
        if todo and executor == "ray":
            _run_ray(config, todo, workers, address, video_dir, done, batch, folder, video_units)
        elif todo:
            _run_local(config, todo, workers, video_dir, done, batch, folder, video_units)
    finally:
        bar.close()
    return [finished[u] for u in units]


def plan_units(suite, splits: list[str], seeds: tuple[int, ...]) -> list[Unit]:
    """Every (split, seed, episode_id), in report order."""
    return [(split, seed, ep.episode_id) for split in splits for seed in seeds for ep in suite.episodes(split)]


def video_units_of(suite, splits: list[str], seeds: tuple[int, ...], episodes: int) -> list[Unit]:
    """The units that get a video: the first ``episodes`` episodes (by id) of each split,
    with the first seed."""
    return [(split, seeds[0], ep.episode_id) for split in splits
            for ep in sorted(suite.episodes(split), key=lambda ep: ep.episode_id)[:episodes]]


def evaluate(
    config: EvalConfig,
    workers: int = 1,
    progress: bool = True,
    executor: str = "local",
    address: str | None = None,
    out: str | Path | None = None,
    video_dir: str | None = None,
    batch: int = 1,
    video_episodes: int = 2,
) -> dict:
    """Evaluate ``config.agent`` on ``config.suite`` and return the results dict.

    With ``out``, the results JSON is written there; until it is, finished episodes are
    kept in ``<out>.partial.jsonl`` and a rerun of the same configuration resumes from it.
    With ``video_dir``, the pictures of the first ``video_episodes`` episodes of each split
    (first seed) are written there (suites that have them); those are played one at a
    time, the rest as usual. With ``batch`` > 1, each worker plays that many episodes in
    lockstep (same records). Outputs that cannot be written are refused before the first
    episode.
    """
    from objsearch.eval.results import build_results
    from objsearch.fileio import check_writable, write_json

    if out:
        check_writable(out, "--out")
        check_writable(f"{out}.partial.jsonl", "--out")
    if video_dir:
        check_writable(video_dir, "--video", folder=True)
    suite = make_suite(config.suite, **config.suite_config)
    splits = check_splits(suite, list(config.splits))
    if video_dir and not hasattr(suite, "write_video"):
        raise UserError(f"--video is not available for suite {config.suite!r} (house suites have it)")
    folder = os.getcwd()
    agent = make_agent(config.agent, config.checkpoint, config.suite, folder)  # fail fast, before any worker starts
    config = EvalConfig(
        agent=config.agent,
        suite=config.suite,
        splits=tuple(splits),
        seeds=config.seeds,
        checkpoint=config.checkpoint,
        suite_config=suite.config(),
        step_time_limit=config.step_time_limit,
        weights_sha256=getattr(agent, "weights_sha256", None),
    )
    del agent
    partial = PartialResults(f"{out}.partial.jsonl", config) if out else None
    try:
        units = plan_units(suite, splits, config.seeds)
        video_units = video_units_of(suite, splits, config.seeds, video_episodes) if video_dir else None
        records = run_units(config, units, workers, executor, address, partial, progress, video_dir, batch, folder,
                            video_units)
    finally:
        if partial:
            partial.close()
    results = build_results(config, suite, records)
    if out:
        write_json(out, results)
        partial.path.unlink(missing_ok=True)
    return results
