"""``objsearch reproduce TABLE``: rebuild one of the paper's tables (or ``--suite S --methods
A,B``) from what is missing, resumably.

The table becomes a plan of steps, each with an output and a "done" check, so that a rerun
after any interrupt skips what is finished and resumes what was not:

    train SUITE/METHOD/seedK  a training run (``objsearch train``, the shipped recipe) into
                              CHECKPOINTS/SUITE/METHOD[/seedK]; done: a finished run is there
    eval SUITE/ENTRY          ``objsearch-eval`` of every training run, into WORK/results/;
                              done: the results file (an interrupted one resumes its episodes)
    add SUITE/ENTRY           ``objsearch leaderboard add``; done: the entry holds those results
    verify SUITE/ENTRY        ``objsearch leaderboard verify``; done: replayed for that content
    render TABLE              ``objsearch leaderboard render`` and WORK/TABLE.md (always runs)

The recipe of a training run is the ``command.txt`` shipped beside its checkpoint (of its
seed, else of seed 0 with the seed changed), or the agent's default; a ``--set`` naming a
file of another run (``pretrained``, ``explorer``) makes that run a step it needs.
``--dry-run`` prints the plan with each step's estimated time (``reproduce_cost``).
A stored entry that the plan did not write (a shipped one, say) is never replaced, nor a full
entry by a partial one, unless ``--replace`` is given: the plan refuses before any step runs.
``--executor ray`` runs the training runs and evaluations as Ray tasks (the records are
the local run's); add, verify and render run here.
"""

from __future__ import annotations

import argparse

from objsearch.leaderboard.reproduce_plan import WORK, make_plan


def add_parser(subparsers) -> None:
    """Add ``objsearch reproduce`` to ``subparsers``."""
    from objsearch.cliargs import key_value, positive_int, seed_list
    from objsearch.cluster import EXECUTORS

    names = lambda text: tuple(dict.fromkeys(s.strip() for s in text.split(",") if s.strip()))  # noqa: E731
    p = subparsers.add_parser(
        "reproduce",
        help="train what is missing, evaluate, add, verify and render one of the paper's tables (resumable)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    # fmt: off
    options = [
        ("table", {"nargs": "?", "metavar": "TABLE", "help": "table1, table2, table3 or table4 (or 1-4)"}),
        ("--suite", {"help": "the suite (without TABLE), or one of TABLE's suites"}),
        ("--methods", {"type": names, "help": "comma-separated agents (without TABLE), or some of TABLE's"}),
        ("--observations", {"type": names, "help": "gt, predicted and/or predicted_trained (default: the table's; gt without TABLE)"}),
        ("--runs", {"type": positive_int, "help": "training runs per learned method (default: 3; 1 on gridworld)"}),
        ("--out", {"metavar": "DIR", "help": f"everything in DIR: DIR/checkpoints, DIR/leaderboard, results and step records (default: the shipped agents/checkpoints and leaderboard/, work files in {WORK})"}),
        ("--leaderboard", {"metavar": "DIR", "help": "the leaderboard to add to (default: ./leaderboard, DIR/leaderboard with --out)"}),
        ("--replace", {"action": "store_true", "help": "replace stored entries of the same names, shipped or verified ones too (default: refuse any entry that this reproduction did not write, and a partial entry in a full one's place)"}),
        ("--config", {"choices": ("paper", "tiny"), "default": "paper", "help": "tiny: a test-sized run (needs --out): 1 run of 2000 training steps (50 episodes on gridworld), gt only, the first split and seed, 10-step episodes, 5 episodes verified; its entries are partial (default: paper)"}),
        ("--train-budget", {"type": positive_int, "metavar": "N", "help": "training steps (house) or episodes (gridworld) of every run (default: its recipe's)"}),
        ("--train-set", {"type": key_value, "action": "append", "default": [], "metavar": "KEY=VALUE", "help": "a training config field for every run; repeatable"}),
        ("--splits", {"type": names, "help": "evaluate only these splits (the entries are partial)"}),
        ("--seeds", {"type": seed_list, "help": "evaluation seeds (default: the suite's standard ones; others: partial)"}),
        ("--max-steps", {"type": positive_int, "help": "episode step limit (default: the suite's; another: partial)"}),
        ("--verify-episodes", {"type": positive_int, "metavar": "K", "help": "episodes replayed per entry (default: verify's)"}),
        ("--batch", {"type": positive_int, "default": 32, "help": "episodes per evaluation worker in lockstep (default: 32)"}),
        ("--dry-run", {"action": "store_true", "help": "print the plan and its estimated time on this machine; run nothing"}),
        ("--executor", {"choices": EXECUTORS, "default": "local", "help": "ray: the training runs and evaluations as Ray tasks"}),
        ("--address", {"metavar": "ADDR", "help": "with --executor ray: the cluster (default: start a local one)"}),
        ("--workers", {"type": positive_int, "help": "evaluation processes here, or the CPUs of a local Ray cluster"}),
        ("--quiet", {"action": "store_true", "help": "no progress bars"}),
    ]
    # fmt: on
    for flag, options_of in options:
        p.add_argument(flag, **options_of)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """``objsearch reproduce``: plan, then print the plan (``--dry-run``) or run what is not done."""
    from objsearch.cluster import check_executor_arguments

    check_executor_arguments(args)
    plan = make_plan(args)
    if args.dry_run:
        from objsearch.leaderboard.reproduce_cost import print_plan

        print_plan(plan)
        return 0
    from objsearch.leaderboard.reproduce_run import execute

    execute(plan, args.executor, args.address, args.workers, progress=not args.quiet)
    return 0
