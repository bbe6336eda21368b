"""What an ``objsearch reproduce`` plan costs, from measurements (``--dry-run``).

- A training run: the wall time its training log records (``log.csv``'s last ``wall_s``, and
  that of its pretraining), from the shipped run of the same seed, else of another seed of
  the same method and suite, else of the method on another suite, scaled by the budget
  planned over the budget logged. The shipped runs were trained on the project's 2-core CPU
  machine, except those whose config let them pick a GPU (``device``), which are marked.
- An evaluation: the environment steps it plays over the steps per second of one evaluation
  process measured on that machine (``EVAL_STEPS_PER_S``; docs/scaling.md). The steps: those
  of the same entry on the plan's leaderboard, or the shipped one, if it has the plan's
  splits, seeds and step limit (times the plan's training runs over its own), else at most
  every episode played to the step limit.
- A verification: the share of its entry's episodes it replays, at the evaluation's rate.
- A step that already ran: the wall time it recorded (``Plan.record``).

Observation caches that an evaluation or a training run builds first are not counted.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

from objsearch.leaderboard.reproduce_plan import Plan, Step, run_folder

# Env steps a second of one evaluation process (--batch 32, start-up included), 2026-12-05, the
# 2-core CPU machine at load 2.3-2.7: `objsearch-eval --agent A --suite rooms --split
# unseen-env-unseen-goals --seeds 1 [--training-run 0]`, `objsearch-eval --agent A --suite gridworld`.
EVAL_STEPS_PER_S = {
    "house": {"random": 15300, "oracle": 1550, "frontier": 420, "a3c": 3100, "hrl_grg": 3340, "scene_priors": 520},
    "gridworld": {"random": 136500, "dqn": 18700, "hrl_grg": 9790},
}
# seconds of add and verify beside the episodes verify replays: rooms' random entry (20,000 episodes), same day
ADD_S, VERIFY_S = 8, 5
# an agent not measured counts as the nearest measured one: a learned one as hrl_grg (the
# slowest of the methods sharing its networks), a training-free house agent as frontier
UNMEASURED = {"house": ("hrl_grg", "frontier"), "gridworld": ("hrl_grg", "random")}


def _log_end(path: Path, column: str) -> tuple[float, float] | None:
    """(``column``, ``wall_s``) of a training log's last row; None without one."""
    if not path.is_file():
        return None
    with path.open() as f:
        rows = list(csv.DictReader(f))
    if not rows or not rows[-1].get(column) or not rows[-1].get("wall_s"):
        return None
    return float(rows[-1][column]), float(rows[-1]["wall_s"])


def _measured_runs(plan: Plan, suite: str, agent: str, seed: int, variant: str = "") -> list[tuple[Path, str]]:
    """Shipped run folders of the suite's world whose logs stand for ``agent``'s run ``seed``
    (of ``variant``) on ``suite``, best first, and what each is."""
    from objsearch.eval.suites import SUITES, suite_world

    own = run_folder(plan.shipped, suite, agent, seed, variant)
    seeds = [run_folder(plan.shipped, suite, agent, 0), *sorted((plan.shipped / suite / agent).glob("seed*"))]
    world = suite_world(suite)
    elsewhere = [
        f for s in SUITES if s != suite and suite_world(s) == world for f in [plan.shipped / s / agent] if f.is_dir()
    ]
    found = [(own, "its shipped run")] + [(f, "another seed's run") for f in seeds if f != own]
    found += [(f, f"the run on {f.parent.name}") for f in elsewhere]
    return [(f, what) for f, what in found if (f / "log.csv").is_file() and (f / "config.json").is_file()]


def _pretraining(plan: Plan, folder: Path, suite: str, column: str) -> tuple[tuple[float, float], Path] | None:
    """The log end of a pretraining that stands for the one a run from ``folder``'s recipe
    runs: its own, else another run's on the same suite, else on any (the same approach phase)."""
    candidates = [folder, *sorted((plan.shipped / suite).glob("*/")), *sorted(plan.shipped.glob("*/*/"))]
    for run in candidates:
        for log in (run / "pretrain" / "log.csv", run / "pretrain_log.csv"):
            end = _log_end(log, column)
            if end and end[0]:
                return end, log.parent if log.name == "log.csv" else run
    return None


def _shown(plan: Plan, path: Path) -> Path:
    """``path`` from the checkout, where it lies in it."""
    root = plan.shipped.parent.parent
    return path.relative_to(root) if root in path.parents else path


def train_estimate(plan: Plan, step: Step) -> tuple[float | None, str]:
    """Seconds a training step takes, and where the figure comes from."""
    from objsearch.eval.suites import suite_world
    from objsearch.leaderboard.reproduce_plan import agent_config

    a = step.args
    agent, suite, seed = a["agent"], a["suite"], a["seed"]
    house = suite_world(suite) == "house"
    column, budget_key, pre_key = (
        ("env_steps", "steps", "pretrain_steps") if house else ("episodes", "episodes", "pretrain_episodes")
    )
    default = agent_config(agent, suite)
    overrides = dict(a["overrides"])
    for folder, what in _measured_runs(plan, suite, agent, seed, a.get("variant", "")):
        config = json.loads((folder / "config.json").read_text())
        main = _log_end(folder / "log.csv", column)
        if main is None or not main[0]:
            continue
        planned = a[budget_key] or getattr(default, budget_key, None) or main[0]
        seconds, note = main[1] * planned / main[0], ""
        pre = _pretraining(plan, folder, suite, column)
        # it pretrains unless it starts from a pretrained run, where the logged one pretrained or started from one
        pretrains = not overrides.get("pretrained") and (
            config.get("pretrained") or pre and pre[1].is_relative_to(folder)
        )
        pre_planned = int(overrides.get(pre_key) or getattr(default, pre_key, 0) or 0) if pretrains else 0
        if pre_planned and pre:
            seconds += pre[0][1] * pre_planned / pre[0][0]
            note = f" + pretraining as {_shown(plan, pre[1])}'s"
        if config.get("device", "cpu") != "cpu":
            note += f"; device={config['device']}: it may have trained on a GPU"
        how = f"{main[0]:,.0f} {column} in {_duration(main[1])}"
        return seconds, f"log.csv of {what} ({_shown(plan, folder)}: {how}), for {planned:,.0f}{note}"
    return None, "no shipped run of it in this world logs a time"


def _entry_steps(plan: Plan, a: dict, runs: int) -> tuple[float, float, str]:
    """The env steps and episodes the evaluation ``a`` plays, and where the figures come from."""
    from objsearch.eval.suites import make_suite

    suite = make_suite(a["suite"])
    splits = a["splits"] or list(suite.splits)
    limit = a["suite_config"].get("max_steps")
    repo = plan.shipped.parent.parent  # the checkout: its leaderboard/
    for board in dict.fromkeys((plan.leaderboard, repo / "leaderboard")):
        path = board / "submissions" / a["suite"] / f"{Path(a['results']).stem}.json"
        if not path.is_file():
            continue
        stored = json.loads(path.read_text())
        same_limit = stored["config"]["suite_config"].get("max_steps") == limit if limit else not stored.get("partial")
        if sorted(stored["config"]["splits"]) == sorted(splits) and stored["seeds"] == a["seeds"] and same_limit:
            scale = runs / max(1, len(stored.get("training_runs", [])))
            played = sum(r["steps"] for r in stored["episodes"]) * scale
            return played, len(stored["episodes"]) * scale, f"{played:,.0f} env steps (as its entry in {board.name}/)"
    episodes = sum(len(suite.episodes(split)) for split in splits) * len(a["seeds"]) * runs
    bound = episodes * (limit or getattr(suite, "max_steps", None) or 100)
    return bound, episodes, f"at most {bound:,.0f} env steps ({episodes:,} episodes to the step limit)"


def eval_estimate(plan: Plan, step: Step) -> tuple[float, float, str]:
    """Seconds an evaluation takes, the episodes it plays, and where the figures come from."""
    from objsearch.eval.suites import suite_world

    a = step.args
    world = suite_world(a["suite"])
    agent = a["agent"].removesuffix("_greedy")
    measured = EVAL_STEPS_PER_S[world]
    rated = agent if agent in measured else UNMEASURED[world][0 if step.needs else 1]
    played, episodes, source = _entry_steps(plan, a, max(1, len(step.needs)))
    as_ = "" if rated == agent else f", as {rated}"
    return played / measured[rated], episodes, f"{source} at {measured[rated]:,} steps/s ({world}{as_}; measured)"


def _duration(seconds: float) -> str:
    return (
        f"{seconds / 3600:.1f} h"
        if seconds >= 3600
        else f"{seconds / 60:.0f} min"
        if seconds >= 60
        else f"{seconds:.0f} s"
    )


def print_plan(plan: Plan) -> None:
    """Print every step of ``plan``: done (with the time it took here, if recorded) or to
    run, with its estimated time and where the estimate comes from; then the totals in hours."""
    from objsearch.leaderboard.reproduce_run import is_done
    from objsearch.leaderboard.validate import sample_size

    totals, runs, evals = {}, [0, 0], {}
    print(f"objsearch reproduce {plan.title}: checkpoints {plan.checkpoints}, leaderboard {plan.leaderboard}")
    for step in plan.steps:
        done = is_done(plan, step)
        seconds, source = (
            (ADD_S, "checks it and the stored entries (measured)") if step.kind == "add" else (None, "seconds")
        )
        if step.kind == "train":
            runs[done] += 1
            seconds, source = (None, _shown(plan, Path(step.args["out"]))) if done else train_estimate(plan, step)
        elif step.kind == "eval":
            seconds, episodes, source = eval_estimate(plan, step)
            evals[step.name] = (seconds, episodes)
        elif step.kind == "verify" and step.name in evals:
            spent, episodes = evals[step.name]
            replayed = min(episodes, step.args["episodes"] or sample_size(round(episodes)))
            seconds = VERIFY_S + spent * replayed / max(1, episodes)
            source = f"replays {replayed:,.0f} of {episodes:,.0f} episodes (their share of the evaluation, + start-up)"
        record = plan.record(step)
        if done:
            took = json.loads(record.read_text())["wall_s"] if record.is_file() else None
            shown = "done" if took is None else f"done in {_duration(took)}"
        else:
            shown = "?" if seconds is None and step.kind == "train" else "-" if seconds is None else _duration(seconds)
            totals[step.kind] = totals.get(step.kind, 0) + (seconds or 0)
        print(f"  {shown:>14}  {step.id:<48} {source}")
    total = sum(totals.values())
    parts = ", ".join(
        f"{kind} {totals[kind] / 3600:.1f} h" for kind in ("train", "eval", "add", "verify") if kind in totals
    )
    print(f"training runs: {runs[1]} done, {runs[0]} to train")
    short = "" if total >= 3600 else f" ({_duration(total)})"
    parts = f" ({parts})" if parts else ""
    print(f"estimated time to run: {total / 3600:.1f} hours{short} on one core{parts}; cache builds not counted")
    print(
        "estimates: training from the shipped runs' own log.csv (wall_s), evaluation from env steps/s measured on "
        "the project's 2-core CPU machine (docs/scaling.md); --executor ray spreads the runs over a cluster's cores"
    )
