"""``objsearch cache build --suite NAME``: pre-render the observations of a suite's houses
(and, with ``--observation predicted``, pre-compute the perception network's predictions),
one house after another or, with ``--executor ray``, one Ray task per house."""

from __future__ import annotations

import argparse
from pathlib import Path

from objsearch.cluster import add_executor_arguments, check_executor_arguments


def add_parser(subparsers) -> None:
    from objsearch.sim.suites import SUITE_NAMES

    parser = subparsers.add_parser("cache", help="pre-rendered observation caches of house suites", description=__doc__)
    commands = parser.add_subparsers(dest="cache_command", metavar="ACTION", required=True)
    build = commands.add_parser("build", help="render every pose of every house of a suite into the cache")
    build.add_argument("--suite", required=True,
                       help=f"{', '.join(SUITE_NAMES)}, or a suite file (.json) made by objsearch suite make")
    build.add_argument("--cache-dir", help="cache folder (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)")
    build.add_argument("--training", action="store_true", help="also the suite's training houses (house-gen)")
    build.add_argument("--observation", choices=("gt", "predicted"), default="gt",
                       help="predicted: also fill the perception network's predictions (default: gt only)")
    build.add_argument("--perception", metavar="CHECKPOINT", help="the network for --observation predicted (default: the shipped one)")
    add_executor_arguments(build, "--cache-dir")
    build.set_defaults(func=run_build)


def run_build(args: argparse.Namespace) -> int:
    from objsearch.errors import UserError
    from objsearch.sim.suites import load_suite_file

    suite = load_suite_file(args.suite)  # an unknown name is an error naming the house suites
    if args.perception and args.observation != "predicted":
        raise UserError("--perception applies to --observation predicted")
    check_executor_arguments(args)
    checkpoint = None
    if args.observation == "predicted":
        from objsearch.perception.inference import load_checkpoint, resolve_checkpoint

        checkpoint = resolve_checkpoint(args.perception)
        load_checkpoint(checkpoint)  # a bad checkpoint fails here, before any house is rendered
    houses = dict(suite["houses"])
    if args.training:
        houses.update(suite["training_houses"])
    lines = build_caches(houses, args.cache_dir, perception=checkpoint, executor=args.executor, address=args.address,
                         workers=args.workers, desc=f"houses of {args.suite}")
    for line in lines:
        print(line)
    return 0


def build_caches(houses: dict[str, dict], cache_dir=None, settings=None, perception=None, *, executor: str = "local",
                 address: str | None = None, workers: int | None = None, desc: str = "houses",
                 progress: bool = True) -> list[str]:
    """Build the observation cache (``settings``, default: the agent camera) of every house
    (house id -> ``HouseRef`` fields) and, with ``perception`` (a checkpoint path), the
    network's predictions; one task per house (``objsearch.cluster.map_houses``). Returns
    one report line a cache, in the houses' order."""
    from functools import partial

    from objsearch.cluster import map_houses
    from objsearch.sim.cache import default_cache_dir
    from objsearch.sim.goals import GOAL_CAMERA

    root = Path(cache_dir or default_cache_dir()).resolve()  # what every worker, wherever it runs, writes to
    perception = None if perception is None else str(Path(perception).resolve())
    task = partial(build_house_cache, cache_dir=root, settings=settings or GOAL_CAMERA, perception=perception)
    parts = map_houses(task, houses.items(), executor, address, workers, desc=desc, progress=progress)
    return [line for part in parts for line in part]


def build_house_cache(item: tuple[str, dict], cache_dir: Path, settings, perception: str | None) -> list[str]:
    """The task of ``build_caches``: one house's caches (``item``: house id, ``HouseRef`` fields)."""
    from objsearch.sim.cache import HouseCache, PredictedCache
    from objsearch.sim.suites import load_house
    from objsearch.sim.world import HouseRef

    house_id, info = item
    world = load_house(HouseRef(**info), house_id)
    cache = HouseCache.open(world, settings, cache_dir, progress=False)
    lines = [f"{house_id}: {cache.num_poses} poses in {cache.directory}"]
    if perception is not None:
        from objsearch.perception.inference import Predictor

        predictor = Predictor.from_checkpoint(perception)
        predicted = PredictedCache.open(world, settings, predictor, cache_dir, progress=False)
        lines.append(f"{house_id}: predictions of network {predictor.key} in {predicted.directory}")
    return lines
