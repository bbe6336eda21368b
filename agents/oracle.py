"""The upper bound: follows a shortest path to the goal (the paper's Oracle).

It reads the episode's ground truth (``task.privileged.shortest_path()``) and replays it;
the suites' dynamics are deterministic, so it succeeds in exactly the minimal steps.
"""

from objsearch.eval.agent import AgentTask


class OracleAgent:
    """Shortest-path actions from the suite's ground truth."""

    def reset(self, task: AgentTask) -> None:
        self.start_batch(1)
        self.reset_batch({0: task})

    def act(self, observation):
        return self.act_batch({0: observation})[0]

    # the batched form: one plan per slot
    def start_batch(self, num_slots: int) -> None:
        self._plans: list[list] = [[] for _ in range(num_slots)]

    def reset_batch(self, tasks: dict) -> None:
        for i, task in tasks.items():
            if task.privileged is None:
                raise ValueError(f"suite {task.suite!r} gives no ground truth for the oracle")
            self._plans[i] = list(task.privileged.shortest_path())[::-1]  # next action last

    def act_batch(self, observations: dict) -> dict:
        if any(not self._plans[i] for i in observations):
            raise RuntimeError("the oracle ran past its shortest path; the episode should have ended")
        return {i: self._plans[i].pop() for i in observations}
