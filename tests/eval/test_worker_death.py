"""Worker processes of ``--workers N`` die with the evaluation that started them."""

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

BIN = Path(sys.executable).parent
SLOW_AGENT = """
import time

from objsearch_agents.baselines.oracle import OracleAgent


class SlowAgent(OracleAgent):
    def act(self, observation):
        time.sleep(0.1)
        return super().act(observation)
"""


def children(pid: int) -> list[int]:
    """The processes whose parent is ``pid``."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def alive(pid: int) -> bool:
    """Running: not gone and not a zombie waiting for a parent that does not reap it."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def wait_for(condition, seconds: float) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.2)
    return condition()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT])
def test_workers_die_with_the_evaluation(tmp_path, sig):
    (tmp_path / "slow_agent.py").write_text(SLOW_AGENT)
    parent = subprocess.Popen(
        [
            str(BIN / "objsearch-eval"),
            "--agent",
            "./slow_agent.py:SlowAgent",
            "--suite",
            "gridworld",
            "--workers",
            "2",
            "--quiet",
            "--out",
            "r.json",
        ],
        cwd=tmp_path,
        # Ctrl-C as a terminal delivers it: a shell's background job (nohup ... &) starts with SIGINT ignored,
        # and a process that inherits SIG_IGN keeps it (Python installs its handler only over SIG_DFL)
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        partial = tmp_path / "r.json.partial.jsonl"
        workers = lambda: [p for p in children(parent.pid) if "spawn_main" in Path(f"/proc/{p}/cmdline").read_text()]
        assert wait_for(lambda: len(workers()) == 2 and partial.exists(), 120), "the workers never started"
        started = workers()
        time.sleep(3)  # the workers build their agents and play
        assert all(map(alive, started))
        parent.send_signal(sig)
        assert wait_for(lambda: not any(map(alive, started)), 30), "workers outlived the evaluation"
        assert parent.wait(30) != 0
    finally:
        parent.kill()
        parent.wait()
