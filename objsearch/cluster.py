"""Running one task per house: in this process, in local worker processes, or on a Ray
cluster (``--executor ray [--address ADDR]`` of ``objsearch cache build`` and ``objsearch
perception dataset``; ``objsearch-eval`` starts Ray the same way).

A task writes its house's files itself and returns a small result; the caller gets the
results back in the order of its houses. On a cluster the output folder must be one that
every node sees at the same path (a shared filesystem). A task's files and result depend
only on its input, so they are the same for any executor and number of workers.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import contextlib
import ctypes
import multiprocessing
import os
import signal
import sys
import threading
import time
from typing import Callable, Iterable

from objsearch.cliargs import positive_int
from objsearch.errors import UserError

EXECUTORS = ("local", "ray")


def add_executor_arguments(parser: argparse.ArgumentParser, output: str) -> None:
    """``--executor``, ``--address`` and ``--workers`` of a command that builds ``output``
    house by house."""
    parser.add_argument(
        "--executor",
        choices=EXECUTORS,
        default="local",
        help=f"local: this machine (default); ray: one Ray task per house over a cluster, "
        f"all writing to {output} (on a cluster: a filesystem every node shares)",
    )
    parser.add_argument(
        "--address",
        metavar="ADDR",
        help="with --executor ray: the cluster's address (default: start a local Ray cluster)",
    )
    parser.add_argument(
        "--workers",
        type=positive_int,
        metavar="N",
        help="houses at once: local worker processes, or the CPUs of the local Ray cluster "
        "(default: 1 locally, every core with --executor ray)",
    )


def check_address(address: str | None, executor: str) -> None:
    """A Ray ``--address`` needs ``--executor ray``: refuse it with any other executor."""
    if address and executor != "ray":
        raise UserError(f"--address {address} needs --executor ray; add it, or drop --address to run here")


def check_executor_arguments(args: argparse.Namespace) -> None:
    """Refuse combinations of ``add_executor_arguments``' flags that would be ignored."""
    check_address(args.address, args.executor)
    if args.workers is not None and args.address is not None:
        raise UserError(
            "--workers sizes a run on this machine; with --address the cluster's CPUs decide: drop --workers"
        )


def one_math_thread() -> None:
    """In a worker process that shares the cores with others: one math thread (OpenMP, MKL,
    torch). Two processes of 2 torch threads each on 2 cores made small networks' forward
    passes 4x slower (``benchmarks/RESULTS.md``, "Evaluation")."""
    os.environ["OMP_NUM_THREADS"] = os.environ["MKL_NUM_THREADS"] = "1"
    if "torch" in sys.modules:
        sys.modules["torch"].set_num_threads(1)


PR_SET_PDEATHSIG = 1  # linux/prctl.h


def die_with_parent(parent: int) -> None:
    """Make this worker process exit when the process ``parent`` that started it dies, even
    by SIGKILL: the kernel's parent-death signal on Linux, and everywhere a thread that
    watches the parent's pid."""
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
        except (OSError, AttributeError):
            pass

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)

    if os.getppid() != parent:  # it died before the signal was set
        os._exit(1)
    threading.Thread(target=watch, name="die-with-parent", daemon=True).start()


def _start_worker(parent: int, initializer: Callable | None, initargs: tuple) -> None:
    # Ctrl-C and SIGTERM reach the whole process group; the parent alone decides what to
    # save and stops its workers (local_pool), instead of each dying with a traceback.
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, signal.SIG_IGN)
    die_with_parent(parent)
    one_math_thread()
    if initializer is not None:
        initializer(*initargs)


@contextlib.contextmanager
def local_pool(workers: int, initializer: Callable | None = None, initargs: tuple = ()):
    """Spawned worker processes (no fork: torch and EGL dislike it) that run one math
    thread, ignore SIGINT and SIGTERM and die with this process; on an error (Ctrl-C,
    SIGTERM, a crash) they are killed at once, not after their tasks. Futures are not
    cancelled: the pool marks the unfinished ones broken (cancelling them as well made
    Python 3.11's pool thread fail with InvalidStateError)."""
    pool = cf.ProcessPoolExecutor(
        workers,
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_start_worker,
        initargs=(os.getpid(), initializer, initargs),
    )
    try:
        yield pool
    except BaseException:
        for process in list((getattr(pool, "_processes", None) or {}).values()):  # private, but no public way
            process.kill()
        pool.shutdown(wait=False)
        raise
    pool.shutdown()


@contextlib.contextmanager
def ray_session(address: str | None = None, num_cpus: int | None = None):
    """Yield the ``ray`` module, connected to the cluster at ``address`` or to a new local
    one of ``num_cpus`` CPUs (None: every core), and shut down on exit. A Ray already
    initialised (by a test, say) is used as it is and left running."""
    try:
        import ray
    except ImportError:
        raise UserError("--executor ray needs Ray: pip install 'objsearch[ray]'") from None
    started_here = not ray.is_initialized()
    if started_here:
        init = {"address": address} if address else {"num_cpus": num_cpus}
        ray.init(**init, include_dashboard=False, logging_level="ERROR", log_to_driver=False)
    try:
        yield ray
    finally:
        if started_here:
            ray.shutdown()


def map_houses(
    fn: Callable,
    items: Iterable,
    executor: str = "local",
    address: str | None = None,
    workers: int | None = None,
    desc: str = "houses",
    progress: bool = True,
) -> list:
    """``[fn(item) for item in items]``, one house an item, with a progress bar over finished houses.

    Args:
        fn: the task. Outside a plain local run it must pickle: a module-level function
            or a ``functools.partial`` of one.
        items: one per house.
        executor: ``local``: in this process (``workers`` None or 1) or in ``workers``
            spawned processes; ``ray``: one Ray task (1 CPU) per item, on the cluster at
            ``address`` or on a local one of ``workers`` CPUs (None: every core).
        address: Ray cluster address (``ray`` only).
        workers: see ``executor``.
        desc: the progress bar's label.
        progress: show the progress bar.

    Returns:
        The results in the order of ``items``. The first task that raises stops the run
        (a ``UserError`` from a Ray task is raised as it is).
    """
    if executor not in EXECUTORS:
        raise ValueError(f"unknown executor {executor!r}; known: {', '.join(EXECUTORS)}")
    if address is not None and executor != "ray":
        raise ValueError(f"a Ray address ({address!r}) needs executor='ray', not {executor!r}")
    from tqdm import tqdm

    items = list(items)
    results = [None] * len(items)
    with tqdm(total=len(items), desc=desc, unit="house", disable=not progress or None) as bar:
        if executor == "ray":
            with ray_session(address, workers) as ray:
                task = ray.remote(num_cpus=1)(_call)
                fn_ref = ray.put(fn)
                pending = {task.remote(fn_ref, item): i for i, item in enumerate(items)}
                while pending:
                    (ref,), _ = ray.wait(list(pending), num_returns=1)
                    try:
                        results[pending.pop(ref)] = ray.get(ref)
                    except ray.exceptions.RayTaskError as err:
                        if isinstance(err.cause, UserError):
                            raise err.cause from None
                        raise
                    bar.update()
        elif workers is None or workers <= 1:
            for i, item in enumerate(items):
                results[i] = fn(item)
                bar.update()
        else:
            with local_pool(workers) as pool:
                futures = {pool.submit(fn, item): i for i, item in enumerate(items)}
                for future in cf.as_completed(futures):
                    results[futures[future]] = future.result()
                    bar.update()
    return results


def _call(fn: Callable, item):
    """The Ray task: ``fn`` travels once through the object store, the items one by one."""
    return fn(item)
