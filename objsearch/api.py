"""objsearch from Python: evaluate an agent, build a suite, register a suite.

```python
import objsearch
from objsearch_agents.baselines.random_agent import RandomAgent

results = objsearch.evaluate(RandomAgent(), "gridworld", seeds=[1])
print(results["splits"]["seen-goals"]["sr"])
```

``evaluate`` is ``objsearch-eval`` without the command line: the same harness, episodes,
records and results dict (the JSON ``--out`` writes). These names are exported from
``objsearch`` itself and imported only when first used, so ``import objsearch`` stays light.
"""

from __future__ import annotations

import numbers
from pathlib import Path
from typing import Iterable

from objsearch.eval.config import check_seeds
from objsearch.eval.suites import make_suite, register_suite, standard_seeds

__all__ = ["evaluate", "make_suite", "register_suite"]


def evaluate(
    agent,
    suite: str = "gridworld",
    seeds: Iterable[int] | None = None,
    split: str | Iterable[str] | None = None,
    *,
    episodes: int | None = None,
    checkpoint: str | None = None,
    batch: int = 1,
    workers: int = 1,
    out: str | Path | None = None,
    progress: bool = False,
    step_time_limit: float | None = 10.0,
    **suite_config,
) -> dict:
    """Play ``agent`` on every episode of ``suite``'s splits, once per seed; return the results.

    Args:
        agent: an agent object (anything with ``reset(task)`` and ``act(observation)``;
            played in this process, as it is) or a name ``objsearch-eval --agent`` takes (a
            registered name, ``package.module:Class`` or ``file.py:Class``; its shipped
            checkpoint or training runs are loaded as the command line does).
        suite: a suite name (``objsearch suite list``) or a suite file's path.
        seeds: evaluation seeds; every episode is played once per seed. None: the suite's
            standard seeds, as ``objsearch-eval`` (``PAPER_SEEDS``; the large-house tier: 1).
        split: one split, several, or None for all of the suite's.
        episodes: only the first this many episodes of each split (``--episodes``, a quick
            look: the results are marked partial and the leaderboard refuses them).
        checkpoint: a checkpoint for a named agent (``--checkpoint``).
        batch, workers, out, progress, step_time_limit: as ``objsearch-eval``'s flags
            (``workers`` > 1 needs a named agent).
        **suite_config: the suite's options (e.g. ``observation="predicted"``).

    Returns:
        The results dict: ``splits`` (per split ``sr``, ``spl``, intervals, ...) and every
        episode's record under ``episodes``.
    """
    from objsearch.errors import UserError
    from objsearch.eval.config import EvalConfig
    from objsearch.eval.runner import evaluate as run

    counts = [("batch", batch), ("workers", workers)] + ([("episodes", episodes)] if episodes is not None else [])
    for name, value in counts:
        if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
            raise UserError(f"{name}={value!r}: give an integer >= 1")
    step_time_limit = _step_time_limit(step_time_limit)
    splits = (split,) if isinstance(split, str) else tuple(split or ())
    if isinstance(agent, str):
        name, instance = agent, None
    else:
        if not (callable(getattr(agent, "reset", None)) and callable(getattr(agent, "act", None))):
            raise UserError(f"agent {agent!r} has no reset(task) and act(observation) methods")
        if checkpoint is not None:
            raise UserError("checkpoint= is for an agent given by name; load it into the agent object yourself")
        cls = type(agent)
        # its class, never a name the object gives itself: a registered name means the registry's agent
        name, instance = f"{cls.__module__}:{cls.__qualname__}", agent
        from objsearch.eval.registry import check_supports

        check_supports(name, cls, suite)
    config = EvalConfig(
        agent=name,
        suite=suite,
        splits=splits,
        seeds=check_seeds(standard_seeds(suite) if seeds is None else seeds),
        checkpoint=checkpoint,
        episodes=episodes,
        suite_config=suite_config,
        step_time_limit=step_time_limit,
    )
    return run(config, workers=workers, progress=progress, out=out, batch=batch, agent=instance)


def _step_time_limit(value) -> float | None:
    """``step_time_limit`` checked: None or 0 (no limit), else a finite number of seconds > 0
    (at most ``cliargs.MAX_SECONDS``); ``UserError`` naming it otherwise."""
    from objsearch.cliargs import MAX_SECONDS
    from objsearch.errors import UserError

    if value is None or (isinstance(value, numbers.Real) and not isinstance(value, bool) and value == 0):
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 < value <= MAX_SECONDS:
        raise UserError(
            f"step_time_limit={value!r}: give a number of seconds > 0 (at most {MAX_SECONDS:g}), or 0 or None for no limit"
        )
    return float(value)
