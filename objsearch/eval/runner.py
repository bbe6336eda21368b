"""Running an agent over a suite's fixed episodes: in one process, a pool of worker
processes, or a Ray cluster.

Every (split, seed, episode) is an independent unit with its own random Generator derived
from those three values, and the agent is reset before each, so the records do not depend
on the order units run in, the number of workers or the executor. An agent that raises,
returns an invalid action or exceeds the per-step time limit fails that episode (the record
keeps the error) and the run goes on. With a partial-results file, finished units are
appended as they complete, and a rerun with the same configuration skips them.

The parts: ``config`` (``EvalConfig``), ``plan`` (the config resolved once: the suite, each
play's agent and training run, the units), ``episode`` (one episode, its Generator and time
limit), ``lockstep`` (N episodes at once), ``worker`` (one process's agent, suite and envs),
``executors`` (local processes or Ray), ``partial`` (the partial-results file); this module
resolves an evaluation's plan, then plays it.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Iterable

from objsearch.cluster import EXECUTORS
from objsearch.errors import UserError
from objsearch.eval.config import EvalConfig, Unit
from objsearch.eval.executors import run_local, run_ray
from objsearch.eval.partial import PartialResults, keep_what_did_not_fail
from objsearch.eval.plan import EvalPlan, resolve, resolve_play
from objsearch.progress import progress_bar


def check_executor(executor: str) -> None:
    """Refuse an executor other than ``objsearch.cluster.EXECUTORS``."""
    if executor not in EXECUTORS:
        raise UserError(f"unknown executor {executor!r}; choose one of {', '.join(EXECUTORS)}")


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
    agent=None,
    bar=None,
) -> list[dict]:
    """Play ``config`` as it is (its checkpoint, or the training run it names) over the
    (split, seed, episode_id) ``units`` and return their records in the units' order: a
    replay of recorded episodes (``objsearch leaderboard verify``). ``folder``: where the
    agent's module or file is also looked for (default: the current folder). With
    ``video_dir``, the units of ``video_units`` (None: every unit) get pictures there.
    ``agent``: an agent object to play in this process instead of building ``config.agent``.
    The rest as ``play_units``."""
    check_executor(executor)
    plan = resolve_play(config, units, folder, agent, video_dir, video_units)
    return play_units(plan, 0, workers, executor, address, partial, progress, batch, bar)


def play_units(
    plan: EvalPlan,
    play: int = 0,
    workers: int = 1,
    executor: str = "local",
    address: str | None = None,
    partial: PartialResults | None = None,
    progress: bool = True,
    batch: int = 1,
    bar=None,
) -> list[dict]:
    """Play ``plan.plays[play]`` over the plan's units and return their records in the units' order.

    Units already in ``partial`` are not run again; new records are appended to it. With
    ``batch`` > 1 each worker plays that many episodes in lockstep. ``bar``: a progress bar
    that already counts these units (``evaluate``'s over every training run) to advance, left
    open; None: one of their own."""
    check_executor(executor)
    units, config = list(plan.units), plan.plays[play].config
    finished = {(r["split"], r["seed"], r["episode_id"]): r for r in (partial.records if partial else [])}
    todo = [u for u in units if u not in finished]
    if partial and len(todo) < len(units):
        print(f"resuming: {len(units) - len(todo)} of {len(units)} episodes done in {partial.path}", file=sys.stderr)
    own_bar = bar is None
    if own_bar:
        bar = progress_bar(len(units), f"{config.agent} on {config.suite}", "ep", progress, len(units) - len(todo))

    def done(records: list[dict]) -> None:
        for r in records:
            finished[(r["split"], r["seed"], r["episode_id"])] = r
        if partial:
            partial.add(records)
        bar.update(len(records))

    # never more workers than episodes, nor more envs a worker than its share: --batch 100000 on
    # a 2-episode suite builds 2 envs, not 100000 (records are the same for any batch and workers)
    workers = max(1, min(workers, len(todo)))
    batch = max(1, min(batch, -(-len(todo) // workers)))
    try:
        if todo and executor == "ray":
            run_ray(plan, play, todo, workers, address, done, batch)
        elif todo:
            run_local(plan, play, todo, workers, done, batch)
    except KeyboardInterrupt as err:  # Ctrl-C or SIGTERM: say what is kept (the CLI prints it)
        kept = sum(u in finished for u in units)
        if partial:
            what = f"{kept} of {len(units)} episodes saved in {partial.path}; rerun the same command to resume"
        else:
            what = f"{kept} of {len(units)} episodes played, none saved (pass --out to keep them)"
        raise type(err)(what) from None
    finally:
        if own_bar:
            bar.close()
    return [finished[u] for u in units]


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
    agent=None,
    retry_failed: bool = False,
) -> dict:
    """Evaluate ``config.agent`` on ``config.suite`` and return the results dict.

    The config is resolved once (``objsearch.eval.plan.resolve``: the suite, the agent, its
    training runs and their checkpoints, the units; a bad suite, split, agent, training run or
    checkpoint is refused there), then each play of the plan is played (``play_units``).

    With ``out``, the results JSON is written there; until it is, finished episodes are
    kept in ``<out>.partial.jsonl`` (one ``<out>.run<SEED>.partial.jsonl`` per training run)
    and a rerun of the same configuration resumes from it. An agent that lists several
    training runs for the suite plays each (``objsearch.eval.runs``), unless
    ``config.checkpoint`` or ``config.training_run`` names one. With ``video_dir``, the
    pictures of the first ``video_episodes`` episodes of each split (first seed) are written
    there (suites that have them); those are played one at a time, the rest as usual. With
    ``batch`` > 1, each worker plays that many episodes in lockstep (same records). Outputs
    that cannot be written are refused before the first episode. ``agent``: an agent object
    to play (in this process, ``workers`` 1) instead of building ``config.agent``, which then
    only names it in the results; it is played as it is (no checkpoint or training runs).
    The checkpoint each play loads is printed when the agent or its training run chose it, and
    recorded (``loaded_checkpoint``: in the results, or in each of several ``training_runs``).
    ``retry_failed``: ``out`` is the results file of a finished run of the same configuration;
    its episodes that ended in an agent error are played again, the others kept.
    """
    from objsearch.eval.results import build_results
    from objsearch.fileio import check_writable, write_json

    if retry_failed and not out:
        raise UserError("--retry-failed needs --out: the results file whose failed episodes to play again")
    if out:
        check_writable(out, "--out")
        check_writable(f"{out}.partial.jsonl", "--out")
    if video_dir:
        check_writable(video_dir, "--video", folder=True)
    if agent is not None and (workers > 1 or executor != "local"):
        raise UserError(
            f"agent object {config.agent!r} plays in this process only: pass workers=1 and the local executor, "
            "or pass the agent's registered name or 'package.module:Class' to play it in several processes"
        )
    plan = resolve(config, os.getcwd(), agent, out, video_dir, video_episodes)  # once: the executors only play it
    check_executor(executor)
    config = plan.config
    for i, play in enumerate(plan.plays):
        if play.loaded is not None and config.checkpoint is None:  # chosen for the user: say which
            run = f" (training run {play.run.seed}, {i + 1} of {len(plan.plays)})" if plan.several else ""
            print(f"{config.agent} on {config.suite}: checkpoint {play.loaded}{run}", file=sys.stderr)
    if retry_failed:
        configs, paths = [play.config for play in plan.plays], [play.partial for play in plan.plays]
        failed = keep_what_did_not_fail(out, plan.recorded, configs, paths)
        if failed >= 0:
            print(f"--retry-failed: playing the {failed} failed episode(s) of {out} again", file=sys.stderr)
    prepare = getattr(plan.suite, "prepare", None)
    if callable(prepare) and executor == "local":  # e.g. missing caches: a stage of its own, not in the ETA
        prepare(list(plan.units), workers=workers, progress=progress)
    records, partials, bar = [], [], None
    label = lambda i: f"{config.agent} on {config.suite}, run {i + 1}/{len(plan.plays)}"  # noqa: E731
    try:
        partials = [PartialResults(play.partial, play.config) if out else None for play in plan.plays]
        if plan.several:  # one bar over every run: its ETA is the whole evaluation's, its label says which run plays
            done = sum(len(set(plan.units) & p.done_units()) for p in partials if p)
            bar = progress_bar(len(plan.units) * len(plan.plays), label(0), "ep", progress, done)
        for i, (play, partial) in enumerate(zip(plan.plays, partials)):
            if bar is not None and i:
                bar.set_description_str(label(i))  # a line in a log: this run starts
            played = play_units(plan, i, workers, executor, address, partial, progress, batch, bar)
            records += [{**r, "training_run": play.config.training_run} for r in played] if plan.several else played
    finally:
        if bar is not None:
            bar.close()
        for partial in partials:
            if partial:
                partial.close()
    results = build_results(plan.recorded, plan.suite, records, plan.runs, plan.loaded)
    if out:
        write_json(out, results, elsewhere="choose another --out")
        for play in plan.plays:
            Path(play.partial).unlink(missing_ok=True)
    return results
