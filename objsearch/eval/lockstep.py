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

The slots are any object with the protocol of ``EnvSlots`` (one env per slot, reset and
stepped one by one: any suite); a suite may offer a faster equivalent with
``make_slots(n)`` (the grid world's steps every slot in one ``BatchedGridWorld`` call),
which must give each slot the observations, rewards and ends its own env would.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Sequence

from objsearch.eval.agent import AgentTask, is_batched
from objsearch.eval.episode import agent_task, describe_failure, episode_record, time_limit, valid_action

Unit = tuple[str, int, int]


class EnvSlots:
    """Lockstep slots over one gymnasium env each, reset and stepped one by one.

    The protocol ``play_lockstep`` drives (a suite's ``make_slots(n)`` may return a faster
    object with the same methods and the same results):

    - ``len(slots)``: the number of slots;
    - ``start({slot: (episode, seed)})`` -> ``{slot: (first observation, reset info)}``:
      reset those slots' envs to the episodes, as ``env.reset(seed=seed,
      options={"task": episode.task})`` does;
    - ``observation_space(slot)``, ``action_space(slot)``: the slot env's spaces;
    - ``valid(slot, action)``: whether ``action`` is in the slot's action space;
    - ``step({slot: action})`` -> ``{slot: (observation, terminated, truncated, info)}``:
      one step of each of those slots (valid actions only; the others wait).
    """

    def __init__(self, envs: Sequence):
        self.envs = list(envs)

    def __len__(self) -> int:
        return len(self.envs)

    def start(self, starts: dict[int, tuple[Any, int]]) -> dict[int, tuple[Any, dict]]:
        """Reset the given slots' envs to their (episode, seed); returns each slot's (observation, info)."""
        return {
            i: self.envs[i].reset(seed=seed, options={"task": episode.task}) for i, (episode, seed) in starts.items()
        }

    def observation_space(self, i: int):
        """Slot ``i``'s env's observation space."""
        return self.envs[i].observation_space

    def action_space(self, i: int):
        """Slot ``i``'s env's action space."""
        return self.envs[i].action_space

    def valid(self, i: int, action) -> bool:
        """Whether ``action`` is in slot ``i``'s action space."""
        return valid_action(self.envs[i].action_space, action)

    def step(self, actions: dict[int, Any]) -> dict[int, tuple[Any, bool, bool, dict]]:
        """Step each given slot's env once; returns each slot's (observation, terminated, truncated, info)."""
        out = {}
        for i, action in actions.items():
            obs, _, terminated, truncated, info = self.envs[i].step(action)
            out[i] = obs, terminated, truncated, info
        return out


@dataclass
class Slot:
    """A slot's episode in play: its unit, episode, agent task, last observation and steps taken."""

    unit: Unit
    episode: Any
    task: AgentTask
    obs: Any = None
    steps: int = 0


def play_lockstep(
    units: list[Unit],
    envs,
    make_agent: Callable[[], Any],
    episode_of: Callable[[str, int], Any],
    suite_name: str,
    step_time_limit: float | None,
) -> Iterator[dict]:
    """Yield the record of every unit, as episodes finish.

    Args:
        units: (split, seed, episode_id) to play.
        envs: the slots: one env per slot (a list), or an object with ``EnvSlots``' protocol.
        make_agent: builds an agent (called once if it is batched, else once per slot).
        episode_of: (split, episode_id) -> the suite's ``Episode``.
        suite_name: the suite's name (for the agents' tasks).
        step_time_limit: seconds one agent call may take (None: no limit).
    """
    env_slots = EnvSlots(envs) if isinstance(envs, (list, tuple)) else envs
    num_slots = len(env_slots)
    todo = deque(units)
    first = make_agent()
    batched = is_batched(first)
    agents = [first] + ([] if batched else [make_agent() for _ in range(num_slots - 1)])
    if batched:
        first.start_batch(num_slots)
    slots: dict[int, Slot] = {}

    def fill(free: list[int]) -> dict[int, AgentTask]:
        """Start the next units in the ``free`` slots (in order); returns their tasks."""
        starting = {}
        for i in free:
            split, seed, episode_id = unit = todo.popleft()
            starting[i] = unit, episode_of(split, episode_id)
        started = env_slots.start({i: (episode, unit[1]) for i, (unit, episode) in starting.items()})
        for i, (unit, episode) in starting.items():
            obs, info = started[i]
            task = agent_task(
                suite_name, unit[0], episode, unit[1], info, env_slots.observation_space(i), env_slots.action_space(i)
            )
            slots[i] = Slot(unit, episode, task, obs)
        return {i: slots[i].task for i in starting}

    def finish(i: int, success: bool, error: str | None, trace: str | None = None) -> dict:
        s = slots.pop(i)
        return episode_record(s.unit[0], s.unit[1], s.episode, success, s.steps, error, trace)

    def call(fn, *args):
        """Run an agent call under the time limit: (result, None), or (None, the exception)
        if it raised or ran past the limit."""
        try:
            with time_limit(step_time_limit):
                return fn(*args), None
        except (Exception, SystemExit) as err:  # the agent's failure (StepTimeLimit, sys.exit) is its episodes'
            return None, err

    def failure(i: int, error: Exception) -> dict:
        return finish(i, False, *describe_failure(error, step_time_limit, slots[i].steps))

    while True:
        done: list[dict] = []
        while todo and len(slots) < num_slots:  # fill the free slots; a failed reset frees its slot again
            free = [i for i in range(num_slots) if i not in slots][: len(todo)]
            pending = fill(free)
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
                error = RuntimeError(
                    f"act_batch must return a dict with an action for each of the slots {sorted(slots)}"
                )
            errors = dict.fromkeys(slots, error) if error else {}
        else:
            actions, errors = {}, {}
            for i in slots:
                actions[i], error = call(agents[i].act, slots[i].obs)
                if error:
                    errors[i] = error
        moving = {i: actions[i] for i in slots if i not in errors and env_slots.valid(i, actions[i])}
        stepped = env_slots.step(moving) if moving else {}
        for i in list(slots):
            s = slots[i]
            if i in errors:
                done.append(failure(i, errors[i]))
            elif i not in stepped:
                done.append(
                    finish(
                        i,
                        False,
                        f"ValueError: invalid action {actions[i]!r} for action space {env_slots.action_space(i)}",
                    )
                )
            else:
                s.obs, terminated, truncated, info = stepped[i]
                s.steps += 1
                if terminated or truncated:
                    done.append(finish(i, bool(info["success"]), None))
        yield from done
