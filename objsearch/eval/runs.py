"""Learned agents trained several times: which training runs an evaluation plays.

One training run is not evidence of an ordering (Agarwal et al., NeurIPS 2021). An agent
class may list the checkpoints made for a suite by one recipe with different training
seeds (``training_runs(suite) -> list[TrainingRun]``, ``objsearch.eval.agent``). With no
``--checkpoint``, an evaluation plays every run on the same episodes, tags each record
with its run's seed (``training_run``) and reports across runs, with intervals from a
bootstrap over runs and episodes (``objsearch.eval.metrics.bootstrap_ci``);
``--training-run SEED`` plays one. An evaluation lists them once, when it is resolved
(``objsearch.eval.plan``).
"""

from __future__ import annotations

from dataclasses import replace

from objsearch.errors import UserError
from objsearch.eval.agent import TrainingRun
from objsearch.eval.config import EvalConfig
from objsearch.eval.registry import check_supports, make_agent, resolve_agent


def training_runs(config: EvalConfig, folder: str | None = None) -> list[TrainingRun]:
    """The runs ``config`` evaluates: every run the agent lists for the suite, or the one
    ``config.training_run`` names; none for an explicit checkpoint or an agent that lists none."""
    check_run_choice(config)
    if config.checkpoint is not None:
        return []
    cls = resolve_agent(config.agent, folder)
    check_supports(config.agent, cls, config.suite)  # a suite of another world has no runs to ask for
    return listed_runs(config, cls)


def check_run_choice(config: EvalConfig) -> None:
    """Refuse a config that names both a checkpoint and a training run."""
    if config.checkpoint is not None and config.training_run is not None:
        raise UserError(
            "--training-run picks one of an agent's shipped training runs; with --checkpoint there is "
            "only that one: drop one of the two"
        )


def listed_runs(config: EvalConfig, cls: type) -> list[TrainingRun]:
    """The runs of agent class ``cls`` (resolved, and checked for the suite) that ``config``
    (with no checkpoint) evaluates: every run the class lists for the suite, or the one
    ``config.training_run`` names."""
    listed = getattr(cls, "training_runs", None)
    runs = list(listed(config.suite)) if callable(listed) else []
    if config.training_run is None:
        return runs
    picked = [run for run in runs if run.seed == config.training_run]
    if not picked:
        have = ", ".join(str(run.seed) for run in runs) or "none"
        raise UserError(
            f"--training-run {config.training_run}: agent {config.agent!r} has no training run with that "
            f"seed for suite {config.suite!r} (its runs' training seeds: {have})"
        )
    return picked


def run_config(config: EvalConfig, run: TrainingRun) -> EvalConfig:
    """The configuration that plays one training run. It names the run by its seed, not its
    checkpoint's path, so that results replay on any machine that has the agent."""
    return replace(config, training_run=run.seed)


def agent_of(config: EvalConfig, folder: str | None = None):
    """The agent ``config`` plays: its checkpoint's, or its training run's (``make_agent``); for a
    caller that holds one config (``objsearch leaderboard verify``). An evaluation resolves its
    agents once, in ``objsearch.eval.plan.resolve``."""
    checkpoint = config.checkpoint
    if config.training_run is not None:
        checkpoint = training_runs(config, folder)[0].checkpoint
    return make_agent(config.agent, checkpoint, config.suite, folder)


def run_entry(run: TrainingRun, weights_sha256: str | None, splits: dict, loaded: str | None = None) -> dict:
    """A run's entry in the results' ``training_runs``: its seed, weights, cost and split
    summaries, and the checkpoint it loaded (``loaded``) if given."""
    entry = {
        "seed": run.seed,
        "weights_sha256": weights_sha256,
        "env_steps": run.env_steps,
        "wall_s": run.wall_s,
        "splits": splits,
    }
    if loaded is not None:
        entry["loaded_checkpoint"] = str(loaded)
    return entry
