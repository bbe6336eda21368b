"""``objsearch suite``: list the suites, make a suite file from your own houses, rebuild a
shipped house suite's file.

  objsearch suite list
  objsearch suite make --houses DIR --out my-suite.json [--targets a,b] [--episodes N] [--seed S]
                       [--starts anywhere|entrance] [--protocol paper|objectnav]
  objsearch suite rebuild NAME [NAME ...]

``make`` takes the folders that ``objsearch generate --out DIR`` writes and makes a suite
file as the shipped ones are made (goal poses, starts, spec hashes); ``objsearch-eval
--suite my-suite.json`` evaluates on it. The file names each house by its folder relative
to the file, so keep the file and the houses where they are, or move them together.
``--protocol objectnav`` makes a suite of the ObjectNav protocol: goal poses within 1 m of a
visible target, success only when the agent calls STOP at one, 500 steps.
``rebuild`` overwrites ``objsearch/sim/data/NAME.json`` (deliberately: bump the suite's
version, and its digest in ``objsearch.sim.suites.SUITE_DIGESTS``, which it prints); it renders
every pose of the suite's evaluation houses (minutes).
"""

from __future__ import annotations

import argparse
import sys

from objsearch.cliargs import non_negative_int, positive_float, positive_int, seed_list
from objsearch.errors import UserError


def add_parser(subparsers) -> None:
    """Add ``objsearch suite`` (list, make, rebuild) to ``subparsers``."""
    from objsearch.sim.env import STARTS
    from objsearch.sim.goals import PROTOCOLS
    from objsearch.sim.suite_build import EPISODES_PER_SPLIT
    from objsearch.sim.suites import SUITE_NAMES

    parser = subparsers.add_parser(
        "suite",
        help="list suites, make one from your houses, rebuild a shipped one",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    commands = parser.add_subparsers(dest="suite_command", metavar="ACTION", required=True)

    listing = commands.add_parser("list", help="the suites: name, world and the options each takes")
    listing.set_defaults(func=run_list)

    make = commands.add_parser("make", help="make a suite file from houses written by objsearch generate")
    make.add_argument(
        "--houses",
        required=True,
        metavar="DIR",
        help="folder of house folders (objsearch generate --out DIR: house-gen-2 houses by default)",
    )
    make.add_argument("--out", required=True, metavar="FILE", help="the suite file to write (.json)")
    make.add_argument(
        "--targets",
        type=name_list,
        metavar="A,B,...",
        help="target categories (default: the suites' targets with goal poses in at least half of the houses)",
    )
    make.add_argument(
        "--episodes",
        type=positive_int,
        default=EPISODES_PER_SPLIT,
        help=f"episodes of its one split (default: {EPISODES_PER_SPLIT})",
    )
    make.add_argument("--seed", type=non_negative_int, default=0, help="seed of the episodes drawn (default: 0)")
    make.add_argument(
        "--starts",
        choices=STARTS,
        default="anywhere",
        help="where episodes start: anywhere 6-40 steps from the goal (default), or near the house's "
        "entrance (house-gen-2 houses)",
    )
    make.add_argument(
        "--protocol",
        choices=PROTOCOLS,
        default="paper",
        help="how an episode succeeds: paper (the episode ends on reaching one of the views the target fills "
        "most; 1000 steps; default) or objectnav (the agent calls STOP within 1 m of a visible target; 500 steps)",
    )
    tier = make.add_argument_group(
        "the large-house tier's rules",
        "house-large-v2's are --protocol objectnav --goal-pixels 5 --goal-distance 1 --min-distance 12 "
        "--min-room-hops 3 --max-steps 500 --seeds 1 (docs/add_a_suite.md)",
    )
    tier.add_argument(
        "--goal-pixels", type=positive_int, metavar="N", help="objectnav: target pixels a goal view shows (default 20)"
    )
    tier.add_argument(
        "--goal-distance",
        type=positive_float,
        metavar="M",
        help="objectnav: those pixels' depth limit, metres (default 1)",
    )
    tier.add_argument(
        "--min-distance",
        type=positive_float,
        metavar="M",
        help="far starts: at least M metres walking from the nearest goal pose (drawn among every pose that "
        "meets the far-start rules, instead of 6-40 steps)",
    )
    tier.add_argument(
        "--min-room-hops",
        type=positive_int,
        metavar="K",
        help="far starts: in a room at least K doors from every room that holds the target",
    )
    tier.add_argument("--max-steps", type=positive_int, metavar="N", help="the step limit (default: the protocol's)")
    tier.add_argument(
        "--seeds",
        type=seed_list,
        metavar="A,B,...",
        help="the seeds a full evaluation plays (default: the paper's 1,5,13,45,99)",
    )
    make.add_argument(
        "--cache-dir",
        help="observation cache the houses are rendered into (default: $OBJSEARCH_CACHE "
        "or ~/.cache/objsearch; objsearch-eval reuses it)",
    )
    make.set_defaults(func=run_make)

    rebuild = commands.add_parser("rebuild", help="rebuild shipped house suite files from their seeds (minutes each)")
    rebuild.add_argument(
        "names", nargs="+", choices=SUITE_NAMES, metavar="NAME", help=f"one of {', '.join(SUITE_NAMES)}"
    )
    rebuild.add_argument("--cache-dir", help="observation cache (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)")
    rebuild.set_defaults(func=run_rebuild)


def name_list(text: str) -> list[str]:
    """Comma-separated names (``--targets``)."""
    names = [name.strip() for name in text.split(",") if name.strip()]
    if not names:
        raise argparse.ArgumentTypeError(f"expected comma-separated category names, e.g. bed,sofa (got {text!r})")
    return names


def run_list(args: argparse.Namespace) -> int:
    """``objsearch suite list``: print every suite's name, world, protocol, step limit, splits
    with their episodes, and the standard seeds; then the options each world's suites take
    (a suite file made by ``objsearch suite make``, ``FILE.json``, takes the houses'); returns 0."""
    from objsearch.eval.suites import SUITES, make_suite, standard_seeds, suite_class

    width = max(map(len, SUITES))
    print(f"{'suite':<{width}} {'world':<9} {'protocol':<9} {'steps':>5}  splits (episodes)  seeds")
    options = {}
    for name in SUITES:
        suite = make_suite(name)
        splits = ", ".join(f"{split} {len(suite.episodes(split))}" for split in suite.splits)
        seeds = ",".join(map(str, standard_seeds(name)))
        print(f"{name:<{width}} {suite.world:<9} {suite.protocol:<9} {suite.max_steps:>5}  {splits}  {seeds}")
        options.setdefault(suite.world, suite_class(name).options)
    for world, taken in options.items():
        also = " (and FILE.json, a suite file that objsearch suite make wrote)" if world == "house" else ""
        print(f"options of the {world} suites{also}: {', '.join(taken)}")
    return 0


def run_make(args: argparse.Namespace) -> int:
    """``objsearch suite make``: write a suite file from generated houses; ``UserError`` if ``--out`` is not .json."""
    from objsearch.fileio import check_writable
    from objsearch.sim.start_rules import MadeRules
    from objsearch.sim.suite_build import suite_from_houses
    from objsearch.sim.suites import write_suite_file

    if not args.out.endswith(".json"):
        raise UserError(
            f"--out {args.out}: a suite file's name ends in .json (objsearch-eval --suite tells it by that)"
        )
    check_writable(args.out, "--out")  # before the houses' caches are built, not after
    rules = MadeRules(
        goal_pixels=args.goal_pixels,
        goal_distance=args.goal_distance,
        min_distance=args.min_distance or 0.0,
        min_room_hops=args.min_room_hops or 0,
        max_steps=args.max_steps,
        seeds=args.seeds,
    )
    suite = suite_from_houses(
        args.houses, args.out, args.targets, args.episodes, args.seed, args.cache_dir, args.starts, args.protocol, rules
    )
    write_suite_file(args.out, suite)
    ((split, episodes),) = suite["splits"].items()
    print(
        f"wrote {args.out}: {len(suite['houses'])} houses, targets {', '.join(suite['categories']['targets'])}; "
        f"split {split} of {len(episodes)} episodes, protocol {args.protocol}. "
        f"Evaluate with: objsearch-eval --suite {args.out}",
        file=sys.stderr,
    )
    return 0


def run_rebuild(args: argparse.Namespace) -> int:
    """``objsearch suite rebuild``: rebuild the named shipped suite files under ``objsearch/sim/data``."""
    from objsearch.sim.suite_build import build_suite
    from objsearch.sim.suite_schema import content_digest
    from objsearch.sim.suites import DATA_DIR, write_suite_file

    for name in args.names:
        path = DATA_DIR / f"{name}.json"
        suite = build_suite(name, args.cache_dir)
        write_suite_file(path, suite)
        print(f"wrote {path} (version {suite['version']}, content digest {content_digest(suite)}: SUITE_DIGESTS)")
    return 0
