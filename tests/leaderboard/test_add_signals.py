"""``objsearch leaderboard add A B`` is all-or-nothing under SIGTERM and Ctrl-C: a signal that
arrives while the entries and pages are renamed into place waits until every one of them is
(``objsearch.interrupt.signals_deferred``, ``render._write_together``); the process then
stops as the signal says. Real processes, real signals, sent at the first rename."""

import json
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

SHIPPED = Path(__file__).resolve().parents[2] / "leaderboard" / "submissions" / "gridworld"

# objsearch's CLI, with os.replace sending the process SIGNAL right after the first entry is renamed
# (Ctrl-C as a terminal sends it: a shell starts background jobs with SIGINT ignored)
AT_FIRST_RENAME = """
import os, signal, sys
signal.signal(signal.SIGINT, signal.default_int_handler)
real, sent = os.replace, []
def replace(src, dst, *args, **kwargs):
    real(src, dst, *args, **kwargs)
    if not sent and str(dst).endswith(".json") and "submissions" in str(dst):
        sent.append(dst)
        os.kill(os.getpid(), getattr(signal, sys.argv[1]))
os.replace = replace
from objsearch.cli import main
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.parametrize("signame, status", [("SIGTERM", 143), ("SIGINT", 130)])
def test_a_signal_during_the_renames_stores_every_entry_and_page_or_none(tmp_path, signame, status):
    files = []
    for name in ("random", "oracle"):
        files.append(tmp_path / f"{name}-results.json")
        shutil.copyfile(SHIPPED / f"{name}.json", files[-1])
    board = tmp_path / "board"
    argv = ["leaderboard", "--dir", str(board), "add", *map(str, files), "--create"]
    proc = subprocess.run(
        [sys.executable, "-c", AT_FIRST_RENAME, signame, *argv], capture_output=True, text=True, timeout=300
    )
    assert proc.returncode == status, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr
    stored = sorted(p.name for p in (board / "submissions" / "gridworld").glob("*.json"))
    readme = (board / "README.md").read_text() if (board / "README.md").exists() else ""
    assert stored == ["oracle.json", "random.json"], "the signal waited until every entry was stored"
    assert "oracle" in readme and "random" in readme, "and the pages list what is stored"
    for name in ("oracle", "random"):
        assert json.loads((board / "submissions" / "gridworld" / f"{name}.json").read_text())["agent"] == name
    assert not list(board.rglob(".*.tmp")), "no temp file is left"


def test_signals_deferred_delivers_the_signal_after_the_block():
    from objsearch.interrupt import Terminated, signals_deferred, sigterm_as_interrupt

    done = []
    with pytest.raises(Terminated), sigterm_as_interrupt():
        with signals_deferred():
            signal.raise_signal(signal.SIGTERM)
            done.append("the block ran to its end")
    assert done == ["the block ran to its end"]
    with signals_deferred():  # no signal: nothing happens after
        pass
