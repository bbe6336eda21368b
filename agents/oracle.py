"""The upper bound: follows a shortest path to the goal (the paper's Oracle).

It reads the episode's ground truth (``task.privileged.shortest_path()``) and replays it;
the suites' dynamics are deterministic, so it succeeds in exactly the minimal steps.
"""

from objsearch.eval.agent import AgentTask


class OracleAgent:
    """Shortest-path actions from the suite's ground truth."""

    def reset(self, task: AgentTask) -> None:
        if task.privileged is None:
            raise ValueError(f"suite {task.suite!r} gives no ground truth for the oracle")
        self._plan = list(task.privileged.shortest_path())
        self._step = 0

    def act(self, observation):
        if self._step >= len(self._plan):
            raise RuntimeError("the oracle ran past its shortest path; the episode should have ended")
        action = self._plan[self._step]
        self._step += 1
        return action
