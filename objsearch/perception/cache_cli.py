"""``objsearch cache build --suite NAME``: pre-render the observations of a suite's houses
(and, with ``--observation predicted``, pre-compute the perception network's predictions),
one house after another or, with ``--executor ray``, one Ray task per house; a damaged
cache is rebuilt. ``objsearch cache list`` shows the caches of the cache folder (house,
kind, size, current or why not: file sizes and headers are checked, not digests) and
leftover temp folders; ``objsearch cache verify``
checks every file's sha256 (exit 2 if one is damaged); ``objsearch cache clear`` removes
the caches that are not current (old versions, damaged: digests checked) and temp folders of killed builds,
``--house ID`` every cache of a house, ``--all`` every cache. Only folders objsearch made count
(``cache_folder.cache_meta``, ``fileio.is_temp_folder``): anything else in the cache folder is
left and named, and a link to a cache is never deleted through.

It lives in ``perception`` (not in ``sim``, beside the caches) because a build may fill the
perception network's predictions too: ``perception`` is the lowest layer that sees both."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from objsearch.cluster import add_executor_arguments, check_executor_arguments


def add_parser(subparsers) -> None:
    """Add ``objsearch cache`` (build, list, verify, clear) to ``subparsers``."""
    from objsearch.sim.suites import SUITE_NAMES

    parser = subparsers.add_parser("cache", help="pre-rendered observation caches of house suites", description=__doc__)
    commands = parser.add_subparsers(dest="cache_command", metavar="ACTION", required=True)
    build = commands.add_parser("build", help="render every pose of every house of a suite into the cache")
    build.add_argument(
        "--suite", required=True, help=f"{', '.join(SUITE_NAMES)}, or a suite file (.json) made by objsearch suite make"
    )
    build.add_argument("--cache-dir", help="cache folder (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)")
    build.add_argument("--training", action="store_true", help="also the suite's training houses (house-gen)")
    build.add_argument(
        "--observation",
        choices=("gt", "predicted"),
        default="gt",
        help="predicted: also fill the perception network's predictions (default: gt only)",
    )
    build.add_argument(
        "--perception", metavar="CHECKPOINT", help="the network for --observation predicted (default: the shipped one)"
    )
    add_executor_arguments(build, "--cache-dir")
    build.set_defaults(func=run_build)
    cache_dir_help = "cache folder (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)"
    listing = commands.add_parser("list", help="the caches in the cache folder: house, kind, size, current or not")
    listing.add_argument("--cache-dir", help=cache_dir_help)
    listing.set_defaults(func=run_list)
    verify = commands.add_parser("verify", help="check the sha256 of every cache file (exit 2 if one is damaged)")
    verify.add_argument("--cache-dir", help=cache_dir_help)
    verify.add_argument("--suite", help="only the caches of this suite's houses (also its training houses)")
    verify.set_defaults(func=run_verify)
    clear = commands.add_parser("clear", help="remove caches: by default those not current and leftover temp folders")
    clear.add_argument("--cache-dir", help=cache_dir_help)
    which = clear.add_mutually_exclusive_group()
    which.add_argument("--house", nargs="+", metavar="ID", help="every cache of these houses")
    which.add_argument("--all", action="store_true", help="every cache")
    clear.set_defaults(func=run_clear)


def _root(args, must_exist: bool = False) -> Path:
    """The cache folder of ``args``; one that is a file, or a ``--cache-dir`` that does not
    exist (``must_exist``: any that does not), is a ``UserError``."""
    from objsearch.errors import UserError
    from objsearch.sim.cache import default_cache_dir

    root = Path(args.cache_dir) if args.cache_dir else default_cache_dir()
    where = "pass the folder the caches are in (--cache-dir or $OBJSEARCH_CACHE)"
    if root.exists() and not root.is_dir():
        raise UserError(f"cache folder {root} is a file, not a folder; {where}")
    if not root.exists() and (args.cache_dir or must_exist):
        raise UserError(f"cache folder {root} does not exist; {where}, or build them: objsearch cache build")
    return root


def run_list(args: argparse.Namespace) -> int:
    """``objsearch cache list``: print every cache and temp folder with its size and state; returns 0."""
    from objsearch.fileio import abandoned_temp_folders
    from objsearch.sim.cache import cache_folders
    from objsearch.sim.cache_folder import folder_bytes, format_size

    root = _root(args)
    folders = cache_folders(root)
    for c in folders:
        state = "current" if c["problem"] is None else f"not current: {c['problem']}"
        link = f" -> {os.path.realpath(c['path'])}" if c["link"] else ""
        print(f"{c['house']:<16} {c['kind']:<9} {format_size(c['bytes']):>7}  {state}  {c['path'].name}{link}")
    abandoned = set(abandoned_temp_folders(root))
    temps = sorted(p for p in root.glob(".*.tmp") if p.is_dir()) if root.is_dir() else []
    for tmp in temps:
        size = folder_bytes(tmp)
        state = "left by an interrupted build" if tmp in abandoned else "a build in progress"
        print(f"{'(temp)':<16} {'':<9} {format_size(size):>7}  {state}  {tmp.name}")
    total = sum(c["bytes"] for c in folders)
    print(f"{len(folders)} caches, {format_size(total)} in {root}" + _others(root, folders, "not listed:"))
    return 0


def _others(root: Path, caches: list[dict], done: str) -> str:
    """What ``root`` holds beside its caches (visible entries only), for the last line of
    ``list`` and ``clear``: ``; DONE N folders and M files that are not objsearch caches: a, b, ...``."""
    paths = {c["path"] for c in caches}
    others = sorted(p for p in root.iterdir() if not p.name.startswith(".") and p not in paths) if root.is_dir() else []
    if not others:
        return ""
    folders = sum(p.is_dir() for p in others)
    counts = [
        f"{n} {word}{'s' if n != 1 else ''}" for n, word in ((folders, "folder"), (len(others) - folders, "file")) if n
    ]
    names = ", ".join(p.name for p in others[:6]) + (f" and {len(others) - 6} more" if len(others) > 6 else "")
    return f"; {done} {' and '.join(counts)} that {'is' if len(others) == 1 else 'are'} not objsearch caches: {names}"


def run_verify(args: argparse.Namespace) -> int:
    """``objsearch cache verify``: check every cache's file digests; ``UserError`` if one is stale or damaged."""
    from objsearch.errors import UserError
    from objsearch.sim.cache import cache_folders

    root = _root(args, must_exist=True)
    houses = None
    if args.suite:
        from objsearch.sim.suites import load_suite_file

        suite = load_suite_file(args.suite)
        houses = {*suite["houses"], *suite.get("training_houses", {})}
    folders = [c for c in cache_folders(root, digests=True) if houses is None or c["house"] in houses]
    if not folders:  # nothing checked is not "all intact"
        raise UserError(
            f"no caches{f' of {args.suite}' if args.suite else ''} in {root} to verify; "
            f"objsearch cache build --suite SUITE{f' --cache-dir {root}' if args.cache_dir else ''} builds them"
        )
    damaged = [c for c in folders if c["problem"] is not None]
    for c in folders:
        print(f"{c['path'].name}: {'ok' if c['problem'] is None else c['problem']}")
    if damaged:
        raise UserError(
            f"{len(damaged)} of {len(folders)} caches in {root} are not current or damaged; "
            "objsearch cache build rebuilds them, objsearch cache clear removes them"
        )
    print(f"{len(folders)} caches in {root}: all intact")
    return 0


def run_clear(args: argparse.Namespace) -> int:
    """``objsearch cache clear``: remove stale caches (or ``--house``'s, or ``--all``) and
    abandoned temp folders: only folders that objsearch made (``cache_meta``, ``is_temp_folder``),
    never through a symlink; what else the folder holds is left and named. ``UserError`` if a
    cache could not be removed (what was removed is said first)."""
    import shutil

    from objsearch.errors import UserError
    from objsearch.fileio import abandoned_temp_folders
    from objsearch.sim.cache import cache_folders
    from objsearch.sim.cache_folder import folder_bytes, format_size, locked

    root = _root(args)
    folders = cache_folders(root, digests=not (args.all or args.house))
    if args.all:
        doomed = folders
    elif args.house:
        doomed = [c for c in folders if c["house"] in args.house]
    else:
        doomed = [c for c in folders if c["problem"] is not None]
    links = [c for c in doomed if c["link"]]  # its target may be anyone's: left, and said so
    freed, removed, failed = 0, [], []
    for c in doomed:
        if c["link"]:
            continue
        with locked(c["path"]):  # not while it is being built
            shutil.rmtree(c["path"], ignore_errors=True)
        left = folder_bytes(c["path"]) if c["path"].exists() else 0
        freed += c["bytes"] - left
        (failed if c["path"].exists() else removed).append(c)
    for tmp in abandoned_temp_folders(root):
        size = folder_bytes(tmp)
        shutil.rmtree(tmp, ignore_errors=True)
        freed += size - (folder_bytes(tmp) if tmp.exists() else 0)
    kept = [c for c in folders if c not in doomed]
    print(
        f"removed {len(removed)} cache{'s' if len(removed) != 1 else ''}, {format_size(freed)} freed; kept "
        f"{len(kept)} current caches ({format_size(sum(c['bytes'] for c in kept))}) in {root}"
        + ("" if not kept else "; --all removes them too")
        + _others(root, folders, "left")
    )
    if links:
        print(
            f"left {len(links)} link{'s' if len(links) > 1 else ''} to a cache (not removed: objsearch does not delete "
            "through links): " + ", ".join(f"{c['path'].name} -> {os.path.realpath(c['path'])}" for c in links)
        )
    if failed:
        raise UserError(
            f"could not remove {len(failed)} cache(s) in full: {', '.join(c['path'].name for c in failed)}; "
            "check their permissions (or whether another process holds them), then run objsearch cache clear again"
        )
    return 0


def run_build(args: argparse.Namespace) -> int:
    """``objsearch cache build``: render every house of ``--suite`` (and ``--training`` houses) into the cache.

    Raises ``UserError`` for a bad suite, ``--perception`` without ``--observation predicted`` or a bad checkpoint.
    """
    from objsearch.errors import UserError
    from objsearch.sim.suites import load_suite_file

    suite = load_suite_file(args.suite)  # an unknown name is an error naming the house suites
    if args.perception and args.observation != "predicted":
        raise UserError("--perception applies to --observation predicted")
    check_executor_arguments(args)
    checkpoint = None
    if args.observation == "predicted":
        from objsearch.perception.inference import check_checkpoint_camera, resolve_checkpoint

        checkpoint = resolve_checkpoint(args.perception)
        # a bad checkpoint, or one trained on another camera than the caches' (the agent camera),
        # fails here, before any house is rendered
        check_checkpoint_camera(checkpoint)
    houses = dict(suite["houses"])
    if args.training:
        houses.update(suite["training_houses"])
    lines = build_caches(
        houses,
        args.cache_dir,
        perception=checkpoint,
        executor=args.executor,
        address=args.address,
        workers=args.workers,
        desc=f"houses of {args.suite}",
    )
    for line in lines:
        print(line)
    return 0


def build_caches(
    houses: dict[str, dict],
    cache_dir=None,
    settings=None,
    perception=None,
    *,
    executor: str = "local",
    address: str | None = None,
    workers: int | None = None,
    desc: str = "houses",
    progress: bool = True,
) -> list[str]:
    """Build the observation cache (``settings``, default: the agent camera) of every house
    (house id -> ``HouseRef`` fields) and, with ``perception`` (a checkpoint path), the
    network's predictions; one task per house (``objsearch.cluster.map_houses``). Returns
    one report line a cache, in the houses' order."""
    from functools import partial

    from objsearch.cluster import map_houses
    from objsearch.sim.cache import default_cache_dir
    from objsearch.sim.camera import AGENT_CAMERA

    root = Path(cache_dir or default_cache_dir()).resolve()  # what every worker, wherever it runs, writes to
    perception = None if perception is None else str(Path(perception).resolve())
    task = partial(build_house_cache, cache_dir=root, settings=settings or AGENT_CAMERA, perception=perception)
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
