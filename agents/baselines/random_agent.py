"""The lower bound: a uniformly random action every step."""

from objsearch.eval.agent import AgentTask


class RandomAgent:
    """Uniformly random actions from the env's discrete action space (the paper's Random)."""

    training_free = True  # nothing learned: the board shows no training runs (registry.is_training_free)

    def reset(self, task: AgentTask) -> None:
        self._rng = task.rng
        self._num_actions = int(task.action_space.n)

    def act(self, observation) -> int:
        return int(self._rng.integers(self._num_actions))

    # the batched form: one (Generator, action count) per slot, drawn as ``act`` draws
    def start_batch(self, num_slots: int) -> None:
        self._slots: list = [None] * num_slots

    def reset_batch(self, tasks: dict) -> None:
        for i, task in tasks.items():
            self._slots[i] = (task.rng, int(task.action_space.n))

    def act_batch(self, observations: dict) -> dict:
        return {i: int(self._slots[i][0].integers(self._slots[i][1])) for i in observations}
