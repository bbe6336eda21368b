"""The checkpoint an agent or its training run chose is printed and recorded in the results
(``loaded_checkpoint``), so that a number says which weights made it."""

import json
from pathlib import Path

from own_houses import run

from objsearch.eval.config import EvalConfig
from objsearch.eval.runner import evaluate

AGENT = "tests.eval.agents_for_tests:RunsAgent"  # three training runs: checkpoints run-0, run-1, run-2
CHECKPOINTS = Path(__file__).resolve().parents[2] / "agents" / "checkpoints"


def test_each_training_runs_checkpoint_is_printed_and_recorded(capsys):
    results = evaluate(EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1,), episodes=2), progress=False)
    err = capsys.readouterr().err
    for seed in (0, 1, 2):
        assert f"{AGENT} on gridworld: checkpoint run-{seed} (training run {seed}, {seed + 1} of 3)" in err, err
    assert [r["loaded_checkpoint"] for r in results["training_runs"]] == ["run-0", "run-1", "run-2"]
    assert "loaded_checkpoint" not in results and results["config"]["checkpoint"] is None


def test_one_run_records_its_checkpoint_and_a_given_one_is_not_announced(capsys):
    one = evaluate(EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1,), episodes=2, training_run=1))
    assert one["loaded_checkpoint"] == "run-1"
    assert f"{AGENT} on gridworld: checkpoint run-1\n" in capsys.readouterr().err
    given = evaluate(EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1,), episodes=2, checkpoint="run-2"))
    assert given["loaded_checkpoint"] == "run-2" and "checkpoint run-2" not in capsys.readouterr().err
    assert "loaded_checkpoint" not in evaluate(EvalConfig(agent="random", seeds=(1,), episodes=1), progress=False)


def test_a_learned_house_agent_on_your_suite_names_the_checkpoint_it_chose(made, cache_dir, tmp_path):
    out = run(
        "objsearch-eval", "--agent", "hrl_grg_explorer", "--suite", "my-suite.json", "--seeds", "1",
        "--episodes", "2", "--max-steps", "5", "--cache-dir", cache_dir, "--out", str(tmp_path / "r.json"),
        "--quiet", cwd=made,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    chosen = CHECKPOINTS / "house-gen" / "hrl_grg_explorer" / "policy.pt"
    assert f"hrl_grg_explorer on my-suite.json: checkpoint {chosen}" in out.stderr, out.stderr
    results = json.loads((tmp_path / "r.json").read_text())
    assert results["loaded_checkpoint"] == str(chosen) and results["config"]["checkpoint"] is None
