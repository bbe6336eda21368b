"""The leaderboard workflow of docs/add_your_agent.md with a file agent, end to end, in
subprocesses as a user types it: evaluate in the agent's folder, then add and verify from
the repository root."""

import shutil
import subprocess
import sys
from pathlib import Path

from objsearch.leaderboard.cli import default_name

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent
AGENT_FILE = ROOT / "examples/objsearch-greedy-agent/objsearch_greedy_agent/__init__.py"
ENTRY = "gridworld/seek_agent.GreedyVisibleAgent"


def run(*args, cwd):
    return subprocess.run([str(BIN / args[0]), *args[1:]], capture_output=True, text=True, cwd=cwd, timeout=300)


def test_a_file_agent_evaluated_in_its_folder_is_added_and_verified_from_the_root(tmp_path):
    mine, root = tmp_path / "my agent", tmp_path / "repo"  # a space in the path, as on many laptops
    mine.mkdir()
    root.mkdir()
    shutil.copy(AGENT_FILE, mine / "seek_agent.py")
    out = run(
        "objsearch-eval", "--agent", "./seek_agent.py:GreedyVisibleAgent", "--suite", "gridworld",
        "--split", "unseen-goals", "--seeds", "1", "--quiet", "--out", str(root / "seek.json"), cwd=mine,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr

    out = run("objsearch", "leaderboard", "add", "seek.json", "--partial", "--create", cwd=root)
    assert out.returncode == 0, out.stderr
    assert (root / "leaderboard/submissions" / f"{ENTRY}.json").is_file(), out.stdout  # a clean default name
    out = run("objsearch", "leaderboard", "verify", ENTRY, "--episodes", "3", cwd=root)
    assert out.returncode == 2 and "Traceback" not in out.stderr, out.stderr  # it would run the file's code
    assert f"would import and run the Python file {(mine / 'seek_agent.py').resolve()}" in out.stderr
    assert "pass --trust" in out.stderr
    out = run("objsearch", "leaderboard", "verify", ENTRY, "--episodes", "3", "--trust", cwd=root)
    assert out.returncode == 0, out.stderr
    assert "3 of 100 episodes, drawn at random, replayed identical" in out.stdout

    (mine / "seek_agent.py").rename(mine / "moved.py")
    out = run("objsearch", "leaderboard", "verify", ENTRY, "--episodes", "3", "--trust", cwd=root)
    assert out.returncode == 2 and "Traceback" not in out.stderr, out.stderr
    assert (
        f"agent file {(mine / 'seek_agent.py').resolve()} is missing" in out.stderr
        and "put the file back" in out.stderr
    )


def test_default_entry_names():
    assert default_name("/home/me/seek_agent.py:SeekAgent") == "seek_agent.SeekAgent"
    assert default_name("mypkg.mymodule:MyAgent") == "mypkg.mymodule.MyAgent"
    assert default_name("hrl_grg") == "hrl_grg"
    # results on the perception network's predictions never take the ground-truth entry's name
    assert default_name("hrl_grg", "predicted") == "hrl_grg_predicted"
