"""The upper bound: follows a shortest path to the goal (the paper's Oracle).

It reads the episode's ground truth (``task.privileged.shortest_path()``) and replays it;
the suites' dynamics are deterministic, so it succeeds in exactly the minimal steps.
"""

from objsearch.eval.agent import OneSlotBatch


class OracleAgent(OneSlotBatch):
    """Shortest-path actions from the suite's ground truth."""

    # it reads the shortest path, not only its observations: marked and never ranked
    # (objsearch.eval.registry.is_privileged)
    privileged = True
    training_free = True

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
