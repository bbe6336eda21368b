"""Measures over per-episode records (habitat-lab style: small functions over records).

A record is a dict with at least ``success`` (bool), ``steps`` (actions taken),
``min_steps`` (shortest-path length from the start), ``seed``, ``episode_id`` and ``goal``
(a label for the per-goal breakdown). SPL follows Anderson et al. 2018 as the paper writes
it: ``S * l / max(l, p)`` with l the minimal and p the actual steps.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Iterable, Sequence

import numpy as np

BOOTSTRAP_SAMPLES = 1000
BOOTSTRAP_SEED = 0
CONFIDENCE = 0.95


def episode_spl(success: bool, min_steps: int, steps: int) -> float:
    """Success weighted by path length for one episode. ``min_steps`` = 0 (start on the goal)
    counts as a perfect path when successful."""
    if not success:
        return 0.0
    if min_steps <= 0:
        return 1.0
    return min_steps / max(min_steps, steps)


def success_rate(records: Sequence[dict]) -> float:
    """Fraction of ``records`` that succeeded; NaN for none."""
    return float(np.mean([r["success"] for r in records])) if records else float("nan")


def spl(records: Sequence[dict]) -> float:
    """Mean ``episode_spl`` over ``records``; NaN for none."""
    return (
        float(np.mean([episode_spl(r["success"], r["min_steps"], r["steps"]) for r in records]))
        if records
        else float("nan")
    )


def average_steps(records: Sequence[dict]) -> tuple[float | None, float | None]:
    """(AS, MS): mean steps and mean minimal steps over the successful episodes (None if none)."""
    wins = [r for r in records if r["success"]]
    if not wins:
        return None, None
    return float(np.mean([r["steps"] for r in wins])), float(np.mean([r["min_steps"] for r in wins]))


def bootstrap_stats(records: Sequence[dict], measure, seed: int = BOOTSTRAP_SEED) -> np.ndarray:
    """``BOOTSTRAP_SAMPLES`` values of ``measure`` over resamples of ``records``.

    The unit resampled is the task (episode id): its records under all seeds move together,
    since seeds repeat the same tasks. Records of several training runs (``training_run``)
    are resampled over runs too: R whole runs drawn with replacement, then the tasks, as in
    a two-level (hierarchical) bootstrap. A run is one network playing every task, so its
    tasks' scores move together; rliable's stratified bootstrap (Agarwal et al., 2021)
    draws a run per task instead, which averages that away (``docs/evaluation.md``).
    A fixed resampling ``seed``, so the values are reproducible.
    """
    scores, weights = _task_scores(records, measure)
    runs, tasks = scores.shape
    rng = np.random.default_rng(seed)
    picks = rng.integers(tasks, size=(BOOTSTRAP_SAMPLES, tasks))
    if runs == 1:
        return (scores[0][picks] * weights[picks]).sum(axis=1) / weights[picks].sum(axis=1)
    drawn = rng.integers(runs, size=(BOOTSTRAP_SAMPLES, runs))
    w = weights[picks][:, None, :]
    return (scores[drawn[:, :, None], picks[:, None, :]] * w).sum(axis=(1, 2)) / (w.sum(axis=2)[:, 0] * runs)


def _task_scores(records: Sequence[dict], measure) -> tuple[np.ndarray, np.ndarray]:
    """(``measure`` of each task's records in each training run, float (runs, tasks), NaN where
    a run has none; each task's weight, its records in the first run): tasks (episode ids) in
    the order they first appear, runs in name order. SR and SPL are the mean of one value per
    record, in one pass (the leaderboard's pages take hundreds of intervals); any other measure
    is called task by task."""
    names = sorted({r.get("training_run") for r in records}, key=str)
    run_of, task_of = {run: i for i, run in enumerate(names)}, {}
    tasks = np.array([task_of.setdefault(r["episode_id"], len(task_of)) for r in records], dtype=np.int64)
    cells = np.array([run_of[r.get("training_run")] for r in records], dtype=np.int64) * len(task_of) + tasks
    shape = (len(names), len(task_of))
    sizes = np.bincount(cells, minlength=shape[0] * shape[1])
    per_record = {
        success_rate: lambda r: float(r["success"]),
        spl: lambda r: episode_spl(r["success"], r["min_steps"], r["steps"]),
    }
    if measure in per_record:
        sums = np.bincount(cells, weights=[per_record[measure](r) for r in records], minlength=sizes.size)
        with np.errstate(invalid="ignore"):
            scores = sums / sizes  # 0/0: NaN
    else:
        groups: list[list[dict]] = [[] for _ in range(sizes.size)]
        for cell, r in zip(cells.tolist(), records):
            groups[cell].append(r)
        scores = np.array([measure(g) if g else np.nan for g in groups])
    return scores.reshape(shape), sizes[: shape[1]].astype(float)


def _interval(stats: np.ndarray) -> list[float]:
    alpha = (1 - CONFIDENCE) / 2
    return [float(np.quantile(stats, alpha)), float(np.quantile(stats, 1 - alpha))]


def bootstrap_ci(records: Sequence[dict], measure) -> list[float]:
    """95% percentile bootstrap interval of ``measure`` over episodes (and training runs;
    ``bootstrap_stats``)."""
    return _interval(bootstrap_stats(records, measure))


def difference_ci(a: Sequence[dict], b: Sequence[dict], measure) -> list[float]:
    """95% percentile bootstrap interval of ``measure(a) - measure(b)`` for two independent
    sets of records (e.g. one agent on two suites), each resampled as ``bootstrap_ci`` does."""
    return _interval(bootstrap_stats(a, measure) - bootstrap_stats(b, measure, seed=BOOTSTRAP_SEED + 1))


def paired_difference_ci(a: Sequence[dict], b: Sequence[dict], measure) -> list[float]:
    """95% percentile bootstrap interval of ``measure(a) - measure(b)`` for records of the same
    tasks (one agent on two suites with the same episodes, or two agents on one suite): the
    tasks (split and episode id, with all their seeds) are resampled together, so what the
    two share cancels. Single training runs; ``ValueError`` if the tasks differ."""
    per_a, per_b = per_task(a, measure), per_task(b, measure)
    if per_a.keys() != per_b.keys():
        raise ValueError("paired_difference_ci needs records of the same tasks")
    return mean_ci([per_a[k] - per_b[k] for k in sorted(per_a)])


def per_task(records: Sequence[dict], measure) -> dict:
    """``measure`` of each task's records (all its seeds), by task: (split, episode id)."""
    tasks = defaultdict(list)
    for r in records:
        tasks[(r["split"], r["episode_id"])].append(r)
    return {key: measure(rs) for key, rs in tasks.items()}


def mean_ci(values: Sequence[float]) -> list[float]:
    """95% percentile bootstrap interval of the mean of per-task ``values`` (tasks resampled)."""
    values = np.asarray(values, dtype=float)
    picks = np.random.default_rng(BOOTSTRAP_SEED).integers(len(values), size=(BOOTSTRAP_SAMPLES, len(values)))
    return _interval(values[picks].mean(axis=1))


def _round(value):
    return None if value is None else round(float(value), 4)


def summarize(records: Iterable[dict]) -> dict:
    """Summary of one split: SR, SPL, AS, MS, CIs, spread over seeds, per-goal breakdown.

    Keys: ``sr``, ``spl``, ``as``, ``ms``, ``episodes`` (records), ``sr_ci``, ``spl_ci``,
    ``sr_std``/``spl_std`` (population std of the per-seed values), ``per_seed``
    ({seed: {sr, spl}}) and ``per_goal`` ({goal: {sr, spl, as, ms, episodes}}). Records of
    several training runs add ``per_run`` ({training seed: {sr, spl}}) and
    ``sr_std_runs``/``spl_std_runs`` (population std of the per-run values); their CIs come
    from a bootstrap over runs and episodes.
    """
    records = list(records)
    if not records:
        raise ValueError("summarize() needs at least one record")
    avg_steps, min_steps = average_steps(records)
    by_seed: dict = defaultdict(list)
    by_goal: dict = defaultdict(list)
    for r in records:
        by_seed[r["seed"]].append(r)
        by_goal[r["goal"]].append(r)
    per_seed = {str(s): {"sr": _round(success_rate(rs)), "spl": _round(spl(rs))} for s, rs in sorted(by_seed.items())}
    per_goal = {}
    for goal, rs in sorted(by_goal.items(), key=lambda kv: str(kv[0])):
        g_as, g_ms = average_steps(rs)
        per_goal[str(goal)] = {
            "sr": _round(success_rate(rs)),
            "spl": _round(spl(rs)),
            "as": _round(g_as),
            "ms": _round(g_ms),
            "episodes": len(rs),
        }
    summary = {
        "sr": _round(success_rate(records)),
        "spl": _round(spl(records)),
        "as": _round(avg_steps),
        "ms": _round(min_steps),
        "episodes": len(records),
        "sr_ci": [_round(v) for v in bootstrap_ci(records, success_rate)],
        "spl_ci": [_round(v) for v in bootstrap_ci(records, spl)],
        "sr_std": _round(np.std([success_rate(rs) for rs in by_seed.values()])),
        "spl_std": _round(np.std([spl(rs) for rs in by_seed.values()])),
        "per_seed": per_seed,
        "per_goal": per_goal,
    }
    by_run: dict = defaultdict(list)
    for r in records:
        by_run[r.get("training_run")].append(r)
    if len(by_run) > 1:
        summary["per_run"] = {
            str(run): {"sr": _round(success_rate(rs)), "spl": _round(spl(rs))} for run, rs in sorted(by_run.items())
        }
        summary["sr_std_runs"] = _round(np.std([success_rate(rs) for rs in by_run.values()]))
        summary["spl_std_runs"] = _round(np.std([spl(rs) for rs in by_run.values()]))
    return summary
