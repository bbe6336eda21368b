"""Misbehaving agents for the harness tests (an oracle that fails in chosen ways)."""

import time

from objsearch_agents.oracle import OracleAgent


class RaisingAgent(OracleAgent):
    """Raises in act() on even episodes."""

    def reset(self, task):
        super().reset(task)
        self._fail = task.episode_id % 2 == 0

    def act(self, observation):
        if self._fail:
            raise RuntimeError("boom")
        return super().act(observation)


class SlowAgent(OracleAgent):
    """Takes 2 s for its first action of episode 0."""

    def reset(self, task):
        super().reset(task)
        self._slow = task.episode_id == 0

    def act(self, observation):
        if self._slow:
            self._slow = False
            time.sleep(2.0)
        return super().act(observation)


class BadActionAgent(OracleAgent):
    def act(self, observation):
        return 7


class InterruptedAgent(OracleAgent):
    """An oracle that counts resets, and raises KeyboardInterrupt (as Ctrl-C would) once
    ``interrupt_after`` episodes have started."""

    interrupt_after: int | None = None
    resets = 0

    def reset(self, task):
        cls = type(self)
        if cls.interrupt_after is not None and cls.resets >= cls.interrupt_after:
            raise KeyboardInterrupt
        cls.resets += 1
        super().reset(task)
