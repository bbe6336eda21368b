"""Submissions of several training runs: checked run by run and replayed with each run's weights."""

import copy

import pytest

from objsearch.eval.config import EvalConfig
from objsearch.eval.runner import evaluate
from objsearch.leaderboard.validate import check_submission, verify_submission

AGENT = "tests.eval.agents_for_tests:RunsAgent"  # three runs of unequal skill (seeds 0, 1, 2)


@pytest.fixture(scope="module")
def runs_results():
    results = evaluate(EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1,)), progress=False)
    return dict(results, partial=True)


def test_a_multi_run_submission_is_valid_and_replays(runs_results):
    assert len(runs_results["training_runs"]) == 3
    assert check_submission(runs_results) == []
    assert verify_submission(runs_results, k=12, trust=True) == []  # a test module: not a registered agent


def test_each_runs_summary_and_records_are_checked(runs_results):
    bad = copy.deepcopy(runs_results)
    bad["training_runs"][2]["splits"]["unseen-goals"]["sr"] = 0.99
    assert check_submission(bad) == [
        "training run 2, split unseen-goals: summary (sr) differs from the one recomputed from its episodes"
    ]
    bad = copy.deepcopy(runs_results)
    del bad["episodes"][-1]["training_run"]
    assert "the records' training runs" in check_submission(bad)[0]
    bad = copy.deepcopy(runs_results)
    bad["episodes"] = [r for r in bad["episodes"] if r["training_run"] != 1 or r["episode_id"] % 2]
    assert check_submission(bad)[0].startswith(
        "50 missing episode(s), e.g. unseen-goals/seed 1/episode 0 of training run 1"
    )
    bad["episodes"] = [r for r in bad["episodes"] if r["training_run"] != 1]  # a whole run left out
    assert "the records' training runs [0, 2] are not those of training_runs ([0, 1, 2])" in check_submission(bad)[0]
    bad = copy.deepcopy(runs_results)
    bad["training_runs"][1]["seed"] = 0
    assert check_submission(bad) == ["training_runs names a training seed twice ([0, 0, 2])"]


def test_a_run_with_other_weights_is_refused_on_replay(runs_results):
    bad = copy.deepcopy(runs_results)
    bad["training_runs"][1]["weights_sha256"] = "0" * 64
    (problem,) = verify_submission(bad, trust=True)
    assert "the submission used weights 000000000000" in problem and "training run 1" in problem


def test_a_result_of_another_protocol_is_refused(runs_results):
    """Each suite has one protocol, so a ranking never mixes two: a result must carry its suite's."""
    assert check_submission(dict(runs_results, protocol="objectnav")) == [
        "protocol 'objectnav' is not the suite's 'paper'"
    ]
    (problem,) = check_submission(dict(runs_results, protocol="<b>"))
    assert problem.startswith("results field 'protocol' is '<b>', not one of the protocols paper, objectnav")
