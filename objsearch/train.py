"""``objsearch train``: train an agent on a suite, resumably.

objsearch never imports ``objsearch_agents`` (or any agent package) statically. The agent is
found by name through the registry, like ``objsearch eval`` finds it, and trained through
its class's hook::

    AgentClass.train(*, suite, out, episodes, seed, overrides, fresh, progress, command[, steps]) -> dict

(``overrides``: the ``--set KEY=VALUE`` pairs, interpreted by the agent's config). An agent
class without ``train`` cannot be trained here. Re-running the same command resumes the run
in ``--out`` from its last checkpoint; Ctrl-C (or SIGTERM) finishes the current step, writes
a checkpoint and exits with 130 (143).
"""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from objsearch.cliargs import key_value, one_seed, positive_int
from objsearch.errors import UserError


def add_parser(subparsers) -> None:
    """Add ``objsearch train`` to ``subparsers``."""
    parser = subparsers.add_parser(
        "train",
        help="train an agent on a suite (resumable)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--agent", required=True, help="registered agent name or package.module:Class")
    parser.add_argument("--suite", default="gridworld", help="suite to train on (default: gridworld)")
    parser.add_argument(
        "--episodes", type=positive_int, help="training episodes (default: the agent's, the paper's 100000)"
    )
    parser.add_argument(
        "--steps",
        type=positive_int,
        help="house agents: environment steps of the main phase (default: the agent's)",
    )
    parser.add_argument("--seed", type=one_seed, default=0, help="run seed (default: 0)")
    parser.add_argument(
        "--out", help="run directory (default: runs/SUITE/AGENT-seedS); an existing run there is resumed"
    )
    parser.add_argument(
        "--set",
        action="append",
        type=key_value,
        default=[],
        dest="overrides",
        metavar="KEY=VALUE",
        help="override a field of the agent's training config; repeatable",
    )
    parser.add_argument("--fresh", action="store_true", help="start over even if --out holds a run")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """``objsearch train``: train (or resume) the agent's run in ``--out`` with its class's ``train``.

    Returns 0, or 130 if interrupted (143 by SIGTERM); ``UserError`` if the agent cannot be trained.
    """
    from objsearch.eval.registry import check_supports, resolve_agent
    from objsearch.fileio import check_writable
    from objsearch.interrupt import interrupted_line, stop_status

    cls = resolve_agent(args.agent)
    trainer = getattr(cls, "train", None)
    if not callable(trainer):
        raise UserError(f"agent {args.agent!r} cannot be trained (its class has no train(...) classmethod)")
    check_supports(args.agent, cls, args.suite)  # a world or protocol it cannot play: refused before training
    suite_dir = Path(args.suite).stem if args.suite.endswith(".json") else args.suite  # a suite file: its name
    out = args.out or f"runs/{suite_dir}/{args.agent.replace(':', '.')}-seed{args.seed}"
    check_writable(out, "--out", folder=True)  # before any training, not at the first checkpoint
    command = "objsearch " + " ".join(shlex.quote(a) for a in sys.argv[1:]) if sys.argv[1:2] == ["train"] else None
    budget = {"episodes": args.episodes} if args.steps is None else {"episodes": args.episodes, "steps": args.steps}
    summary = trainer(
        suite=args.suite,
        out=out,
        seed=args.seed,
        overrides=dict(args.overrides),
        fresh=args.fresh,
        progress=not args.quiet,
        command=command,
        **budget,
    )
    print(
        f"{args.agent}: {summary.get('finished')} episodes, {summary.get('env_steps')} env steps in {out}",
        file=sys.stderr,
    )
    if summary.get("interrupted"):
        status = stop_status()
        saved = f"checkpoint written to {out}; rerun the same command to resume"
        print(f"objsearch train: {interrupted_line(status, saved)}", file=sys.stderr)
        return status
    return 0
