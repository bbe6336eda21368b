"""Misbehaving agents for the harness tests (an oracle that fails in chosen ways)."""

import hashlib
import os
import time

from objsearch_agents.baselines.oracle import OracleAgent


class RaisingAgent(OracleAgent):
    """Raises in act() on even episodes."""

    def reset(self, task):
        super().reset(task)
        self._fail = task.episode_id % 2 == 0

    def act(self, observation):
        if self._fail:
            raise RuntimeError("boom")
        return super().act(observation)


class FlakyAgent(OracleAgent):
    """Raises in act() as $FLAKY_AGENT_FAILS says: on even episodes ("even"), on every one ("all"),
    or never (unset)."""

    def reset(self, task):
        super().reset(task)
        mode = os.environ.get("FLAKY_AGENT_FAILS", "")
        self._fail = mode == "all" or (mode == "even" and task.episode_id % 2 == 0)

    def act(self, observation):
        if self._fail:
            raise RuntimeError("flaky")
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


def weights_of(checkpoint) -> str:
    """The stand-in weights digest of a ``RunsAgent`` checkpoint."""
    return hashlib.sha256(str(checkpoint).encode()).hexdigest()


class RunsAgent(OracleAgent):
    """A learned agent shipped as three training runs (seeds 0, 1, 2) of unequal skill: the
    run of checkpoint ``"run-K"`` plays an episode as the oracle with probability
    ``SKILL[K]``, else with random moves. Grid world only, for fast tests of multi-run
    evaluation."""

    SKILL = (0.9, 0.5, 0.1)

    @classmethod
    def training_runs(cls, suite):
        from objsearch.eval.agent import TrainingRun

        return [TrainingRun(seed, f"run-{seed}", env_steps=1000 * (seed + 1), wall_s=1.5) for seed in (0, 1, 2)]

    @classmethod
    def for_suite(cls, suite, checkpoint=None):
        agent = cls()
        agent.load(checkpoint or "run-0")
        return agent

    def load(self, path):
        self.skill = self.SKILL[int(str(path).rsplit("-", 1)[1])]
        self.weights_sha256 = weights_of(path)

    def reset(self, task):
        super().reset(task)
        self._rng, self._n = task.rng, task.action_space.n
        self._oracle = self._rng.random() < self.skill

    def act(self, observation):
        return super().act(observation) if self._oracle else int(self._rng.integers(self._n))
