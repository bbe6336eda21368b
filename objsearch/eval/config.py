"""What determines an evaluation's results: ``EvalConfig`` (written into every results file
and every partial-results file) and the unit an evaluation is made of."""

from __future__ import annotations

import numbers
from dataclasses import asdict, dataclass, field
from typing import Iterable

PAPER_SEEDS = (1, 5, 13, 45, 99)
Unit = tuple[str, int, int]  # (split, seed, episode_id): one episode played with one seed


def check_seeds(seeds: Iterable[int]) -> tuple[int, ...]:
    """``seeds`` as a tuple of distinct integers >= 0 (Python or numpy integers), else
    ``UserError``: ``[1.7, "5"]`` is not silently seeds 1 and 5, as ``--seeds`` refuses it."""
    from objsearch.errors import UserError

    if isinstance(seeds, (str, bytes)) or not isinstance(seeds, Iterable):
        raise UserError(f"seeds={seeds!r}: give a list of integers >= 0, e.g. seeds=[1, 5]")
    out = tuple(seeds)
    bad = [s for s in out if isinstance(s, bool) or not isinstance(s, numbers.Integral) or s < 0]
    if bad or not out:
        raise UserError(
            f"seeds={list(out)!r}: {bad[0]!r} is not an integer >= 0" if bad else "seeds=[]: give one seed or more"
        )
    if len(set(out)) != len(out):
        raise UserError(f"seeds={list(out)!r}: a seed is given twice (each episode would count twice)")
    return tuple(int(s) for s in out)


@dataclass(frozen=True)
class EvalConfig:
    """Everything that determines an evaluation's results.

    Attributes:
        agent: registered agent name or ``package.module:Class``.
        suite: suite name.
        splits: splits to run (empty: all of the suite's).
        seeds: evaluation seeds; every episode is run once per seed.
        checkpoint: path passed to the agent's ``load``, if any.
        suite_config: arguments of the suite (e.g. ``maps``, ``tasks``, ``max_steps``).
        step_time_limit: seconds an agent may take for one ``act`` (or ``reset``); past it
            the episode fails. None: no limit.
        weights_sha256: the digest of the files the agent loaded (its ``weights_sha256``,
            ``objsearch.digests.of_files``), set by ``evaluate``; None for an agent without
            or for several training runs (each run's is in the results' ``training_runs``).
        training_run: the training seed of the one shipped training run to evaluate
            (``--training-run``; ``objsearch.eval.runs``); None: every run.
        episodes: play only the first this many episodes of each split (``--episodes``, a
            quick look: the results are marked partial and the leaderboard refuses them);
            None: every episode.
        checkpoints: the folder ``$OBJSEARCH_CHECKPOINTS`` named (absolute) when the agent chose
            its own checkpoint under it (set by ``plan.resolve``), so that a replay loads the
            same weights; None: the shipped ones.
    """

    agent: str
    suite: str = "gridworld"
    splits: tuple[str, ...] = ()
    seeds: tuple[int, ...] = PAPER_SEEDS
    checkpoint: str | None = None
    suite_config: dict = field(default_factory=dict)
    step_time_limit: float | None = 10.0
    weights_sha256: str | None = None
    training_run: int | None = None
    episodes: int | None = None
    checkpoints: str | None = None

    def to_json(self) -> dict:
        """The fields as a JSON-ready dict (tuples as lists; ``training_run``, ``episodes`` and
        ``checkpoints`` only when set)."""
        out = asdict(self)
        out["splits"], out["seeds"] = list(self.splits), list(self.seeds)
        for key in ("training_run", "episodes", "checkpoints"):
            if out[key] is None:
                del out[key]
        return out
