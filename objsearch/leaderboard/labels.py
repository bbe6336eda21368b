"""The labels of a submission that the pages show: what the agent observed, its training runs
and steps, how many of its episodes were replayed, its suite settings that are not the
standard, and numbers as table cells. ``render`` (the leaderboard's pages), ``paper_tables``
and ``headline`` (the project README's table) use them."""

from __future__ import annotations

from objsearch.eval.registry import is_training_free


def observation_label(results: dict) -> str:
    """What the agent saw: ``gt`` (ground-truth segmentation and depth) or ``predicted <network key>``."""
    key = results["config"].get("suite_config", {}).get("perception_key")
    return f"predicted {key}" if key else "gt"


def training(results: dict) -> tuple[int | None, int | None]:
    """(training runs, mean training environment steps of a run) of a submission: (None, None)
    for a registered agent that declares itself training-free (``registry.is_training_free``),
    (1, None) for any other that reports no runs."""
    runs = results.get("training_runs")
    if runs:
        steps = [run["env_steps"] for run in runs]
        return len(runs), None if None in steps else round(sum(steps) / len(steps))
    return (None, None) if is_training_free(results["agent"]) else (1, None)


def runs_label(runs: int | None) -> str:
    """``3``; ``1*`` for one training run (marked: its interval covers episodes, not training); ``–`` for none."""
    return "–" if runs is None else f"{runs}*" if runs == 1 else str(runs)


def steps_label(steps: int | None) -> str:
    """``20M`` (environment steps, rounded); ``–`` when unknown."""
    return "–" if steps is None else f"{steps / 1e6:.0f}M" if steps >= 1e6 else f"{steps / 1e3:.0f}k"


def replayed_label(results: dict) -> str:
    """``90/1500``: episodes that ``objsearch leaderboard verify`` replayed identical, of the
    entry's, as recorded for its present content; ``–`` when none were."""
    from objsearch.leaderboard.replay import replayed_of

    replayed = replayed_of(results)
    return "–" if replayed is None else f"{replayed[0]}/{replayed[1]}"


def nonstandard_settings(results: dict) -> list[str]:
    """The suite settings of ``results`` that are not its suite's standard (``checks.nonstandard_settings``)."""
    from objsearch.leaderboard.checks import nonstandard_settings as differing

    return differing(results)


def number_label(value) -> str:
    """A table cell's number: two decimals; ``–`` for None."""
    return "–" if value is None else f"{value:.2f}"
