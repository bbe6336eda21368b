"""The house (cluster) bootstrap of ``objsearch.eval.house_bootstrap`` on hand-made records
whose answers are known: wider than the episode interval where episodes of a house succeed
together, zero-width for a constant per-house difference, the pooled ratio (not a mean of
house means), reproducible, and refused for records without houses."""

import numpy as np
import pytest

from objsearch.eval.house_bootstrap import (
    has_houses,
    house_ci,
    house_contrast_ci,
    house_difference_ci,
    house_paired_difference_ci,
    house_stats,
)
from objsearch.eval.metrics import BOOTSTRAP_SAMPLES, bootstrap_ci, paired_difference_ci, spl, success_rate


def _records(outcomes: dict[str, list[bool]], run=None, seed: int = 1) -> list[dict]:
    """Records of ``outcomes`` (house -> success of each of its episodes), episode ids counted
    across houses in order; 10 steps of a shortest 5 (SPL 0.5 on success)."""
    records, i = [], 0
    for house, oks in outcomes.items():
        for ok in oks:
            r = {"split": "test", "seed": seed, "episode_id": i, "success": ok, "steps": 10, "min_steps": 5}
            r["task"] = {"house": house}
            if run is not None:
                r["training_run"] = run
            records.append(r)
            i += 1
    return records


def _rate(n_success: int, n: int = 20) -> list[bool]:
    return [i < n_success for i in range(n)]


def test_house_interval_is_wider_where_episodes_of_a_house_succeed_together():
    # 10 houses of 20 episodes: 5 houses solve every episode, 5 none. Over episodes the 200
    # look independent (a narrow interval around 0.5); over houses only 10 units vary.
    records = _records({f"h{h}": [h % 2 == 0] * 20 for h in range(10)})
    lo, hi = house_ci(records, success_rate)
    elo, ehi = bootstrap_ci(records, success_rate)
    assert lo < elo < 0.5 < ehi < hi
    assert hi - lo > 2 * (ehi - elo)
    # where success does not depend on the house (every house at 0.5), houses cannot move it
    mixed = _records({f"h{h}": [i % 2 == 0 for i in range(20)] for h in range(10)})
    assert house_ci(mixed, success_rate) == [0.5, 0.5]  # every house is at 0.5: nothing varies


def test_a_constant_per_house_difference_gives_a_zero_width_paired_interval():
    # frontier's SR varies from house to house; the agent solves exactly 4 more of each house's
    # 20 episodes (+0.2 everywhere): resampling houses cannot move the difference
    ref = _records({f"h{h}": _rate(2 * h) for h in range(8)})
    mine = _records({f"h{h}": _rate(2 * h + 4) for h in range(8)})
    lo, hi = house_paired_difference_ci(mine, ref, success_rate)
    assert lo == pytest.approx(0.2) and hi == pytest.approx(0.2)
    # the episode-paired interval is not zero-width (tasks differ by 0 or 1), the house one is
    elo, ehi = paired_difference_ci(mine, ref, success_rate)
    assert ehi - elo > 0.05
    # unpaired (other houses in the two sets): the houses' spread comes back
    other = _records({f"g{h}": _rate(2 * h + 4) for h in range(8)})
    ulo, uhi = house_difference_ci(other, ref, success_rate)
    assert uhi - ulo > 0.1
    # the same houses: house_difference_ci pairs them
    assert house_difference_ci(mine, ref, success_rate) == [lo, hi]


def test_the_resample_is_the_pooled_ratio_not_a_mean_of_house_means():
    # house a: 1 episode, solved; house b: 9 episodes, all failed. SR = 1/10. A resample of
    # houses (a, b) pools 10 episodes (0.1), not (1 + 0) / 2; (a, a) is 1.0 and (b, b) 0.0.
    records = _records({"a": [True], "b": [False] * 9})
    stats = house_stats([records], success_rate)[0]
    assert stats.shape == (BOOTSTRAP_SAMPLES,)
    assert set(np.round(stats, 9)) == {0.0, 0.1, 1.0}
    # SPL the same: a mean over records, pooled
    assert set(np.round(house_stats([records], spl)[0], 9)) == {0.0, 0.05, 0.5}


def test_house_intervals_are_reproducible_and_ignore_record_order():
    rng = np.random.default_rng(3)
    records = _records({f"h{h}": list(rng.random(15) < rng.random()) for h in range(12)})
    first = house_ci(records, success_rate)
    assert house_ci(records, success_rate) == first
    assert house_ci(list(reversed(records)), success_rate) == first
    assert house_ci([dict(r) for r in records], success_rate) == first


def test_several_training_runs_are_resampled_too():
    # run 0 solves everything, run 1 nothing: every house is at 0.5 pooled over runs, so a
    # bootstrap over houses alone would say [0.5, 0.5]; drawing the runs as well does not
    records = _records({f"h{h}": [True] * 5 for h in range(6)}, run=0)
    records += _records({f"h{h}": [False] * 5 for h in range(6)}, run=1)
    lo, hi = house_ci(records, success_rate)
    assert lo == 0.0 and hi == 1.0
    # the same runs in two sets are drawn together: an agent minus itself is exactly zero
    assert house_paired_difference_ci(records, records, success_rate) == [0.0, 0.0]


def test_a_contrast_of_four_sets_pairs_them_by_house():
    # (agent - frontier) on one placement minus the same on another: the agent's +0.25 in
    # every house vanishes on the moved placement, so it owes +0.25, exactly
    base_ref = _records({f"h{h}": _rate(h + 2) for h in range(6)})
    base = _records({f"h{h}": _rate(h + 7) for h in range(6)})
    moved_ref = _records({f"h{h}": _rate(2 * h) for h in range(6)})
    moved = _records({f"h{h}": _rate(2 * h) for h in range(6)})
    lo, hi = house_contrast_ci([base, base_ref, moved, moved_ref], (1, -1, -1, 1), success_rate)
    assert lo == pytest.approx(0.25) and hi == pytest.approx(0.25)
    with pytest.raises(ValueError, match="one sign a set"):
        house_contrast_ci([base, base_ref], (1,), success_rate)


def test_records_without_houses_are_refused_not_resampled_as_episodes():
    records = _records({"h0": [True, False], "h1": [True]})
    assert has_houses(records)
    bare = [{k: v for k, v in r.items() if k != "task"} for r in records]
    grid = [{**r, "task": {"map": 3, "start": [1, 1], "goal": "apple"}} for r in bare]  # a grid-world record
    for no_house in (bare, grid, records[:1] + bare[1:]):
        assert not has_houses(no_house)
        with pytest.raises(ValueError, match="names no house"):
            house_ci(no_house, success_rate)
    assert not has_houses([])
    with pytest.raises(ValueError, match="non-empty"):
        house_ci([], success_rate)
    with pytest.raises(ValueError, match="same houses"):
        house_paired_difference_ci(records, _records({"h0": [True], "h9": [False]}), success_rate)
