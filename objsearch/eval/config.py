"""What determines an evaluation's results: ``EvalConfig`` (written into every results file
and every partial-results file) and the unit an evaluation is made of."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

PAPER_SEEDS = (1, 5, 13, 45, 99)
Unit = tuple[str, int, int]  # (split, seed, episode_id): one episode played with one seed


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

    def to_json(self) -> dict:
        """The fields as a JSON-ready dict (tuples as lists; ``training_run`` and ``episodes``
        only when set)."""
        out = asdict(self)
        out["splits"], out["seeds"] = list(self.splits), list(self.seeds)
        for key in ("training_run", "episodes"):
            if out[key] is None:
                del out[key]
        return out
