"""Where one play of an evaluation's plan (``objsearch.eval.plan.EvalPlan``) runs: in this
process, a pool of local worker processes, or the actors of a Ray cluster. Each process builds
one ``Worker`` from the plan and plays chunks of units; finished records are handed to
``done`` as they come (in any order). A worker process gets the plan without this process's
objects (``EvalPlan.portable``). Local worker processes die with the process that started
them (``objsearch.cluster.local_pool``)."""

from __future__ import annotations

import concurrent.futures as cf
from typing import Callable

from objsearch.cluster import local_pool
from objsearch.eval.config import Unit
from objsearch.eval.plan import EvalPlan
from objsearch.eval.worker import Worker

Done = Callable[[list[dict]], None]

_worker: Worker | None = None  # the Worker of a local pool's process


def _init_worker(plan: EvalPlan, play: int, batch: int) -> None:
    global _worker
    _worker = Worker(plan, play, batch)


def _run_chunk(units: list[Unit]) -> list[dict]:
    return _worker.run_chunk(units)


def chunks(units: list[Unit], workers: int, batch: int = 1) -> list[list[Unit]]:
    """``units`` cut into the pieces handed to workers: small enough to share the work out,
    big enough for lockstep slots to stay busy."""
    size = max(1, min(50, len(units) // (workers * 4)))
    if batch > 1:  # a lockstep chunk keeps its slots busy for most of its length
        size = max(size, 4 * batch)
    return [units[i : i + size] for i in range(0, len(units), size)]


def run_local(plan: EvalPlan, play: int, units: list[Unit], workers: int, done: Done, batch: int = 1) -> None:
    """Play ``units`` of ``plan.plays[play]`` in this process (``workers`` <= 1) or a pool of
    ``workers`` processes (not with an agent object: ``plan.agent`` plays in this process only)."""
    if workers <= 1:
        for record in Worker(plan, play, batch).play(units):
            done([record])
        return
    with local_pool(workers, _init_worker, (plan.portable(), play, batch)) as pool:
        # as they finish, so that an interrupt keeps every finished chunk (not pool.map: it
        # cancels the rest when interrupted, which local_pool must not see)
        futures = [pool.submit(_run_chunk, chunk) for chunk in chunks(units, workers, batch)]
        for future in cf.as_completed(futures):
            done(future.result())


def run_ray(
    plan: EvalPlan, play: int, units: list[Unit], workers: int, address: str | None, done: Done, batch: int = 1
) -> None:
    """Play ``units`` of ``plan.plays[play]`` on ``workers`` Ray actors (at least one per CPU of
    a cluster at ``address``; None: a local cluster started for the run)."""
    from objsearch.cluster import ray_session

    with ray_session(address, num_cpus=workers) as ray:
        from ray.util import ActorPool

        if address:
            workers = max(workers, int(ray.cluster_resources().get("CPU", 1)))
        portable = plan.portable()
        actors = [ray.remote(num_cpus=1)(Worker).remote(portable, play, batch) for _ in range(workers)]
        for part in ActorPool(actors).map_unordered(
            lambda actor, chunk: actor.run_chunk.remote(chunk), chunks(units, workers, batch)
        ):
            done(part)
