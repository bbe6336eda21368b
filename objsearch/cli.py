"""The ``objsearch`` command and its ``objsearch-eval`` shortcut.

Each subcommand lives beside the code it drives, in a module that provides
``add_parser(subparsers)``; the parser it adds sets ``func(args) -> int``. To add a
subcommand, add its module to ``COMMANDS``.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import sys

from objsearch.errors import UserError

# Subcommand modules, imported only when the parser is built (each keeps heavy imports
# inside its func).
COMMANDS = [
    "objsearch.eval.cli",
    "objsearch.eval.suites.cli",
    "objsearch.leaderboard.cli",
    "objsearch.house.cli",
    "objsearch.perception.cache_cli",
    "objsearch.perception.cli",
    "objsearch.train",
    "objsearch.leaderboard.reproduce",
    "objsearch.data_cli",
    "objsearch.plot_cli",
]


def build_parser() -> argparse.ArgumentParser:
    """The ``objsearch`` parser, with a subcommand from every module in ``COMMANDS``."""
    from objsearch import __version__

    parser = argparse.ArgumentParser(prog="objsearch", description="Benchmark suite for goal-driven object search.")
    parser.add_argument("--version", action="version", version=f"objsearch {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMANDS:
        importlib.import_module(module).add_parser(subparsers)
    return parser


def _run(parser: argparse.ArgumentParser, argv: list[str]) -> int:
    """Run the parsed command: bad input, a full disk and an interrupt end with one line on
    stderr (never a traceback) and their exit status (2, 2, 130 for Ctrl-C, 143 for SIGTERM)."""
    from objsearch.fileio import full_disk_error
    from objsearch.interrupt import interrupt_status, interrupted_line, sigterm_as_interrupt

    args = parser.parse_args(argv)
    try:
        with sigterm_as_interrupt():
            return int(args.func(args) or 0)
    except UserError as err:
        print(f"{parser.prog}: error: {err}", file=sys.stderr)
        return err.exit_code
    except KeyboardInterrupt as err:  # its message, if any, says what was saved and how to resume
        status = interrupt_status(err)
        print(f"{parser.prog}: {interrupted_line(status, str(err))}", file=sys.stderr)
        return status
    except OSError as err:  # a write no check of the command's own named: still one line, not a traceback
        if err.errno in (errno.EROFS, errno.EACCES) and err.filename:
            print(
                f"{parser.prog}: error: cannot use {err.filename} ({err.strerror}); choose a place you can write "
                "to, or fix its permissions",
                file=sys.stderr,
            )
            return 2
        full = full_disk_error(err, err.filename)
        if full is None:
            raise
        print(f"{parser.prog}: error: {full}", file=sys.stderr)
        return full.exit_code


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``objsearch``."""
    return _run(build_parser(), sys.argv[1:] if argv is None else argv)


def eval_main(argv: list[str] | None = None) -> int:
    """Entry point of ``objsearch-eval``: the same as ``objsearch eval``."""
    from objsearch.eval.cli import build_eval_parser

    return _run(build_eval_parser(prog="objsearch-eval"), sys.argv[1:] if argv is None else argv)


if __name__ == "__main__":
    sys.exit(main())
