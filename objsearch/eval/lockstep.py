"""Playing many episodes in lockstep (``objsearch-eval --batch N``).

N slots, each with its own env, play units (split, seed, episode) side by side: one agent
call per step for all slots, and a slot is refilled with the next unit as soon as its
episode ends. An agent with the batched protocol (``objsearch.eval.agent``:
``start_batch``, ``reset_batch``, ``act_batch``) decides for all slots in one call; any
other agent gets one instance per slot, each called as in a sequential run. Every episode
keeps its own ``task.rng`` and its own record, so the records do not depend on N, on the
order units run in or on the workers (``docs/add_your_agent.md``, "Batched, for speed").

Failures stay per episode: an invalid action fails its episode; an exception or a call
past the step time limit fails the episodes that call was for.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any, Callable, Iterator

from objsearch.eval.agent import AgentTask, is_batched
from objsearch.eval.episode import describe_failure, episode_record, start_episode, time_limit

Unit = tuple[str, int, int]


@dataclass
class Slot:
    unit: Unit
    episode: Any
    task: AgentTask
    obs: Any = None
    steps: int = 0


def play_lockstep(
    units: list[Unit],
    envs: list,
    make_agent: Callable[[], Any],
    episode_of: Callable[[str, int], Any],
    suite_name: str,
    step_time_limit: float | None,
) -> Iterator[dict]:
    """Yield the record of every unit, as episodes finish.

    Args:
        units: (split, seed, episode_id) to play.
        envs: one env per slot.
        make_agent: builds an agent (called once if it is batched, else once per slot).
        episode_of: (split, episode_id) -> the suite's ``Episode``.
        suite_name: the suite's name (for the agents' tasks).
        step_time_limit: seconds one agent call may take (None: no limit).
    """
    todo = deque(units)
    first = make_agent()
    batched = is_batched(first)
    agents = [first] + ([] if batched else [make_agent() for _ in range(len(envs) - 1)])
    if batched:
        first.start_batch(len(envs))
    slots: dict[int, Slot] = {}

    def fill(i: int) -> None:
        split, seed, episode_id = unit = todo.popleft()
        episode = episode_of(split, episode_id)
        obs, task = start_episode(envs[i], suite_name, split, episode, seed)
        slots[i] = Slot(unit, episode, task, obs)

    def finish(i: int, success: bool, error: str | None, trace: str | None = None) -> dict:
        s = slots.pop(i)
        return episode_record(s.unit[0], s.unit[1], s.episode, success, s.steps, error, trace)

    def call(fn, *args):
        """Run an agent call under the time limit: (result, None), or (None, the exception)
        if it raised or ran past the limit."""
        try:
            with time_limit(step_time_limit):
                return fn(*args), None
        except Exception as err:  # the agent's failure (StepTimeLimit included) is its episodes', not the run's
            return None, err

    def failure(i: int, error: Exception) -> dict:
        return finish(i, False, *describe_failure(error, step_time_limit, slots[i].steps))

    while True:
        done: list[dict] = []
        while todo and len(slots) < len(envs):  # fill the free slots; a failed reset frees its slot again
            pending: dict[int, AgentTask] = {}
            for i in range(len(envs)):
                if i not in slots and todo:
                    fill(i)
                    pending[i] = slots[i].task
            if batched:
                _, error = call(first.reset_batch, pending)
                failed = dict.fromkeys(pending, error) if error else {}
            else:
                failed = {i: e for i, e in ((i, call(agents[i].reset, t)[1]) for i, t in pending.items()) if e}
            done += [failure(i, error) for i, error in failed.items()]
        if not slots:
            yield from done
            return
        if batched:
            actions, error = call(first.act_batch, {i: s.obs for i, s in slots.items()})
            if error is None and (not isinstance(actions, dict) or set(actions) != set(slots)):
                error = RuntimeError(f"act_batch must return a dict with an action for each of the slots {sorted(slots)}")
            errors = dict.fromkeys(slots, error) if error else {}
        else:
            actions, errors = {}, {}
            for i in slots:
                actions[i], error = call(agents[i].act, slots[i].obs)
                if error:
                    errors[i] = error
        for i in list(slots):
            s = slots[i]
            if i in errors:
                done.append(failure(i, errors[i]))
            elif not envs[i].action_space.contains(actions[i]):
                done.append(finish(i, False, f"ValueError: invalid action {actions[i]!r} for action space {envs[i].action_space}"))
            else:
                s.obs, _, terminated, truncated, info = envs[i].step(actions[i])
                s.steps += 1
                if terminated or truncated:
                    done.append(finish(i, bool(info["success"]), None))
        yield from done
