"""``objsearch cache build --suite NAME``: pre-render the observations of a suite's houses
(and, with ``--observation predicted``, pre-compute the perception network's predictions)."""

from __future__ import annotations

import argparse


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("cache", help="pre-rendered observation caches of house suites", description=__doc__)
    commands = parser.add_subparsers(dest="cache_command", metavar="ACTION", required=True)
    build = commands.add_parser("build", help="render every pose of every house of a suite into the cache")
    build.add_argument("--suite", required=True, help="house-single, house-multi or house-gen")
    build.add_argument("--cache-dir", help="cache folder (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)")
    build.add_argument("--training", action="store_true", help="also the suite's training houses (house-gen)")
    build.add_argument("--observation", choices=("gt", "predicted"), default="gt",
                       help="predicted: also fill the perception network's predictions (default: gt only)")
    build.add_argument("--perception", metavar="CHECKPOINT", help="the network for --observation predicted (default: the shipped one)")
    build.set_defaults(func=run_build)


def run_build(args: argparse.Namespace) -> int:
    from tqdm import tqdm

    from objsearch.errors import UserError
    from objsearch.sim.cache import HouseCache, PredictedCache
    from objsearch.sim.goals import GOAL_CAMERA
    from objsearch.sim.suites import SUITE_NAMES, load_suite_file
    from objsearch.sim.world import HouseRef, World

    if args.suite not in SUITE_NAMES:
        raise UserError(f"unknown house suite {args.suite!r}; known: {', '.join(SUITE_NAMES)}")
    if args.perception and args.observation != "predicted":
        raise UserError("--perception applies to --observation predicted")
    predictor = None
    if args.observation == "predicted":
        from objsearch.perception.inference import Predictor

        predictor = Predictor.from_checkpoint(args.perception)
    suite = load_suite_file(args.suite)
    houses = dict(suite["houses"])
    if args.training:
        houses.update(suite["training_houses"])
    for house_id, info in tqdm(houses.items(), desc=f"houses of {args.suite}", unit="house"):
        world = World.load(HouseRef(**info))
        cache = HouseCache.open(world, GOAL_CAMERA, args.cache_dir)
        print(f"{house_id}: {cache.num_poses} poses in {cache.directory}")
        if predictor is not None:
            predicted = PredictedCache.open(world, GOAL_CAMERA, predictor, args.cache_dir)
            print(f"{house_id}: predictions of network {predictor.key} in {predicted.directory}")
    return 0
