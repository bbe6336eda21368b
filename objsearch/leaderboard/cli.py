"""``objsearch leaderboard check|add|render``: validate, store and publish results."""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from objsearch.errors import UserError

DEFAULT_DIR = "leaderboard"
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]*$")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("leaderboard", help="validate, add and render leaderboard submissions", description=__doc__)
    parser.add_argument("--dir", default=DEFAULT_DIR, help=f"the leaderboard folder (default: ./{DEFAULT_DIR})")
    commands = parser.add_subparsers(dest="leaderboard_command", metavar="ACTION", required=True)
    check = commands.add_parser("check", help="validate submissions (default: every stored one)")
    check.add_argument("files", nargs="*", metavar="FILE")
    check.set_defaults(func=run_check)
    add = commands.add_parser("add", help="validate a results JSON, store it and regenerate the pages")
    add.add_argument("file", metavar="FILE")
    add.add_argument("--name", help="entry name (default: the agent's name)")
    add.add_argument("--replace", action="store_true", help="replace a stored entry of the same name")
    add.set_defaults(func=run_add)
    render = commands.add_parser("render", help="regenerate README.md and index.html from the stored submissions")
    render.set_defaults(func=run_render)


def _validated(path: str | Path) -> dict:
    from objsearch.leaderboard.validate import check_submission, load_submission

    results = load_submission(path)
    problems = check_submission(results)
    if problems:
        raise UserError(f"submission {path} is rejected: " + "; ".join(problems))
    return results


def run_check(args: argparse.Namespace) -> int:
    from objsearch.leaderboard.render import SUBMISSIONS

    files = args.files or sorted(str(p) for p in Path(args.dir, SUBMISSIONS).glob("*/*.json"))
    if not files:
        raise UserError(f"no submissions under {Path(args.dir, SUBMISSIONS)}; pass FILE or --dir")
    for path in files:
        results = _validated(path)
        print(f"ok: {path} ({results['agent']} on {results['suite']}, {len(results['episodes'])} episodes)")
    return 0


def run_add(args: argparse.Namespace) -> int:
    from objsearch.fileio import write_json
    from objsearch.leaderboard.render import SUBMISSIONS, render

    results = _validated(args.file)
    name = args.name or results["agent"]
    if not NAME.match(name):
        raise UserError(f"entry name {name!r} must be letters, digits, '_', '-' or '.'; pass --name")
    target = Path(args.dir, SUBMISSIONS, results["suite"], f"{name}.json")
    if target.exists() and not args.replace:
        raise UserError(f"{target} exists; pass --replace to replace it or --name to add another entry")
    write_json(target, results, indent=None)
    for path in render(args.dir):
        print(f"wrote {path}", file=sys.stderr)
    print(f"added {target}")
    return 0


def run_render(args: argparse.Namespace) -> int:
    from objsearch.leaderboard.render import render

    for path in render(args.dir):
        print(f"wrote {path}")
    return 0
