"""Intervals over houses: a cluster bootstrap of per-episode records.

A generated benchmark samples houses, then episodes in them, so an interval that says how
much a figure would move on other houses must resample houses (the unit of sampling is the
house): each bootstrap sample draws the houses with replacement,
and every episode and seed of a drawn house moves with it. The episode intervals of
``objsearch.eval.metrics`` resample tasks instead; they say how much a figure would move on
other episodes of the same houses, and are narrower wherever episodes of one house succeed
or fail together.

The value of a resample is the measure of the pooled records of the drawn houses (a house
drawn twice counts twice): SR is the successes of the drawn houses over their episodes, not
a mean of house means, so a house with more episodes weighs more, as it does in the point
estimate. ``measure`` must therefore be a mean over records (``success_rate``, ``spl``):
each house's value is weighted by its number of records.

A record's house is ``record["task"]["house"]``. Records without one (the grid world's hold
a ``map``; hand-made ones may hold nothing) have no house interval: every function here
raises ``ValueError`` for them, and a caller that may meet them checks ``has_houses`` first
and shows the episode interval alone (the leaderboard's tables print ``n/a``).

Records of several training runs (``training_run``) are resampled over runs too, as
``metrics.bootstrap_stats`` does: each sample draws the runs with replacement, then the
houses. Sets with the same runs share the draw of runs, so a paired difference pairs the
runs as well as the houses. A fixed seed (``metrics.BOOTSTRAP_SEED``) and
``metrics.BOOTSTRAP_SAMPLES`` samples, so every interval is reproducible.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Callable, Sequence

import numpy as np

from objsearch.eval.metrics import BOOTSTRAP_SAMPLES, BOOTSTRAP_SEED, _interval

Measure = Callable[[Sequence[dict]], float]


def house_of(record: dict) -> str:
    """The house a record was played in.

    Args:
        record: One episode record.

    Returns:
        ``record["task"]["house"]``.

    Raises:
        ValueError: The record names no house (a grid-world record, or a hand-made one).
    """
    house = (record.get("task") or {}).get("house")
    if house is None:
        raise ValueError(
            f"episode {record.get('episode_id')!r} of split {record.get('split')!r} names no house "
            "(task.house): a house interval needs house records; use the episode interval"
        )
    return str(house)


def has_houses(records: Sequence[dict]) -> bool:
    """Whether every record names its house (so that the house intervals apply).

    Args:
        records: Episode records.

    Returns:
        True when ``records`` is not empty and each has ``task.house``.
    """
    return bool(records) and all((r.get("task") or {}).get("house") is not None for r in records)


def houses(records: Sequence[dict]) -> list[str]:
    """The houses of ``records``, sorted.

    Args:
        records: Episode records, each naming its house.

    Returns:
        The distinct ``task.house`` values, sorted.

    Raises:
        ValueError: A record names no house.
    """
    return sorted({house_of(r) for r in records})


def house_stats(sets: Sequence[Sequence[dict]], measure: Measure, seed: int = BOOTSTRAP_SEED) -> np.ndarray:
    """``BOOTSTRAP_SAMPLES`` values of ``measure`` on each set of records, houses resampled.

    Every set is evaluated on the same draws of houses (and of runs, for sets with the same
    training runs), so differences between the rows are paired by house.

    Args:
        sets: Sets of records over the same houses (e.g. two agents on one suite, or one agent
            on two placements of the same houses).
        measure: A mean over records (``metrics.success_rate``, ``metrics.spl``).
        seed: The resampling seed.

    Returns:
        An array of shape ``(len(sets), BOOTSTRAP_SAMPLES)``: row i holds the measure of the
        pooled records of set i in each resample's houses.

    Raises:
        ValueError: No sets, an empty set, a record without a house, or sets over different houses.
    """
    if not sets or not all(sets):
        raise ValueError("a house bootstrap needs at least one non-empty set of records")
    names = houses(sets[0])
    for records in sets[1:]:
        if houses(records) != names:
            raise ValueError("a paired house bootstrap needs sets of records over the same houses")
    rng = np.random.default_rng(seed)
    picks = rng.integers(len(names), size=(BOOTSTRAP_SAMPLES, len(names)))
    run_draws: dict[tuple, np.ndarray] = {}
    out = np.empty((len(sets), BOOTSTRAP_SAMPLES))
    for i, records in enumerate(sets):
        runs, sums, weights = _per_run_and_house(records, names, measure)
        if len(runs) == 1:
            out[i] = sums[0][picks].sum(axis=1) / weights[0][picks].sum(axis=1)
            continue
        if runs not in run_draws:
            run_draws[runs] = rng.integers(len(runs), size=(BOOTSTRAP_SAMPLES, len(runs)))
        drawn = run_draws[runs][:, :, None]
        out[i] = sums[drawn, picks[:, None, :]].sum(axis=(1, 2)) / weights[drawn, picks[:, None, :]].sum(axis=(1, 2))
    return out


def _per_run_and_house(records: Sequence[dict], names: list[str], measure: Measure):
    """(runs, sums, weights): for each training run and house (in ``names``' order), the
    measure times the number of records (the sum of the per-episode values for a mean), and
    that number."""
    groups: dict = defaultdict(list)
    for r in records:
        groups[(r.get("training_run"), house_of(r))].append(r)
    runs = tuple(sorted({run for run, _ in groups}, key=str))
    sums = np.zeros((len(runs), len(names)))
    weights = np.zeros((len(runs), len(names)))
    for (run, house), rs in groups.items():
        i, j = runs.index(run), names.index(house)
        sums[i, j], weights[i, j] = measure(rs) * len(rs), len(rs)
    return runs, sums, weights


def house_ci(records: Sequence[dict], measure: Measure) -> list[float]:
    """95% percentile interval of ``measure(records)``, houses resampled.

    Args:
        records: Episode records, each naming its house.
        measure: A mean over records (``metrics.success_rate``, ``metrics.spl``).

    Returns:
        ``[low, high]``.

    Raises:
        ValueError: No records, or a record without a house.
    """
    return _interval(house_stats([records], measure)[0])


def house_contrast_ci(sets: Sequence[Sequence[dict]], signs: Sequence[float], measure: Measure) -> list[float]:
    """95% percentile interval of ``sum(sign * measure(set))``, houses resampled together.

    The contrast of several sets over the same houses, e.g. what an agent owes to where things
    are: (agent - frontier) on one placement minus the same on another, signs ``(1, -1, -1, 1)``.

    Args:
        sets: Sets of records over the same houses.
        signs: One weight a set.
        measure: A mean over records.

    Returns:
        ``[low, high]``.

    Raises:
        ValueError: As ``house_stats``, or not one sign a set.
    """
    if len(signs) != len(sets):
        raise ValueError(f"house_contrast_ci needs one sign a set ({len(sets)} sets, {len(signs)} signs)")
    return _interval(np.asarray(signs, dtype=float) @ house_stats(sets, measure))


def house_paired_difference_ci(a: Sequence[dict], b: Sequence[dict], measure: Measure) -> list[float]:
    """95% percentile interval of ``measure(a) - measure(b)``, the same houses drawn for both.

    For two agents on the same episodes, or one agent on two suites of the same houses (the
    episodes may differ): per resample, each set's records in the drawn houses are pooled, so
    what a house does to both cancels. A constant difference in every house gives a
    zero-width interval.

    Args:
        a: Records over some houses.
        b: Records over the same houses.
        measure: A mean over records.

    Returns:
        ``[low, high]``.

    Raises:
        ValueError: The two sets are over different houses, or a record names no house.
    """
    return house_contrast_ci([a, b], (1.0, -1.0), measure)


def house_difference_ci(a: Sequence[dict], b: Sequence[dict], measure: Measure) -> list[float]:
    """95% percentile interval of ``measure(a) - measure(b)``: paired by house where the two
    sets are over the same houses (``house_paired_difference_ci``), else the houses of each
    resampled independently (two sets of other houses: nothing to pair).

    Args:
        a: Records, each naming its house.
        b: Records, each naming its house.
        measure: A mean over records.

    Returns:
        ``[low, high]``.

    Raises:
        ValueError: A set is empty or a record names no house.
    """
    if houses(a) == houses(b):
        return house_paired_difference_ci(a, b, measure)
    return _interval(house_stats([a], measure)[0] - house_stats([b], measure, seed=BOOTSTRAP_SEED + 1)[0])
