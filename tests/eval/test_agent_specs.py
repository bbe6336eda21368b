"""An agent given by module or by file, from the folder the evaluation runs in, in this
process and in worker processes."""

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

BIN = Path(sys.executable).parent
AGENT = textwrap.dedent("""
    from objsearch_agents.baselines.oracle import OracleAgent


    class MyAgent(OracleAgent):
        pass
""")
ONE_SPLIT = ["--suite", "gridworld", "--split", "unseen-goals", "--seeds", "1", "--quiet"]


@pytest.fixture
def agent_folder(tmp_path):
    (tmp_path / "mypkg").mkdir()
    (tmp_path / "mypkg" / "__init__.py").write_text("")
    (tmp_path / "mypkg" / "mymodule.py").write_text(AGENT)
    (tmp_path / "my_agent.py").write_text(AGENT)
    return tmp_path


def evaluate_cli(folder, *args):
    return subprocess.run([str(BIN / "objsearch-eval"), *args], capture_output=True, text=True, cwd=folder, timeout=300)


@pytest.mark.parametrize("spec", ["mypkg.mymodule:MyAgent", "./my_agent.py:MyAgent"])
def test_an_agent_in_the_current_folder_runs_in_worker_processes(agent_folder, spec):
    out = evaluate_cli(agent_folder, "--agent", spec, "--workers", "2", *ONE_SPLIT, "--out", "r.json")
    assert out.returncode == 0, out.stderr
    results = json.loads((agent_folder / "r.json").read_text())
    recorded = f"{(agent_folder / 'my_agent.py').resolve()}:MyAgent" if spec.endswith(".py:MyAgent") else spec
    assert results["agent"] == recorded  # a file by its absolute path, for replays from other folders
    assert results["splits"]["unseen-goals"]["sr"] == 1.0
    assert not any("error" in r for r in results["episodes"])


def test_an_agent_file_given_by_an_absolute_path_runs_from_anywhere(agent_folder, tmp_path_factory):
    elsewhere = tmp_path_factory.mktemp("elsewhere")
    out = evaluate_cli(elsewhere, "--agent", f"{agent_folder / 'my_agent.py'}:MyAgent", *ONE_SPLIT)
    assert out.returncode == 0, out.stderr
    assert "1.00" in out.stdout


@pytest.mark.parametrize(
    "spec, message",
    [
        ("./missing.py:MyAgent", "no file"),
        ("./my_agent.py:Missing", "has no attribute 'Missing'"),
        ("nopkg.mymodule:MyAgent", "no module named 'nopkg.mymodule', neither installed nor in"),
    ],
)
def test_a_missing_agent_is_one_line_and_exit_2(agent_folder, spec, message):
    out = evaluate_cli(agent_folder, "--agent", spec, *ONE_SPLIT)
    assert out.returncode == 2 and message in out.stderr, out.stderr
    assert "Traceback" not in out.stderr


def test_ray_workers_build_an_agent_of_the_folder_the_evaluation_started_in(agent_folder, monkeypatch):
    pytest.importorskip("ray")
    from objsearch.eval.runner import EvalConfig, evaluate

    monkeypatch.chdir(agent_folder)
    config = EvalConfig(agent="mypkg.mymodule:MyAgent", splits=("unseen-goals",), seeds=(1,))
    results = evaluate(config, progress=False, executor="ray", workers=2)
    assert results["splits"]["unseen-goals"]["sr"] == 1.0 and not any("error" in r for r in results["episodes"])
