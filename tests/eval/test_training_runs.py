"""Learned agents with several training runs: every run is evaluated on the same episodes
and reported across runs (``objsearch.eval.runs``); ``--training-run`` evaluates one."""

import json

import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.eval.config import EvalConfig
from objsearch.eval.metrics import bootstrap_ci, success_rate
from objsearch.eval.runner import evaluate
from tests.eval.agents_for_tests import weights_of

AGENT = "tests.eval.agents_for_tests:RunsAgent"
CONFIG = EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1, 5))


@pytest.fixture(scope="module")
def every_run():
    return evaluate(CONFIG, progress=False)


def test_every_training_run_is_evaluated_on_the_same_episodes(every_run):
    runs = every_run["training_runs"]
    assert [r["seed"] for r in runs] == [0, 1, 2]
    assert [r["weights_sha256"] for r in runs] == [weights_of(f"run-{seed}") for seed in (0, 1, 2)]
    assert [(r["env_steps"], r["wall_s"]) for r in runs] == [(1000, 1.5), (2000, 1.5), (3000, 1.5)]
    assert every_run["config"]["weights_sha256"] is None  # each run names its own
    units = {}
    for r in every_run["episodes"]:
        units.setdefault(r["training_run"], set()).add((r["split"], r["seed"], r["episode_id"]))
    assert units[0] == units[1] == units[2] and len(units[0]) == 200
    # the runs differ as their skill does, and the summary is their mean
    srs = [r["splits"]["unseen-goals"]["sr"] for r in runs]
    assert srs[0] > srs[1] > srs[2]
    split = every_run["splits"]["unseen-goals"]
    assert split["sr"] == pytest.approx(np.mean(srs), abs=1e-4)
    assert split["per_run"] == {
        str(r["seed"]): {k: r["splits"]["unseen-goals"][k] for k in ("sr", "spl")} for r in runs
    }
    assert split["sr_std_runs"] == pytest.approx(np.std(srs), abs=1e-4)


def test_the_interval_across_runs_holds_the_spread_of_the_runs(every_run):
    """One run's interval covers its episodes; the interval across runs also covers which
    seed was drawn, so it is wider than any one run's and lies between the runs' means."""
    split = every_run["splits"]["unseen-goals"]
    width = split["sr_ci"][1] - split["sr_ci"][0]
    for run in every_run["training_runs"]:
        one = run["splits"]["unseen-goals"]["sr_ci"]
        assert width > one[1] - one[0]
    srs = [r["splits"]["unseen-goals"]["sr"] for r in every_run["training_runs"]]
    assert min(srs) < split["sr_ci"][0] < split["sr"] < split["sr_ci"][1] < max(srs)


def test_one_training_run_gives_that_runs_records(every_run):
    one = evaluate(EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1, 5), training_run=1), progress=False)
    assert one["config"]["training_run"] == 1 and one["config"]["weights_sha256"] == weights_of("run-1")
    assert [r["seed"] for r in one["training_runs"]] == [1]
    strip = lambda r: {k: v for k, v in r.items() if k != "training_run"}
    assert one["episodes"] == [strip(r) for r in every_run["episodes"] if r["training_run"] == 1]
    assert one["splits"] == {"unseen-goals": every_run["training_runs"][1]["splits"]["unseen-goals"]}


def test_training_run_errors_name_the_fix():
    with pytest.raises(UserError, match=r"no training run with that seed .*training seeds: 0, 1, 2"):
        evaluate(EvalConfig(agent=AGENT, seeds=(1,), training_run=7), progress=False)
    with pytest.raises(UserError, match="with --checkpoint there is only that one"):
        evaluate(EvalConfig(agent=AGENT, seeds=(1,), checkpoint="run-1", training_run=1), progress=False)
    with pytest.raises(UserError, match=r"agent 'random' has no training run .*none"):
        evaluate(EvalConfig(agent="random", seeds=(1,), training_run=0), progress=False)


def test_interrupted_multi_run_evaluation_resumes(tmp_path, every_run):
    """Each run keeps its own partial-results file; a rerun plays only what is missing."""
    out = tmp_path / "r.json"
    first = evaluate(CONFIG, progress=False, out=out)
    assert not list(tmp_path.glob("*.partial.jsonl"))
    out.unlink()
    # what an interruption during the last run leaves: its first 50 records (one marked, to see it is kept)
    partial = tmp_path / "r.json.run2.partial.jsonl"
    header = {"partial_results_of": {**first["config"], "training_run": 2, "weights_sha256": weights_of("run-2")}}
    kept = [{k: v for k, v in r.items() if k not in ("training_run", "spl")} for r in first["episodes"]]
    kept = [r for r, full in zip(kept, first["episodes"]) if full["training_run"] == 2][:50]
    kept[0]["task"] = "kept from the partial file"
    partial.write_text("\n".join(json.dumps(x) for x in [header, *kept]) + "\n")
    again = evaluate(CONFIG, progress=False, out=out)
    resumed = [r for r in again["episodes"] if r.get("task") == "kept from the partial file"]
    assert len(resumed) == 1 and resumed[0]["training_run"] == 2
    assert [r["success"] for r in again["episodes"]] == [r["success"] for r in every_run["episodes"]]
    assert not partial.exists()


def test_bootstrap_over_one_run_is_the_bootstrap_over_episodes():
    """Tagging the records of a single run changes nothing: stored results stay valid."""
    rng = np.random.default_rng(3)
    records = [{"episode_id": i % 40, "success": bool(rng.random() < 0.6)} for i in range(200)]
    tagged = [{**r, "training_run": 4} for r in records]
    assert bootstrap_ci(records, success_rate) == bootstrap_ci(tagged, success_rate)
