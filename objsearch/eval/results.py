"""The results JSON (a contract read by other tools and the leaderboard) and its table.

Schema (``schema_version`` 1)::

    {
      "schema_version": 1,
      "agent": "random", "suite": "gridworld", "episode_set_version": "gridworld-v1",
      "protocol": "paper",
      "objsearch_version": "0.1.0", "git_commit": "<sha or null>",
      "seeds": [1, 5, 13, 45, 99],
      "config": {agent, suite, splits, seeds, checkpoint, suite_config},
      "splits": {"seen-goals": {"sr", "spl", "as", "ms", "episodes", "sr_ci", "spl_ci",
                                "sr_std", "spl_std", "per_seed", "per_goal"}, ...},
      "loaded_checkpoint": "<the checkpoint the agent loaded, if known>",
      "training_runs": [{"seed", "weights_sha256", "env_steps", "wall_s", "splits",
                         "loaded_checkpoint" (several runs)}, ...],
      "episodes": [{"split", "seed", "episode_id", "goal", "success", "steps",
                    "min_steps", "spl", "task"}, ...]
    }

``training_runs`` is there for agents that list their training runs
(``objsearch.eval.runs``). With several, every record has ``training_run`` (its run's
training seed), the split summaries are across runs (``per_run``, ``sr_std_runs``,
``spl_std_runs``; CIs from a bootstrap over runs and episodes) and the config names no
weights.

A failed episode's record also has ``error`` (the message) and, if the agent's own code
raised it, ``traceback`` (its last frames).

``partial`` (true) marks the results of ``--episodes N`` (``config.episodes``: the first N
episodes of each split only), which the leaderboard refuses.

``protocol`` is the suite's (``paper`` or ``objectnav``: whether success needs STOP); results
written before it existed are ``paper``.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

from objsearch.eval.metrics import episode_spl, summarize

SCHEMA_VERSION = 1


def git_commit() -> str | None:
    """The commit of the objsearch checkout, if it is one (None for an installed wheel)."""
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=Path(__file__).resolve().parent,
            capture_output=True,
            text=True,
            timeout=5,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() if out.returncode == 0 else None


def build_results(config, suite, records: list[dict], runs: list = (), loaded: list = ()) -> dict:
    """The results dict of a run: agent, suite, versions, git commit, seeds, config, per-split
    summaries, records; with ``runs`` ((``TrainingRun``, its ``EvalConfig``) pairs, the agent's
    training runs that were played), ``training_runs``: each run's seed, weights, cost and
    per-split summaries. ``loaded``: the checkpoint each play loaded (None: none known), in
    the order of ``runs`` when there are several (each run's ``loaded_checkpoint``), else one
    (the results' ``loaded_checkpoint``).

    Adds each record's ``spl`` (rounded to 4 places) in place.
    """
    from objsearch.eval.runs import run_entry
    from objsearch.version import __version__

    for r in records:
        r["spl"] = round(episode_spl(r["success"], r["min_steps"], r["steps"]), 4)
    results = {
        "schema_version": SCHEMA_VERSION,
        "agent": config.agent,
        "suite": suite.name,
        "episode_set_version": suite.episode_set_version,
        "protocol": suite.protocol,
        "objsearch_version": __version__,
        "git_commit": git_commit(),
        "seeds": list(config.seeds),
        "config": config.to_json(),
        "splits": {split: summarize([r for r in records if r["split"] == split]) for split in config.splits},
    }
    tagged = len(runs) > 1
    if loaded and not tagged and loaded[0] is not None:
        results["loaded_checkpoint"] = str(loaded[0])
    if config.episodes is not None:  # a quick look at the first episodes: never a result for the board
        results["partial"] = True
    if runs:
        results["training_runs"] = [
            run_entry(
                run,
                played.weights_sha256,
                {
                    split: summarize(
                        [r for r in records if r["split"] == split and (not tagged or r["training_run"] == run.seed)]
                    )
                    for split in config.splits
                },
                loaded[i] if tagged and i < len(loaded) else None,
            )
            for i, (run, played) in enumerate(runs)
        ]
    results["episodes"] = records
    return results


# The last line of every results table: what its columns and rows mean.
TABLE_LEGEND = (
    "SR: success rate; SPL: success weighted by path length; AS / MS: mean steps / mean shortest-path steps "
    "of the successful episodes only (an agent that succeeds only from nearby starts has a low MS); "
    "95% CI: bootstrap over tasks; std/seeds: std over evaluation seeds"
)


def _fmt(value, spec=".2f") -> str:
    return "-" if value is None else format(value, spec)


def format_table(results: dict) -> str:
    """The results as a text table laid out like the paper's Table 1: one column group per
    split with SR, AS / MS and SPL, then rows with the 95% intervals and the spread (std)
    over seeds (``n/a`` for one seed); a footer (suite, seeds, episodes) and the ``TABLE_LEGEND`` last."""
    splits = results["splits"].values()
    sr_w, as_w, spl_w = 6, 16, 11

    def row(label: str, cells) -> str:
        return f"{label:<14}" + "".join(f"| {c}" for c in cells)

    def interval(ci) -> str:
        return f"{_fmt(ci[0])}-{_fmt(ci[1])}"

    def spread(std) -> str:  # a spread over one seed is not 0: there is none
        return "n/a" if len(results["seeds"]) < 2 else _fmt(std)

    group = sr_w + as_w + spl_w
    lines = [
        row("", (name.replace("-", " ").title().ljust(group) for name in results["splits"])),
        row("Method", (f"{'SR':<{sr_w}}{'AS / MS':<{as_w}}{'SPL':<{spl_w}}" for _ in splits)),
        row(
            results["agent"].rsplit(":", 1)[-1][:14],  # a module:Class agent shows as its class
            (
                f"{_fmt(s['sr']):<{sr_w}}{_fmt(s['as']) + ' / ' + _fmt(s['ms']):<{as_w}}{_fmt(s['spl']):<{spl_w}}"
                for s in splits
            ),
        ),
        row("  95% CI", (f"{interval(s['sr_ci']):<{sr_w + as_w}}{interval(s['spl_ci']):<{spl_w}}" for s in splits)),
        row(
            "  std/seeds",
            (f"{spread(s['sr_std']):<{sr_w + as_w}}{spread(s['spl_std']):<{spl_w}}" for s in splits),
        ),
    ]
    runs = results.get("training_runs", [])
    if len(runs) > 1:
        lines.append(
            row(
                "  std/runs",
                (f"{_fmt(s['sr_std_runs']):<{sr_w + as_w}}{_fmt(s['spl_std_runs']):<{spl_w}}" for s in splits),
            )
        )
    rule = "-" * max(len(line) for line in lines)
    episodes = ", ".join(f"{name} {s['episodes']}" for name, s in results["splits"].items())
    footer = (
        f"suite {results['suite']} ({results['episode_set_version']}), "
        f"seeds {','.join(map(str, results['seeds']))}; episodes: {episodes}"
    )
    if results.get("protocol", "paper") != "paper":
        footer += f"; protocol {results['protocol']}"
    if len(runs) > 1:
        footer += (
            f"; {len(runs)} training runs (training seeds {','.join(str(r['seed']) for r in runs)}): "
            "the mean over runs, CI over runs and episodes"
        )
    elif runs or results["config"].get("training_run") is not None:
        footer += "; one training run"
    if results["config"].get("episodes") is not None:
        footer += (
            f"; partial: the first {results['config']['episodes']} episodes of each split only (--episodes), "
            "not a result the leaderboard takes"
        )
    perception = results["config"].get("suite_config", {}).get("perception_key")
    if perception:
        footer += f"; predicted observations (perception network {perception})"
    legend = TABLE_LEGEND + ("; std/runs: std over training runs" if len(runs) > 1 else "")
    return "\n".join([rule, *lines[:2], rule, *lines[2:], rule, footer, legend])
