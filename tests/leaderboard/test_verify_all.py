"""``objsearch leaderboard verify --all`` goes through every entry: one it refuses to replay
(a file agent without ``--trust``) or that fails does not stop it, and the one error line
names each entry that did not pass (objsearch.leaderboard.cli.run_verify)."""

import json

from objsearch.cli import main
from objsearch.eval.runner import EvalConfig, evaluate

FILE_AGENT = '''
from objsearch_agents.baselines.random_agent import RandomAgent


class Mine(RandomAgent):
    """The random agent, from a file."""
'''


def test_verify_all_reaches_every_entry_and_names_the_refused_one(tmp_path, capsys, random_results):
    (tmp_path / "agent_file.py").write_text(FILE_AGENT)
    mine = evaluate(
        EvalConfig(agent=f"{tmp_path / 'agent_file.py'}:Mine", splits=("unseen-goals",), seeds=(1,)), progress=False
    )
    board = tmp_path / "board"
    for name, results in (("a_file_agent", mine), ("random", random_results)):
        (tmp_path / f"{name}.json").write_text(json.dumps(results))
        argv = ["leaderboard", "--dir", str(board), "add", str(tmp_path / f"{name}.json"), "--partial", "--create"]
        assert main([*argv, "--name", name]) == 0
    capsys.readouterr()
    code = main(["leaderboard", "--dir", str(board), "verify", "--all", "--episodes", "2"])
    out, err = capsys.readouterr()
    assert code == 2
    assert "verified: " in out and "random.json" in out, "the entry after the refused one is verified"
    (line,) = [line for line in err.splitlines() if line.startswith("objsearch: error: ")]
    assert "a_file_agent.json is not replayed (not verified)" in line and "--trust" in line
    assert "fails verification" not in line
    stored = json.loads((board / "submissions" / "gridworld" / "random.json").read_text())
    assert stored["verified"]["replayed"] == 2
