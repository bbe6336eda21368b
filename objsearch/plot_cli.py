"""``objsearch plot grg RUN``: draw the Goals Relational Graph an HRL-GRG agent learned.

  objsearch plot grg agents/checkpoints/gridworld/hrl_grg --out grg.png      # the paper's Figure 4
  objsearch plot grg agents/checkpoints/house-single/hrl_grg --out grg.png   # the paper's Figure 5

RUN is a checkpoint or run folder with a ``grg.npz`` (``objsearch train`` writes one for
``hrl_grg`` and its ablations) or the file itself. The world is told by the graph (16 goals:
the grid world, with the share of goals whose chain neighbour is among their two strongest
out-edges; one node per object category: the houses, with the edge list); ``--world``
checks it.

The GRG is part of one method, so its drawing lives with the method in the reference
agents (``objsearch_agents.grg_plot``); objsearch imports them only when this command runs,
never at module level. Top-level glue, like ``objsearch/train.py``.
"""

from __future__ import annotations

import argparse

from objsearch.cliargs import positive_int
from objsearch.errors import UserError

WORLDS = ("gridworld", "house")


def add_parser(subparsers) -> None:
    """Add ``objsearch plot`` (``grg``) to ``subparsers``."""
    parser = subparsers.add_parser(
        "plot",
        help="figures of what an agent learned (the GRG of HRL-GRG)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    commands = parser.add_subparsers(dest="plot_command", metavar="FIGURE", required=True)
    grg = commands.add_parser(
        "grg",
        help="draw a learned Goals Relational Graph (grid world or house) as a PNG",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    grg.add_argument("run", metavar="RUN", help="checkpoint or run folder with grg.npz, or a grg.npz file")
    grg.add_argument("--out", default="grg.png", help="PNG to write (default: grg.png)")
    grg.add_argument("--world", choices=WORLDS, help="the world the graph must be of (default: told by the graph)")
    grg.add_argument("--edges", type=positive_int, help="house GRGs: at most this many edges (default: 24)")
    grg.set_defaults(func=run_grg)


def run_grg(args: argparse.Namespace) -> int:
    """``objsearch plot grg``: draw a learned GRG to ``--out``; ``UserError`` if objsearch_agents is not installed."""
    try:
        from objsearch_agents.grg_plot import plot_grg
    except ModuleNotFoundError as err:
        if not (err.name or "").startswith("objsearch_agents"):
            raise
        raise UserError(
            "objsearch plot grg draws with the reference agents (objsearch_agents), which are not "
            "installed; install the objsearch distribution with its agents (pip install -e .)"
        ) from None
    for line in plot_grg(args.run, args.out, world=args.world, edges=args.edges):
        print(line)
    return 0
