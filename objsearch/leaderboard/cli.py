"""``objsearch leaderboard check|add|verify|render``: validate, store, replay and publish results."""

from __future__ import annotations

import argparse
import contextlib
import re
import sys
import time
from pathlib import Path

from objsearch.errors import UserError

DEFAULT_DIR = "leaderboard"


def add_parser(subparsers) -> None:
    """Add ``objsearch leaderboard`` (check, add, verify, render) to ``subparsers``."""
    from objsearch.leaderboard.validate import DETECT_FRACTION, DETECT_PROBABILITY

    parser = subparsers.add_parser(
        "leaderboard", help="validate, add, verify and render leaderboard submissions", description=__doc__
    )
    parser.add_argument(
        "--dir", default=DEFAULT_DIR, help=f"the leaderboard folder, holding submissions/ (default: ./{DEFAULT_DIR})"
    )
    commands = parser.add_subparsers(dest="leaderboard_command", metavar="ACTION", required=True)
    check = commands.add_parser("check", help="validate submissions (default: every stored one)")
    check.add_argument("files", nargs="*", metavar="FILE")
    check.add_argument(
        "--partial", action="store_true", help="check FILEs as `add --partial` would: some splits or seeds"
    )
    check.set_defaults(func=run_check)
    add = commands.add_parser(
        "add", help="validate results JSONs, store them and regenerate the pages (several: one check, one write)"
    )
    add.add_argument("files", nargs="+", metavar="FILE")
    add.add_argument(
        "--name", help="entry name, one FILE only (default: the agent's name; module:Class gives module.Class)"
    )
    add.add_argument("--replace", action="store_true", help="replace a stored entry of the same name")
    add.add_argument(
        "--partial",
        action="store_true",
        help="store a result that covers only some splits or seeds (listed apart on the pages, never ranked)",
    )
    add.add_argument(
        "--create", action="store_true", help="start a new leaderboard if --dir has no submissions/ folder"
    )
    add.set_defaults(func=run_add)
    verify = commands.add_parser(
        "verify",
        help="replay a random sample of stored entries' episodes; exit 2 unless identical",
        description="Replay a sample of each entry's episodes, drawn with fresh OS randomness now (a submitter "
        "cannot know which), and require identical records. The default sample catches a submission with "
        f"{DETECT_FRACTION:.0%} of its records altered with probability at least {DETECT_PROBABILITY:.0%}; "
        "the number replayed is recorded in the stored entry and shown on the pages.",
    )
    verify.add_argument("entries", nargs="*", metavar="ENTRY", help="a stored entry: its path or SUITE/NAME")
    verify.add_argument("--all", action="store_true", help="verify every stored entry")
    verify.add_argument(
        "--episodes",
        type=_episodes,
        default=None,
        metavar="K|all",
        help=f"episodes replayed per entry, drawn at random now (default: enough to catch {DETECT_FRACTION * 100:.0f}%% "
        f"altered records with probability {DETECT_PROBABILITY * 100:.0f}%%: 90 for a large entry); all: every episode",
    )
    verify.add_argument(
        "--trust",
        action="store_true",
        help="run an entry's agent although it is not a registered one (a .py file or module:Class): "
        "replay imports and runs its code; read it first",
    )
    verify.set_defaults(func=run_verify)
    render = commands.add_parser(
        "render", help="regenerate the pages, and the results table of the README beside --dir, from the stored entries"
    )
    render.set_defaults(func=run_render)


def _episodes(text: str) -> int | str:
    """``--episodes``: an integer >= 1, or ``all``."""
    if text == "all":
        return text
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: give a number of episodes >= 1, or all")
    return value


def _validated(path: str | Path, partial: bool = False, stored: bool = False) -> dict:
    """The results in ``path`` if they pass every check (``stored``: a stored entry, whose file
    name must be an entry name too); ``UserError`` if not."""
    from objsearch.leaderboard.validate import check_submission, load_submission

    if stored:
        check_entry_name(Path(path).stem, f"stored entry {path}", "rename the file")
    results = load_submission(path)
    if partial:
        results["partial"] = True
    problems = check_submission(results)
    if problems:
        raise UserError(f"submission {path} is rejected: " + "; ".join(problems))
    return results


def check_entry_name(name: str, what: str, fix: str = "pass another --name") -> None:
    """Refuse (``UserError``) an entry name that is not ``ENTRY_NAME``; ``what`` says where it
    came from, ``fix`` what to do."""
    from objsearch.leaderboard.validate import ENTRY_NAME

    if not ENTRY_NAME.fullmatch(name):
        raise UserError(
            f"{what}: entry name {name!r} must start with a letter or digit and hold only letters, digits, "
            f"'_', '-' or '.' (at most 100 characters); {fix}"
        )


def _stored(root: str | Path) -> list[Path]:
    """The stored entries of the leaderboard ``root``; an error if it is not a leaderboard folder."""
    from objsearch.leaderboard.render import SUBMISSIONS

    store = Path(root, SUBMISSIONS)
    if not store.is_dir():
        raise UserError(
            f"{Path(root)} is not a leaderboard folder (it has no {SUBMISSIONS}/ folder); run from the "
            "repository root or pass --dir PATH/leaderboard (add --create starts a new leaderboard there)"
        )
    return sorted(store.glob("*/*.json"))


@contextlib.contextmanager
def _writing(root: str | Path):
    """Hold the leaderboard ``root``'s lock: one writer at a time checks, stores and renders,
    so that no entry is lost and the pages list every stored one."""
    from objsearch.leaderboard.render import SUBMISSIONS
    from objsearch.sim.cache_folder import locked

    with locked(Path(root, SUBMISSIONS)):  # the lock file: <root>/.submissions.lock, removed after
        yield


def default_name(agent: str, observation: str = "gt") -> str:
    """An entry name from an agent spec: ``mypkg.mymodule:MyAgent`` gives ``mypkg.mymodule.MyAgent``,
    a file agent ``/path/to/seek_agent.py:SeekAgent`` gives ``seek_agent.SeekAgent`` (the file's
    module name, as if imported); characters a name cannot hold become ``_``. Results on the
    perception network's predictions (``observation`` ``predicted``) get ``PREDICTED_SUFFIX``,
    so that they never take the place of the same agent's ground-truth entry."""
    from objsearch.eval.registry import is_file_spec
    from objsearch.leaderboard.paper import PREDICTED_SUFFIX

    if is_file_spec(agent):
        path, _, attr = agent.rpartition(":")
        agent = f"{Path(path).stem}:{attr}"
    name = re.sub(r"[^A-Za-z0-9_.-]", "_", agent.replace(":", ".")).lstrip("_.-")
    return name + (PREDICTED_SUFFIX if observation == "predicted" else "")


def observation_of(results: dict) -> str:
    """What the results' agent observed: ``gt`` or ``predicted`` (the suite's ``observation`` option)."""
    return (results.get("config", {}).get("suite_config") or {}).get("observation") or "gt"


def run_check(args: argparse.Namespace) -> int:
    """``objsearch leaderboard check``: validate FILEs or every stored entry; ``UserError`` for the first rejected."""
    if args.partial and not args.files:
        raise UserError("--partial checks FILEs about to be added with --partial; stored entries carry their own mark")
    files = args.files or _stored(args.dir)
    if not files:
        raise UserError(f"no submissions under {Path(args.dir)}; pass FILE or --dir")
    for path in files:
        results = _validated(path, args.partial, stored=not args.files)
        kind = "partial, " if results.get("partial") else ""
        print(f"ok: {path} ({kind}{results['agent']} on {results['suite']}, {len(results['episodes'])} episodes)")
    return 0


def run_add(args: argparse.Namespace) -> int:
    """``objsearch leaderboard add``: validate results files, store each under
    ``submissions/<suite>/<name>.json`` and regenerate the pages, all in one write.

    The folder must be writable (checked first). The files are validated before the lock is
    taken; under it, the exists checks, the other entries' check (once, however many files),
    the write and the render: every file is stored, or none. A step that takes longer than a
    moment says so on stderr (``objsearch.progress``).

    Raises ``UserError`` for a rejected file, a bad ``--name`` (or one with several files), an
    unwritable folder, two files for one entry, or an existing entry without ``--replace``.
    """
    from objsearch.fileio import check_writable
    from objsearch.leaderboard.checked import Memo
    from objsearch.leaderboard.render import SUBMISSIONS, render
    from objsearch.leaderboard.validate import content_sha256
    from objsearch.progress import STAGE_DELAY_S, progress_bar, stage

    root = Path(args.dir)
    if args.name is not None:
        check_entry_name(args.name, "--name")
        if len(args.files) > 1:
            raise UserError(f"--name names one entry, but {len(args.files)} files were given; add them one by one")
    create = args.create and not Path(root, SUBMISSIONS).is_dir()  # made once the files pass, not before
    if create:
        check_writable(root, "leaderboard folder --dir", folder=True)
    else:
        _stored(root)
        for folder in (root, Path(root, SUBMISSIONS)):  # the pages, the entries: before the slow validation
            check_writable(folder, "leaderboard folder", folder=True)
    adding: dict[Path, tuple[str, dict]] = {}  # entry path -> (file, results)
    for file in args.files:
        with stage(f"checking {file}"):
            results = _validated(file, args.partial)
        if results.pop("verified", None) is not None:
            print(f"note: dropped {file}'s own 'verified' record: only verify writes it", file=sys.stderr)
        name = args.name if args.name is not None else default_name(results["agent"], observation_of(results))
        check_entry_name(name, f"agent {results['agent']!r}")
        target = Path(root, SUBMISSIONS, results["suite"], f"{name}.json")
        check_writable(target, "entry")
        if target in adding:
            raise UserError(f"{adding[target][0]} and {file} would both be the entry {target}; add one of them")
        adding[target] = (file, results)
    digests = {content_sha256(results): file for file, results in adding.values()}
    if len(digests) < len(adding):
        raise UserError(f"two of {', '.join(args.files)} hold the same results: one result is one entry")
    if create:
        Path(root, SUBMISSIONS).mkdir(parents=True, exist_ok=True)
    with _writing(root):
        for target in adding:
            if target.exists() and not args.replace:
                raise UserError(f"{target} exists; pass --replace to replace it or --name to add another entry")
        others = [path for path in _stored(root) if path not in adding]
        memo, stored = Memo(root), set()  # the entries checked before, unchanged since: not again (leaderboard.checked)
        with progress_bar(len(others), "checking the stored entries", "entry", delay=STAGE_DELAY_S) as bar:
            for path in others:  # the pages are rendered from every stored entry: refuse before writing
                digest = memo.content_sha256(path, lambda p: _validated(p, stored=True))
                stored.add(digest)
                file = digests.get(digest)
                if file is not None:
                    raise UserError(
                        f"{file} holds the same results as the stored entry {path}: one result is one entry; "
                        f"pass --replace --name {path.stem} to store it again under that name"
                    )
                bar.update()
        with stage("rendering the pages"):
            written = render(root, store={target: results for target, (_, results) in adding.items()}, memo=memo)
        for target in adding:
            memo.remember(target, content_sha256(adding[target][1]))
        memo.save(keep=stored | set(digests))
    for path in written:
        if path not in adding:
            print(f"wrote {path}", file=sys.stderr)
    for target, (_, results) in adding.items():
        print(f"added {target}" + (" (partial: listed apart, not ranked)" if results.get("partial") else ""))
    return 0


def _entry_path(root: str | Path, entry: str) -> Path:
    """A stored entry given as its path or as ``SUITE/NAME``."""
    from objsearch.leaderboard.render import SUBMISSIONS

    path = Path(entry)
    if path.is_file():
        return path
    named = Path(root, SUBMISSIONS, f"{entry}.json")
    if entry.count("/") == 1 and named.is_file():
        return named
    raise UserError(
        f"no stored entry {entry!r}: neither a file nor SUITE/NAME of {named.parent.parent} "
        "(objsearch leaderboard check lists the stored entries)"
    )


def run_verify(args: argparse.Namespace) -> int:
    """``objsearch leaderboard verify``: replay a random sample of each entry's episodes;
    ``UserError`` unless identical. The number replayed is recorded in each stored entry that
    passed (``verified``), and the pages are rendered again, when the folder can be written."""
    from objsearch.cluster import one_math_thread
    from objsearch.leaderboard.validate import (
        DETECT_FRACTION,
        DETECT_PROBABILITY,
        check_submission,
        load_submission,
        miss_probability,
        replay_count,
        replay_units,
        sample_size,
        untrusted_code,
        verify_submission,
    )

    one_math_thread()  # a few episodes at a time: more torch threads only fight whatever else runs

    if bool(args.all) == bool(args.entries):
        raise UserError("pass ENTRY (a stored entry's path or SUITE/NAME) or --all, not both or neither")
    paths = _stored(args.dir) if args.all else [_entry_path(args.dir, e) for e in args.entries]
    if not paths:
        raise UserError(f"no stored entries under {Path(args.dir)} to verify")
    start, passed, failures = time.monotonic(), {}, []
    for path in paths:  # every one: an entry that does not pass does not keep the others from being checked
        t = time.monotonic()
        results = load_submission(path)
        total = len(replay_units(results)) if isinstance(results.get("episodes"), list) else 0
        k = total if args.episodes == "all" else args.episodes
        problems = verify_submission(results, k, trust=args.trust)
        if problems:
            refused = not args.trust and not check_submission(results) and untrusted_code(results["agent"])
            said = "is not replayed (not verified)" if refused else "fails verification"
            failures.append(f"submission {path} {said}: " + "; ".join(problems))
            print(f"{'not replayed' if refused else 'failed'}: {path}")
            continue
        replayed = replay_count(results, k)
        print(
            f"verified: {path} ({replayed} of {total} episodes, drawn at random, replayed identical, "
            f"{time.monotonic() - t:.1f} s)"
        )
        if replayed < sample_size(total):
            print(
                f"note: {replayed} episodes catch a submission with {DETECT_FRACTION:.0%} of its records altered "
                f"with probability {1 - miss_probability(total, replayed):.2f} only; the default "
                f"({sample_size(total)}) reaches {DETECT_PROBABILITY:.2f}",
                file=sys.stderr,
            )
        passed[path] = (results, replayed, total)
    _record_verified(args.dir, passed)
    if len(failures) == 1:
        raise UserError(failures[0])
    if failures:
        raise UserError(
            f"{len(failures)} of {len(paths)} entries did not pass ({len(passed)} did): " + " | ".join(failures)
        )
    if len(paths) > 1:
        print(f"verified {len(paths)} entries in {time.monotonic() - start:.0f} s")
    return 0


def _record_verified(root: str | Path, passed: dict[Path, tuple[dict, int, int]]) -> None:
    """Store in each stored entry of ``passed`` ({path: (results, replayed, episodes)}) how many
    of its episodes were replayed (``verified``; the most for its present content), and render
    the pages again, all in one write under the lock. An entry changed since it was read, or a
    path outside ``root``'s submissions, is left as it is; an unwritable folder only warns."""
    from objsearch.fileio import check_writable
    from objsearch.leaderboard.checked import Memo
    from objsearch.leaderboard.render import SUBMISSIONS, render
    from objsearch.leaderboard.validate import content_sha256, load_submission, replayed_of

    store = Path(root, SUBMISSIONS).resolve()
    mine = {path: v for path, v in passed.items() if path.resolve().parent.parent == store}
    if not mine:
        return
    try:
        check_writable(root, "leaderboard folder", folder=True)
        check_writable(store, "leaderboard folder", folder=True)
    except UserError as err:
        print(f"warning: the replay counts are not recorded: {err}", file=sys.stderr)
        return
    with _writing(root):
        updates = {}
        for path, (results, replayed, total) in mine.items():
            digest = content_sha256(results)
            try:
                now = load_submission(path)
            except UserError:
                continue
            if content_sha256(now) != digest:  # replaced meanwhile (add --replace): not what was replayed
                continue
            before = replayed_of(now)
            if before is not None and before[0] >= replayed:
                continue
            updates[Path(root, SUBMISSIONS, path.parent.name, path.name)] = {
                **now,
                "verified": {"replayed": replayed, "episodes": total, "sha256": digest},
            }
        if updates:
            memo = Memo(root)  # the other entries were checked by add: render reads them faster
            written = render(root, store=updates, memo=memo)
            for path in updates:
                memo.remember(path, content_sha256(updates[path]))
            memo.save()
            for path in updates:
                print(f"recorded {updates[path]['verified']['replayed']} replayed episodes in {path}", file=sys.stderr)
            for path in written:
                if path not in updates:
                    print(f"wrote {path}", file=sys.stderr)


def run_render(args: argparse.Namespace) -> int:
    """``objsearch leaderboard render``: regenerate README.md and index.html from the stored entries."""
    from objsearch.fileio import check_writable
    from objsearch.leaderboard.render import render

    _stored(args.dir)
    check_writable(args.dir, "leaderboard folder", folder=True)
    with _writing(args.dir):
        written = render(args.dir)
    for path in written:
        print(f"wrote {path}")
    return 0
