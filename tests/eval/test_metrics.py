import math

import pytest

from objsearch.eval.metrics import average_steps, bootstrap_ci, episode_spl, spl, success_rate, summarize


def rec(success, steps, min_steps, seed=1, episode_id=0, goal="g0"):
    return {
        "success": success,
        "steps": steps,
        "min_steps": min_steps,
        "seed": seed,
        "episode_id": episode_id,
        "goal": goal,
    }


def test_episode_spl_hand_computed():
    assert episode_spl(True, 10, 10) == 1.0
    assert episode_spl(True, 10, 40) == 0.25
    assert episode_spl(False, 10, 10) == 0.0
    assert episode_spl(True, 10, 5) == 1.0  # l / max(l, p): never above 1
    assert episode_spl(True, 0, 3) == 1.0  # zero minimal steps counts as a perfect path


def test_split_measures_hand_computed():
    records = [rec(True, 20, 10), rec(False, 100, 5), rec(True, 8, 8), rec(False, 100, 12)]
    assert success_rate(records) == 0.5
    assert spl(records) == pytest.approx((0.5 + 0 + 1.0 + 0) / 4)
    assert average_steps(records) == (14.0, 9.0)  # over successes only


def test_no_success_gives_no_average_steps():
    records = [rec(False, 100, 5), rec(False, 100, 7)]
    assert average_steps(records) == (None, None)
    summary = summarize(records)
    assert summary["sr"] == 0.0 and summary["spl"] == 0.0
    assert summary["as"] is None and summary["ms"] is None


def test_summary_per_goal_and_per_seed():
    records = [
        rec(True, 4, 4, seed=1, episode_id=0, goal="g2"),
        rec(False, 100, 6, seed=1, episode_id=1, goal="g5"),
        rec(True, 8, 4, seed=5, episode_id=0, goal="g2"),
        rec(True, 6, 6, seed=5, episode_id=1, goal="g5"),
    ]
    s = summarize(records)
    assert s["episodes"] == 4 and s["sr"] == 0.75
    assert s["per_goal"]["g2"] == {"sr": 1.0, "spl": 0.75, "as": 6.0, "ms": 4.0, "episodes": 2}
    assert s["per_goal"]["g5"]["sr"] == 0.5
    assert s["per_seed"] == {"1": {"sr": 0.5, "spl": 0.5}, "5": {"sr": 1.0, "spl": 0.75}}
    assert s["sr_std"] == 0.25  # population std of 0.5 and 1.0
    assert s["spl_std"] == 0.125


def test_bootstrap_interval_brackets_the_mean_and_is_reproducible():
    records = [rec(i % 3 == 0, 10, 5, episode_id=i) for i in range(60)]
    lo, hi = bootstrap_ci(records, success_rate)
    assert lo < success_rate(records) < hi
    assert hi - lo < 0.4
    assert bootstrap_ci(records, success_rate) == [lo, hi]
    constant = [rec(True, 5, 5, episode_id=i) for i in range(10)]
    assert bootstrap_ci(constant, success_rate) == [1.0, 1.0]


def test_bootstrap_resamples_tasks_not_seeds():
    # one task always succeeds, one always fails, under 5 seeds each: the per-task
    # interval must be as wide as two tasks allow (0 .. 1), not shrunk by 10 records.
    records = [rec(ep == 0, 5, 5, seed=s, episode_id=ep) for s in range(5) for ep in range(2)]
    lo, hi = bootstrap_ci(records, success_rate)
    assert lo == 0.0 and hi == 1.0


def test_summarize_rejects_empty():
    with pytest.raises(ValueError):
        summarize([])
    assert math.isnan(success_rate([]))


def test_paired_difference_interval_cancels_what_the_pair_shares():
    """Two agents on the same 40 tasks: B fails 10 tasks A solves, and both solve or fail the
    other 30 together. The paired interval varies only with the 10 that differ (it stays above
    zero); the unpaired one, which resamples the two sets independently, is wider."""
    from objsearch.eval.metrics import difference_ci, paired_difference_ci

    solved = [i % 2 == 0 for i in range(40)]  # the tasks both solve (half of them)
    a = [{"split": "test", "episode_id": i, "seed": 1, "success": s or i < 20} for i, s in enumerate(solved)]
    b = [{"split": "test", "episode_id": i, "seed": 1, "success": s} for i, s in enumerate(solved)]
    lo, hi = paired_difference_ci(a, b, success_rate)
    assert 0.1 < lo < 0.25 < hi < 0.45
    assert paired_difference_ci(a, a, success_rate) == [0.0, 0.0]
    ulo, uhi = difference_ci(a, b, success_rate)
    assert uhi - ulo > hi - lo
    with pytest.raises(ValueError, match="same tasks"):
        paired_difference_ci(a, b[:-1], success_rate)
