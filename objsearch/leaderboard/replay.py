"""Replaying a submission (``verify_submission``): a sample of its episodes, drawn with fresh OS
randomness at verify time (``replay_sample``), never from the submission's content, so that a
submitter cannot know which records will be replayed, is played again with the agent,
checkpoint and suite config it names, and must give identical records (evaluation is
deterministic), which a renamed or fabricated submission cannot. The sample's size
(``sample_size``) catches a submission with ``DETECT_FRACTION`` of its records altered with
probability at least ``DETECT_PROBABILITY``. ``content_sha256`` and ``replayed_of`` tie a stored
entry's ``verified`` record to the content that was replayed."""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from objsearch.eval.agent import CHECKPOINTS_ENV, checkpoints_from
from objsearch.eval.config import EvalConfig
from objsearch.eval.registry import is_file_spec
from objsearch.eval.runner import run_units
from objsearch.eval.runs import agent_of
from objsearch.leaderboard.checks import _unit, _where, check_submission, playable_config

# the fields of a record that a replay must reproduce exactly (spl follows from them; no timing fields exist)
REPLAYED = ("goal", "min_steps", "task", "success", "steps", "error")
# a replay sample catches a submission with DETECT_FRACTION of its records altered with at least this probability
DETECT_FRACTION = 0.05
DETECT_PROBABILITY = 0.99


def sample_size(total: int, fraction: float = DETECT_FRACTION, probability: float = DETECT_PROBABILITY) -> int:
    """How many of ``total`` records a uniform sample without replacement must hold to
    include at least one of ``ceil(fraction * total)`` altered ones with ``probability``:
    the smallest ``n`` whose hypergeometric miss probability, the product over ``i < n`` of
    ``(total - altered - i) / (total - i)``, is at most ``1 - probability`` (90 for large
    entries, where it tends to the binomial bound ``(1 - fraction) ** n``); at most ``total``."""
    altered = max(1, math.ceil(fraction * total - 1e-9))
    miss, n = 1.0, 0
    while n < total and miss > 1 - probability:
        miss *= max(0, total - altered - n) / (total - n)
        n += 1
    return n


def miss_probability(total: int, n: int, fraction: float = DETECT_FRACTION) -> float:
    """The probability that a sample of ``n`` of ``total`` records holds none of
    ``ceil(fraction * total)`` altered ones (see ``sample_size``)."""
    altered = max(1, math.ceil(fraction * total - 1e-9))
    return math.prod(max(0, total - altered - i) / (total - i) for i in range(min(n, total)))


def replay_units(results: dict) -> list[tuple]:
    """Every (split, seed, episode_id, training run) unit of ``results``, in a fixed order."""
    return sorted({_unit(r) for r in results["episodes"]}, key=str)


def replay_sample(results: dict, k: int | None, rng: np.random.Generator) -> list[tuple]:
    """``k`` (``None``: ``sample_size``; at most all) units of ``results`` drawn uniformly
    without replacement by ``rng``. The verifier passes a generator seeded from fresh OS
    randomness (``fresh_rng``), so nothing in a submission decides, or predicts, its sample."""
    units = replay_units(results)
    return [units[i] for i in sorted(rng.choice(len(units), size=replay_count(results, k), replace=False))]


def replay_count(results: dict, k: int | None) -> int:
    """How many units ``replay_sample(results, k, ...)`` draws."""
    total = len(replay_units(results))
    return sample_size(total) if k is None else min(k, total)


def fresh_rng() -> np.random.Generator:
    """A generator seeded from the operating system's randomness at the time of the call:
    the verifier's own, unknown to any submitter."""
    return np.random.default_rng()


def content_sha256(results: dict) -> str:
    """The digest of a submission's content, its ``verified`` record left out: a stored
    verification counts only for the content it replayed."""
    content = {k: v for k, v in results.items() if k != "verified"}
    return hashlib.sha256(json.dumps(content, sort_keys=True).encode()).hexdigest()


def replayed_of(results: dict) -> tuple[int, int] | None:
    """(episodes replayed, episodes) of the stored entry ``results``'s last verification,
    if one was recorded for its present content; None if none was."""
    verified = results.get("verified")
    if not isinstance(verified, dict) or verified.get("sha256") != content_sha256(results):
        return None
    return verified["replayed"], verified["episodes"]


def untrusted_code(agent: str) -> str | None:
    """What code verifying an entry of ``agent`` would import that is not a registered agent
    (a file agent, or a ``module:Class`` that no installed package registers), said in a few
    words; None for a registered agent (by name or by its registered ``module:Class``)."""
    from objsearch.eval.registry import registered_agents

    registered = registered_agents()
    if agent in registered or agent in registered.values():
        return None
    if is_file_spec(agent):
        return f"the Python file {agent.rpartition(':')[0]} (class {agent.rpartition(':')[2]})"
    return f"the module {agent.rpartition(':')[0]!r} (class {agent.rpartition(':')[2]}), not a registered agent"


def verify_submission(
    results: dict, k: int | None = None, rng: np.random.Generator | None = None, trust: bool = False
) -> list[str]:
    """Problems found by replaying ``k`` (None: ``sample_size``) of the episodes of a valid
    submission, drawn by ``rng`` (None: ``fresh_rng()``), with the agent, checkpoint and suite
    config it names (empty when every replayed record is identical). An agent that is not a
    registered one (``untrusted_code``) is imported only with ``trust``; the suite's
    ``WRITE_OPTIONS`` are the verifier's, never the submission's."""
    problems = check_submission(results)
    if problems:
        return problems
    if is_file_spec(results["agent"]):
        path = Path(results["agent"].rpartition(":")[0])
        if not path.is_file():
            return [
                f"its agent file {path.resolve()} is missing: replay loads the file the evaluation recorded; "
                "put the file back there, or evaluate again and add the new results with --replace"
            ]
    code = untrusted_code(results["agent"])
    if code is not None and not trust:
        return [
            f"replaying it would import and run {code}; read that code, then pass --trust to run it "
            "(registered agents need no --trust)"
        ]
    c = results["config"]
    if c.get("checkpoints") is not None and not Path(c["checkpoints"]).is_dir():
        return [
            f"its agent found its weights in ${CHECKPOINTS_ENV} = {c['checkpoints']}, which is no folder here: "
            "replay loads the weights the evaluation recorded; put that folder back, or evaluate again and add "
            "the new results with --replace"
        ]
    with checkpoints_from(c.get("checkpoints")):
        return _replayed_problems(results, k, rng)


def _replayed_problems(results: dict, k: int | None, rng) -> list[str]:
    """``verify_submission``'s replay of a checked submission that may run."""
    c = results["config"]
    config = EvalConfig(
        agent=results["agent"],
        suite=results["suite"],
        splits=tuple(c["splits"]),
        seeds=tuple(results["seeds"]),
        checkpoint=c.get("checkpoint"),
        suite_config=playable_config(c.get("suite_config", {})),
        step_time_limit=None,
        training_run=c.get("training_run"),
    )
    runs = results.get("training_runs", [])
    claims = {None: c.get("weights_sha256")} if len(runs) <= 1 else {run["seed"]: run["weights_sha256"] for run in runs}
    stored, problems = {_unit(r): r for r in results["episodes"]}, []
    units = replay_sample(results, k, fresh_rng() if rng is None else rng)
    for run, claimed in claims.items():
        play = config if run is None else replace(config, training_run=run)
        if claimed is not None:  # the weights the submission names must be the ones that load now
            loaded = getattr(agent_of(play), "weights_sha256", None)
            if loaded != claimed:
                what = f"checkpoint {config.checkpoint or 'shipped'}" + ("" if run is None else f", training run {run}")
                return [
                    f"the submission used weights {claimed[:12]}, but agent {results['agent']!r} loads "
                    f"{str(loaded)[:12]} ({what}); replay it with the weights it names"
                ]
        mine = [u[:3] for u in units if u[3] == run]
        for replayed in run_units(play, mine, progress=False) if mine else []:
            unit = (replayed["split"], replayed["seed"], replayed["episode_id"], run)
            for key in REPLAYED:
                if stored[unit].get(key) != replayed.get(key):
                    problems.append(
                        f"episode {_where(unit)}: {key} is {stored[unit].get(key)!r} in the "
                        f"submission but {replayed.get(key)!r} when replayed with agent {results['agent']!r}"
                    )
                    break
    return problems[:3] + ([f"{len(problems)} of {len(units)} replayed episodes differ"] if len(problems) > 3 else [])
