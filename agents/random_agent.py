"""The lower bound: a uniformly random action every step."""

from objsearch.eval.agent import AgentTask


class RandomAgent:
    """Uniformly random actions from the env's discrete action space (the paper's Random)."""

    def reset(self, task: AgentTask) -> None:
        self._rng = task.rng
        self._num_actions = int(task.action_space.n)

    def act(self, observation) -> int:
        return int(self._rng.integers(self._num_actions))
