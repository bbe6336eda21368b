"""``objsearch eval`` / ``objsearch-eval``: evaluate an agent on a suite and print the table."""

from __future__ import annotations

import argparse
import sys

from objsearch.cliargs import positive_int, seconds, seed_list
from objsearch.errors import UserError

DEFAULT_AGENT = "random"
DEFAULT_BATCH = 32
DEFAULT_VIDEO_EPISODES = 2
# The flags that set suite options: attribute of the parsed arguments -> option of the suite
# (each suite class names the options it takes; a flag its suite lacks is an error).
SUITE_FLAGS = {
    "maps": "maps",
    "tasks": "tasks",
    "max_steps": "max_steps",
    "render": "mode",
    "cache_dir": "cache_dir",
    "observation": "observation",
    "perception": "perception",
}


def configure(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the evaluation flags to ``parser`` (``objsearch eval`` and ``objsearch-eval``) and return it."""
    from objsearch.cluster import EXECUTORS
    from objsearch.eval.suites import DEFAULT_SUITE, SUITES

    parser.add_argument(
        "--agent",
        default=DEFAULT_AGENT,
        help=f"registered name, package.module:Class (also found in the current folder) or "
        f"path/to/file.py:Class (default: {DEFAULT_AGENT})",
    )
    parser.add_argument(
        "--suite",
        help=f"suite to evaluate on: {', '.join(SUITES)}, or a suite file (.json) made by "
        f"objsearch suite make (default: {DEFAULT_SUITE}; gridworld with --maps/--tasks)",
    )
    parser.add_argument(
        "--split",
        action="append",
        dest="splits",
        metavar="NAME",
        help="split to run; repeat for several (default: all)",
    )
    parser.add_argument(
        "--seeds",
        type=seed_list,
        help="comma-separated evaluation seeds (default: the suite's standard seeds: the paper's 1,5,13,45,99, "
        "or those its suite file records, e.g. 1 for the large-house tier)",
    )
    parser.add_argument(
        "--workers", type=positive_int, default=1, help="worker processes; results are identical for any number"
    )
    parser.add_argument(
        "--batch",
        type=positive_int,
        help=f"episodes each worker plays in lockstep (batched agents decide for all in one call); "
        f"the same results for any N (default: {DEFAULT_BATCH})",
    )
    parser.add_argument(
        "--episodes",
        type=positive_int,
        metavar="N",
        help="a quick look: play only the first N episodes of each split; the results are marked partial "
        "and the leaderboard refuses them (default: every episode)",
    )
    parser.add_argument("--checkpoint", help="checkpoint passed to the agent's load()")
    parser.add_argument(
        "--training-run",
        type=int,
        metavar="SEED",
        help="learned agents shipped with several training runs: evaluate only the run of this training "
        "seed (default: every run, reported across runs)",
    )
    parser.add_argument(
        "--out", help="write the results JSON here; an interrupted run resumes from OUT.partial.jsonl when rerun"
    )
    parser.add_argument(
        "--retry-failed",
        action="store_true",
        help="with --out naming the results of a finished run of the same settings: play again only its "
        "episodes that ended in an agent error (e.g. a step-time limit hit on a busy machine), keep the others",
    )
    parser.add_argument("--maps", help="grid world: a directory of map_XXXX.npz to use instead of the test maps")
    parser.add_argument("--tasks", help="grid world: a JSONL task file over --maps; one split named after the file")
    parser.add_argument("--max-steps", type=positive_int, help="step limit per episode (default: the suite's)")
    parser.add_argument(
        "--render",
        choices=("cached", "live"),
        help="house suites: pre-rendered observations (default; live for house-large-v2's suites) or render each step",
    )
    parser.add_argument(
        "--cache-dir", help="house suites: observation cache folder (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)"
    )
    parser.add_argument(
        "--observation",
        choices=("gt", "predicted"),
        help="house suites: ground-truth segmentation and depth (default) or the perception network's predictions",
    )
    parser.add_argument(
        "--perception",
        metavar="CHECKPOINT",
        help="house suites, --observation predicted: the network (default: the shipped one)",
    )
    parser.add_argument(
        "--step-time-limit",
        type=seconds,
        default=10.0,
        metavar="SECONDS",
        help="an agent call that takes longer fails its episode (default: 10; 0: no limit)",
    )
    parser.add_argument("--executor", choices=EXECUTORS, default="local", help="local processes or a Ray cluster")
    parser.add_argument("--address", help="Ray cluster address (default: start a local cluster)")
    parser.add_argument(
        "--video",
        metavar="DIR",
        help="house suites: write the map (PNG) and view (MP4) of the first --video-episodes episodes "
        "of each split (first seed) here",
    )
    parser.add_argument(
        "--video-episodes",
        type=positive_int,
        default=DEFAULT_VIDEO_EPISODES,
        metavar="N",
        help=f"with --video: episodes per split that get pictures; they play one at a time, the "
        f"rest batched (default: {DEFAULT_VIDEO_EPISODES}; what each costs: docs/video.md)",
    )
    parser.add_argument("--list-agents", action="store_true", help="list the installed agents and exit")
    parser.add_argument(
        "--quiet",
        action="store_true",
        help="no progress: no bar on a terminal, no progress line every 30 s in a log (stderr)",
    )
    parser.set_defaults(func=run)
    return parser


def add_parser(subparsers) -> None:
    """Add ``objsearch eval`` to ``subparsers``."""
    configure(subparsers.add_parser("eval", help="evaluate an agent on a suite", description=__doc__))


def build_eval_parser(prog: str = "objsearch-eval") -> argparse.ArgumentParser:
    """The parser of the ``objsearch-eval`` command (named ``prog``)."""
    from objsearch import __version__

    parser = configure(argparse.ArgumentParser(prog=prog, description=__doc__))
    parser.add_argument("--version", action="version", version=f"{prog} {__version__}")
    return parser


def run(args: argparse.Namespace) -> int:
    """Run an evaluation from parsed flags (or ``--list-agents``) and print the results table.

    Returns 1 when every episode failed with an agent error, else 0.
    """
    from objsearch.eval.registry import registered_agents

    if args.list_agents:
        for name, target in registered_agents().items():
            print(f"{name:<28} {target}")
        return 0

    from objsearch.cluster import check_address, one_math_thread
    from objsearch.eval.config import EvalConfig
    from objsearch.eval.registry import recorded_spec
    from objsearch.eval.results import format_table
    from objsearch.eval.runner import evaluate
    from objsearch.eval.suites import DEFAULT_SUITE, standard_seeds

    check_address(args.address, args.executor)
    if args.out is not None and not args.out.strip():  # not silently "no --out"
        raise UserError("--out is empty; give the results file's path, e.g. --out results.json")
    # Batched agents' forward passes are small: torch's default threads fight over shared cores
    # (hrl_grg on gridworld, 1500 episodes on 2 busy cores: 132 s with 2 threads, 17 s with 1).
    one_math_thread()
    if args.suite is None:
        args.suite = "gridworld" if args.maps or args.tasks else DEFAULT_SUITE
    config = EvalConfig(
        agent=recorded_spec(args.agent),  # a file agent's absolute path: replays find it from anywhere
        suite=args.suite,
        splits=tuple(args.splits or ()),
        seeds=args.seeds or standard_seeds(args.suite),
        checkpoint=args.checkpoint,
        training_run=args.training_run,
        suite_config=suite_config(args),
        step_time_limit=args.step_time_limit or None,
        episodes=args.episodes,
    )
    results = evaluate(
        config,
        workers=args.workers,
        progress=not args.quiet,
        executor=args.executor,
        address=args.address,
        out=args.out,
        video_dir=args.video,
        batch=args.batch or DEFAULT_BATCH,
        video_episodes=args.video_episodes,
        retry_failed=args.retry_failed,
    )
    failed = [r for r in results["episodes"] if "error" in r]
    if failed:  # first, so that a table of failures is never mistaken for a result
        first = failed[0]
        print(
            f"{len(failed)} of {len(results['episodes'])} episode(s) failed with an agent error; the first, "
            f"{first['split']}/seed {first['seed']}/{first['episode_id']}: {first['error']}",
            file=sys.stderr,
        )
        if "traceback" in first:
            print("its traceback (the agent's frames, innermost last):\n" + first["traceback"], file=sys.stderr)
        sys.stderr.flush()  # before the table on stdout
    print(format_table(results))
    if args.out:
        print(f"results written to {args.out}", file=sys.stderr)
    if failed and len(failed) == len(results["episodes"]):
        print("every episode failed: this is not a result (exit 1)", file=sys.stderr)
        return 1
    return 0


def suite_config(args: argparse.Namespace) -> dict:
    """The options of ``args.suite`` that its flags set; a flag for an option the suite does not
    take is an error naming the suites that take it."""
    from objsearch.eval.suites import suite_class, suites_taking

    options = suite_class(args.suite).options
    config = {}
    for attribute, option in SUITE_FLAGS.items():
        value = getattr(args, attribute)
        if value is None:
            continue
        if option not in options:
            flag = "--" + attribute.replace("_", "-")
            raise UserError(
                f"{flag} does not apply to suite {args.suite!r}; suites that take it: "
                f"{', '.join(suites_taking(option))}"
            )
        config[option] = value
    return config
