"""Writers of one leaderboard: concurrent adds lose nothing, a failed write changes nothing,
and a folder that cannot be written is refused before any work."""

import contextlib
import copy
import errno
import json
import multiprocessing
import subprocess
import sys
from pathlib import Path

import pytest

from objsearch.cli import main
from objsearch.leaderboard import render as render_module
from objsearch.leaderboard.checked import MEMO
from objsearch.leaderboard.validate import check_submission

BIN = Path(sys.executable).parent
PAGES = ("README.md", "index.html", "paper_tables.md")


def _add(board: Path, file: Path, name: str, barrier) -> None:
    barrier.wait()  # every process adds at the same moment
    sys.exit(main(["leaderboard", "--dir", str(board), "add", str(file), "--name", name]))


def add_at_once(board: Path, adds: list[tuple[Path, str]]) -> list[int]:
    """Run ``objsearch leaderboard add FILE --name NAME`` for every (FILE, NAME) of ``adds`` in
    processes of their own, all at once; their exit statuses."""
    ctx = multiprocessing.get_context("fork")  # the children start with the suite already loaded
    barrier = ctx.Barrier(len(adds))
    procs = [ctx.Process(target=_add, args=(board, file, name, barrier)) for file, name in adds]
    for p in procs:
        p.start()
    for p in procs:
        p.join(timeout=300)
    return [p.exitcode for p in procs]


def page_data(board: Path) -> dict:
    """The data embedded in ``index.html``."""
    page = (board / "index.html").read_text()
    start = page.index("const DATA = ") + len("const DATA = ")
    return json.loads(page[start : page.index(";\n", start)])


def new_board(tmp_path: Path, results: dict) -> Path:
    assert check_submission(results) == []  # and the suite is loaded before the processes fork
    board = tmp_path / "board"
    (board / "submissions").mkdir(parents=True)
    return board


def test_sixteen_concurrent_adds_store_every_entry_once_and_the_pages_list_them_all(tmp_path, full_oracle):
    board = new_board(tmp_path, full_oracle)
    names = [f"entry{i:02d}" for i in range(16)]
    for i, name in enumerate(names):  # one result under two names is refused: told apart by their commits
        (tmp_path / f"{name}.json").write_text(json.dumps(dict(full_oracle, git_commit=f"{i:040x}")))
    assert add_at_once(board, [(tmp_path / f"{name}.json", name) for name in names]) == [0] * 16
    stored = sorted((board / "submissions" / "gridworld").iterdir())
    assert [p.name for p in stored] == [f"{name}.json" for name in names]
    assert all(
        json.loads(p.read_text()) == json.loads(json.dumps(dict(full_oracle, git_commit=f"{i:040x}")))
        for i, p in enumerate(stored)
    )
    readme = (board / "README.md").read_text()
    for split, rows in page_data(board)["tables"]["gridworld"].items():
        assert sorted(r["name"] for r in rows) == names, split
    for name in names:
        assert readme.count(f" | {name} | oracle (privileged) | gt | 1.00 |") == 3, name  # one row per split
    left = sorted(p.name for p in board.iterdir() if p.name != MEMO)  # the memo of checked entries is the board's
    assert left == [*sorted(PAGES), "submissions"]  # no lock or temp file left


def test_concurrent_adds_of_one_name_store_one_and_refuse_the_others(tmp_path, oracle_results):
    partial = dict(oracle_results, partial=True)
    board = new_board(tmp_path, partial)
    adds = []
    for i in range(8):  # the same result, told apart by its commit
        (tmp_path / f"r{i}.json").write_text(json.dumps(dict(partial, git_commit=f"{i:040x}")))
        adds.append((tmp_path / f"r{i}.json", "same"))
    codes = add_at_once(board, adds)
    assert sorted(codes) == [0] + [2] * 7, codes
    (stored,) = (board / "submissions" / "gridworld").iterdir()
    assert json.loads(stored.read_text())["git_commit"] == f"{codes.index(0):040x}"  # the one that said "added"
    assert "| – | same | oracle (privileged) | gt | 1.00 |" in (board / "README.md").read_text()


def test_a_failed_write_leaves_the_entries_and_pages_as_they_were(tmp_path, capsys, monkeypatch, oracle_results):
    partial = dict(oracle_results, partial=True)
    board = new_board(tmp_path, partial)
    (tmp_path / "oracle.json").write_text(json.dumps(oracle_results))
    assert main(["leaderboard", "--dir", str(board), "add", str(tmp_path / "oracle.json"), "--partial"]) == 0
    before = {p: p.read_bytes() for p in sorted(board.rglob("*")) if p.is_file()}

    real = render_module.atomic_write

    @contextlib.contextmanager
    def full_disk_at_the_last_page(path, *args):
        with real(path, *args) as f:
            if Path(path).name == "paper_tables.md":
                raise OSError(errno.ENOSPC, "No space left on device")
            yield f

    monkeypatch.setattr(render_module, "atomic_write", full_disk_at_the_last_page)
    (tmp_path / "b.json").write_text(json.dumps(dict(oracle_results, git_commit="b" * 40)))
    code = main(["leaderboard", "--dir", str(board), "add", str(tmp_path / "b.json"), "--partial", "--name", "b"])
    err = capsys.readouterr().err
    assert code == 2 and "paper_tables.md: No space left on device" in err and "Traceback" not in err
    assert "the leaderboard is as it was" in err
    assert {p: p.read_bytes() for p in sorted(board.rglob("*")) if p.is_file()} == before  # no temp file either


def test_a_read_only_leaderboard_is_refused_before_the_file_is_validated(tmp_path, oracle_results):
    board = new_board(tmp_path, dict(oracle_results, partial=True))
    bad = copy.deepcopy(dict(oracle_results, partial=True))
    bad["episodes"].pop()  # validated first, it would be refused for this
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    script = (
        f'mount --bind "{board}" "{board}" && mount -o remount,ro,bind "{board}" || exit 99\n'
        f'exec "{BIN / "objsearch"}" leaderboard --dir "{board}" add "{tmp_path / "bad.json"}" --partial'
    )
    try:  # a read-only mount of its own, in a user and mount namespace: no root needed, nothing else sees it
        out = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=120)
    except FileNotFoundError:
        out = None
    if out is None or out.returncode == 99:
        pytest.skip("cannot mount a read-only folder here (needs unshare with user namespaces)")
    assert out.returncode == 2, out.stderr
    assert f"leaderboard folder {board}: cannot write in {board} (Read-only file system)" in out.stderr
    assert "rejected" not in out.stderr and "Traceback" not in out.stderr
