"""A house training run's bookkeeping: its counters, the window of finished episodes and
losses that makes each ``log.csv`` row, and the row itself. Saved in ``state.pt`` as plain
dicts (the format of every run so far), so that a run resumes exactly."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

LOG_FIELDS = (
    "env_steps",
    "episodes",
    "updates",
    "epsilon",
    "success_rate",
    "mean_steps",
    "loss_ac",
    "loss_q",
    "grg_counts",
    "wall_s",
)


@dataclass
class Counters:
    """Totals since the run began."""

    started: int = 0
    """Episodes started (each episode's index: exploration and curriculum follow it)."""
    finished: int = 0
    """Episodes finished."""
    env_steps: int = 0
    """Environment steps, summed over the parallel episodes."""
    updates: int = 0
    """Q-network updates."""
    credit: float = 0.0
    """Fractional Q-network updates owed (one per ``update_every`` transitions)."""
    wall_s: float = 0.0
    """Seconds of training, over every session of the run."""
    batched_steps: int = 0
    """Lockstep steps of all episodes (plans are refreshed every ``plan_every``)."""

    def state_dict(self) -> dict:
        return asdict(self)


@dataclass
class Window:
    """What happened since the last ``log.csv`` row: finished episodes and mean losses."""

    success: int = 0
    episodes: int = 0
    steps: int = 0
    loss_ac: list = field(default_factory=lambda: [0.0, 0])
    """[sum, count] of the actor-critic's losses."""
    loss_q: list = field(default_factory=lambda: [0.0, 0])
    """[sum, count] of the Q-network's losses."""

    def finish(self, success: np.ndarray, steps: np.ndarray) -> None:
        """Episodes ended with these outcomes and lengths."""
        self.success += int(success.sum())
        self.episodes += len(success)
        self.steps += int(steps.sum())

    def state_dict(self) -> dict:
        return {k: (list(v) if isinstance(v, list) else v) for k, v in asdict(self).items()}


def log_row(counters: Counters, window: Window, epsilon: float | None, grg_counts: int | None) -> dict:
    """One ``log.csv`` row (empty fields where the method has no such thing)."""
    mean = lambda pair: round(pair[0] / pair[1], 6) if pair[1] else ""
    return {
        "env_steps": counters.env_steps,
        "episodes": counters.finished,
        "updates": counters.updates,
        "epsilon": round(epsilon, 4) if epsilon is not None else "",
        "success_rate": round(window.success / max(window.episodes, 1), 4),
        "mean_steps": round(window.steps / max(window.episodes, 1), 2),
        "loss_ac": mean(window.loss_ac),
        "loss_q": mean(window.loss_q),
        "grg_counts": grg_counts if grg_counts is not None else "",
        "wall_s": round(counters.wall_s, 1),
    }
