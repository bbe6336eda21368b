"""Playing one episode: the agent's task, its random Generator, the per-call time limit
and the episode's record (shared by the sequential and the lockstep runs)."""

from __future__ import annotations

import contextlib
import os
import signal
import threading
import time
import traceback
import zlib

import numpy as np

from objsearch.eval.agent import AgentTask
from objsearch.eval.suites import Episode


def episode_rng(seed: int, split: str, episode_id: int) -> np.random.Generator:
    """The Generator of one (seed, split, episode): independent of run order and workers."""
    return np.random.default_rng([seed, zlib.crc32(split.encode()), episode_id])


class StepTimeLimit(Exception):
    """An agent call ran past the step time limit."""


HARNESS = os.path.dirname(os.path.abspath(__file__)) + os.sep
TRACEBACK_FRAMES = 8  # the agent's innermost frames kept in a failed episode's record


def valid_action(space, action) -> bool:
    """Whether ``action`` is in the action ``space``: an integer in range, as Gymnasium's
    ``Discrete`` says, but never a bool (``True`` is no action, though Python counts it as 1)."""
    return not isinstance(action, (bool, np.bool_)) and bool(space.contains(action))


def describe_failure(err: BaseException, step_time_limit: float | None, steps: int) -> tuple[str, str | None]:
    """An agent's failure as its episode's record keeps it: (``error``, ``traceback``: the
    last frames of the agent's own code, without the harness's, or None if there are none)."""
    if isinstance(err, StepTimeLimit):
        return f"step time limit of {step_time_limit:g} s exceeded at step {steps}", None
    message = f"{type(err).__name__}: {err}"
    frames = [
        f
        for f in traceback.extract_tb(err.__traceback__)
        if not f.filename.startswith(HARNESS) and f.filename != contextlib.__file__
    ]
    if not frames:
        return message, None
    return message, "".join(traceback.format_list(frames[-TRACEBACK_FRAMES:])) + message


@contextlib.contextmanager
def time_limit(seconds: float | None):
    """Interrupt the block after ``seconds`` (SIGALRM, main thread only); elsewhere the
    limit is checked when the call returns."""
    if seconds is None:
        yield
        return
    use_alarm = threading.current_thread() is threading.main_thread() and hasattr(signal, "setitimer")
    if use_alarm:

        def on_alarm(signum, frame):
            raise StepTimeLimit

        previous = signal.signal(signal.SIGALRM, on_alarm)
        signal.setitimer(signal.ITIMER_REAL, seconds)
    start = time.monotonic()
    try:
        yield
    finally:
        if use_alarm:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
    if time.monotonic() - start > seconds:
        raise StepTimeLimit


def run_episode(
    agent,
    env,
    suite_name: str,
    split: str,
    episode: Episode,
    seed: int,
    step_time_limit: float | None = None,
    trajectory: list | None = None,
) -> dict:
    """Play one episode and return its record (``error`` is set if the agent failed it).

    With ``trajectory`` (a list), every (observation, info) of the episode is appended to it.
    """
    obs, task = start_episode(env, suite_name, split, episode, seed, trajectory)
    steps, success, error, trace = 0, False, None, None
    try:
        with time_limit(step_time_limit):
            agent.reset(task)
        while True:
            with time_limit(step_time_limit):
                action = agent.act(obs)
            if not valid_action(env.action_space, action):
                raise ValueError(f"invalid action {action!r} for action space {env.action_space}")
            obs, _, terminated, truncated, info = env.step(action)
            steps += 1
            if trajectory is not None:
                trajectory.append((obs, info))
            if terminated or truncated:
                success = bool(info["success"])
                break
    except (Exception, SystemExit) as err:  # the agent's failure (StepTimeLimit, sys.exit included) is the episode's
        error, trace = describe_failure(err, step_time_limit, steps)
    return episode_record(split, seed, episode, success, steps, error, trace)


def start_episode(env, suite_name: str, split: str, episode: Episode, seed: int, trajectory: list | None = None):
    """Reset ``env`` to the episode; returns (first observation, the agent's ``AgentTask``)."""
    obs, info = env.reset(seed=seed, options={"task": episode.task})
    if trajectory is not None:
        trajectory.append((obs, info))
    return obs, agent_task(suite_name, split, episode, seed, info, env.observation_space, env.action_space)


def agent_task(
    suite_name: str, split: str, episode: Episode, seed: int, info: dict, observation_space, action_space
) -> AgentTask:
    """The agent's ``AgentTask`` for an episode its env has just been reset to (``info``:
    the reset's info, checked against the suite's ``min_steps``)."""
    if info.get("min_steps", episode.min_steps) != episode.min_steps:
        raise RuntimeError(f"env and suite disagree on min_steps of {split}/{episode.episode_id}")
    return AgentTask(
        suite=suite_name,
        split=split,
        episode_id=episode.episode_id,
        goal=episode.goal,
        goal_name=episode.goal_name,
        observation_space=observation_space,
        action_space=action_space,
        rng=episode_rng(seed, split, episode.episode_id),
        privileged=episode.privileged,
        camera=info.get("camera"),
        stop_action=info.get("stop_action"),
        goal_rule=info.get("goal_rule"),
    )


def episode_record(
    split: str, seed: int, episode: Episode, success: bool, steps: int, error: str | None, trace: str | None = None
) -> dict:
    """The record of one played episode (``error`` set if the agent failed it, and
    ``traceback`` if that failure was raised in the agent's code)."""
    record = {
        "split": split,
        "seed": seed,
        "episode_id": episode.episode_id,
        "goal": episode.goal_name,
        "success": success,
        "steps": steps,
        "min_steps": episode.min_steps,
        "task": episode.describe,
    }
    if error is not None:
        record["error"] = error
    if trace is not None:
        record["traceback"] = trace
    return record
