"""``objsearch data rebuild``: rebuild the benchmark's fixed data from its seeds.

  objsearch data rebuild gridworld [--out DIR]      the grid-world maps and task lists
  objsearch data rebuild assets [--out DIR]         the house object meshes and their manifest
  objsearch data rebuild suites NAME [NAME ...]     shipped house suite files (= objsearch suite rebuild)
  objsearch data rebuild agent-io-doc [--check]     the generated "Actions and observations" of docs/add_your_agent.md

The shipped files are the benchmark: code reads them and never regenerates them, so a
generator change cannot silently change results. Rebuild deliberately, after bumping the
version that keys the data (``DATA_VERSION`` in ``objsearch/gridworld/dataset.py``,
``ASSETS_VERSION`` in ``objsearch/house/assets.py``, the suite's version); the tests check
that the generators still reproduce the shipped files (``DEVELOPERS.md``, "Benchmark data
is fixed"). The default ``--out`` is where the package reads the data from, so a rebuild
without it overwrites the shipped files.

Top-level glue: it drives the grid world, the houses and the suites (``eval``), so it sits
above the layers, like ``objsearch/cli.py``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from objsearch.errors import UserError


def add_parser(subparsers) -> None:
    """Add ``objsearch data`` (``rebuild gridworld|assets|suites``, ``agent-io-doc``) to ``subparsers``."""
    from objsearch.sim.suites import SUITE_NAMES

    parser = subparsers.add_parser(
        "data",
        help="rebuild the benchmark's fixed data (maps, meshes, suite files)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    commands = parser.add_subparsers(dest="data_command", metavar="ACTION", required=True)
    rebuild = commands.add_parser(
        "rebuild",
        help="rebuild fixed data from its seeds (deliberately: bump its version)",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    what = rebuild.add_subparsers(dest="data_kind", metavar="DATA", required=True)

    grid = what.add_parser("gridworld", help="the grid-world maps (100 train, 20 test) and task lists (seconds)")
    grid.add_argument(
        "--out",
        type=Path,
        metavar="DIR",
        help="folder to write train/, test/, tasks/, VERSION.json to (default: the shipped objsearch/gridworld/data)",
    )
    grid.set_defaults(func=run_gridworld)

    assets = what.add_parser("assets", help="the house object meshes and manifest.json (seconds)")
    assets.add_argument(
        "--out",
        type=Path,
        metavar="DIR",
        help="assets folder to write meshes/ to (default: $OBJSEARCH_ASSETS or the repository's assets/)",
    )
    assets.set_defaults(func=run_assets)

    suites = what.add_parser("suites", help="shipped house suite files, as objsearch suite rebuild does (minutes each)")
    suites.add_argument(
        "names", nargs="+", choices=SUITE_NAMES, metavar="NAME", help=f"one of {', '.join(SUITE_NAMES)}"
    )
    suites.add_argument("--cache-dir", help="observation cache (default: $OBJSEARCH_CACHE or ~/.cache/objsearch)")
    suites.set_defaults(func=run_suites)

    doc = what.add_parser(
        "agent-io-doc",
        help="the 'Actions and observations' section of docs/add_your_agent.md, "
        "rendered from the suites' envs (seconds; a checkout only)",
    )
    doc.add_argument("--check", action="store_true", help="only compare: exit 1 if the doc's section is stale")
    doc.set_defaults(func=run_agent_io_doc)


def _out_folder(out: Path | None, default: Path) -> Path:
    """``--out`` (or ``default``), refused if it is an existing file."""
    folder = default if out is None else out
    if folder.exists() and not folder.is_dir():
        raise UserError(f"--out {folder} is a file; give a folder (it is created if missing)")
    return folder


def run_gridworld(args: argparse.Namespace) -> int:
    """``objsearch data rebuild gridworld``: regenerate the grid-world maps and task lists into ``--out``."""
    from objsearch.gridworld.dataset import DATA_DIR, DATA_VERSION, NUM_TEST_MAPS, NUM_TRAIN_MAPS, SPLIT_GOALS, build

    out = _out_folder(args.out, DATA_DIR)
    build(out)
    print(
        f"wrote {NUM_TRAIN_MAPS} training maps, {NUM_TEST_MAPS} test maps and the task lists "
        f"{', '.join(SPLIT_GOALS)} ({DATA_VERSION}) under {out}",
        file=sys.stderr,
    )
    return 0


def run_assets(args: argparse.Namespace) -> int:
    """``objsearch data rebuild assets``: rebuild the house object meshes and manifest into ``--out``."""
    from objsearch.house.assets import assets_dir, build_assets

    out = _out_folder(args.out, assets_dir())
    manifest = build_assets(out)
    n = sum(len(v) for v in manifest["categories"].values())
    print(
        f"wrote {n} meshes for {len(manifest['categories'])} categories ({manifest['version']}) under {out / 'meshes'}",
        file=sys.stderr,
    )
    return 0


def run_suites(args: argparse.Namespace) -> int:
    """``objsearch data rebuild suites``: the same as ``objsearch suite rebuild``."""
    from objsearch.eval.suites.cli import run_rebuild

    return run_rebuild(args)  # the one implementation, also behind objsearch suite rebuild


def run_agent_io_doc(args: argparse.Namespace) -> int:
    """``objsearch data agent-io-doc``: rewrite (``--check``: only compare) the agent I/O section of the docs."""
    from objsearch.eval.agent_io import rebuild_doc

    return rebuild_doc(check=args.check)
