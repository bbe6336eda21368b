"""``oracle_rooms_frontier``: a privileged calibration agent, never ranked.

``frontier`` (``agents/baselines/frontier.py``) told which rooms hold the target: it reads the house
from the episode's ground truth (``task.privileged.world``: the rooms the target's instances
stand in) and explores the frontiers in and beside those rooms first. Everything else is
``frontier``'s. What it gains over ``frontier`` is the headroom a perfect room prior could
reach on a suite (``docs/large_houses.md``); it reads ground truth no agent may read, so its
results are marked privileged and it is left off the leaderboard, as the oracle is.

* **Target rooms.** The free cells of the pose graph that lie in a room holding an instance
  of the target, grown by ``margin`` metres (the cells in front of their doors), in the
  agent's map coordinates (its pose sensor's frame, relative to the start).
* **Score.** A frontier pose in the target rooms costs ``room_weight`` steps less, so those
  frontiers are explored first, nearest first; when none is left it explores as ``frontier``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import binary_dilation

from objsearch.eval.agent import AgentTask
from objsearch.sim.pose_sensor import relative_pose_of
from objsearch_agents.baselines.frontier import CELL, RADIUS, SIZE, FrontierAgent, FrontierConfig, SlotState


@dataclass(frozen=True)
class OracleRoomsConfig(FrontierConfig):
    """``frontier``'s settings and the room bonus."""

    room_weight: float = 1000.0
    """Steps a frontier pose in a target room is worth: more than any house is across, so they come first."""
    margin: float = 0.5
    """Target rooms are grown by this much (metres), to take in the frontier poses at their doors."""


def target_room_mask(task: AgentTask, margin: float) -> np.ndarray:
    """Bool (SIZE, SIZE) over the agent's map: cells in (or ``margin`` metres from) a room holding the target."""
    path = task.privileged
    if path is None or getattr(path, "world", None) is None:
        raise ValueError(f"suite {task.suite!r} gives no house ground truth; oracle_rooms_frontier needs it")
    world, start = path.world, tuple(path.task.start)
    rooms = {o.room for o in world.spec.objects if o.category == task.goal_name}
    cells = world.graph.cells[np.isin(world.cell_rooms, sorted(rooms))]
    mask = np.zeros((SIZE, SIZE), bool)
    for row, col in cells.tolist():
        x, y, _ = relative_pose_of(start, (row, col, start[2]))
        i, j = RADIUS + int(round(x / CELL)), RADIUS + int(round(y / CELL))
        if 0 <= i < SIZE and 0 <= j < SIZE:
            mask[i, j] = True
    grow = int(round(margin / CELL))
    return binary_dilation(mask, iterations=grow) if grow else mask


class OracleRoomsSlotState(SlotState):
    """``frontier``'s episode state, and the map cells of the target's rooms."""

    def __init__(self, task: AgentTask, config: OracleRoomsConfig):
        super().__init__(task, config)
        self.in_target_room = target_room_mask(task, config.margin)

    def frontier_cost(self, cells: np.ndarray, cost: np.ndarray) -> np.ndarray:
        return cost - self.config.room_weight * self.in_target_room[cells[:, 0], cells[:, 1]]


class OracleRoomsFrontierAgent(FrontierAgent):
    """Frontier exploration that knows the target's rooms (``objsearch-eval --agent oracle_rooms_frontier``;
    privileged: it reads ground truth, for calibration only)."""

    config = OracleRoomsConfig()
    privileged = True

    def new_slot(self, task: AgentTask) -> OracleRoomsSlotState:
        return OracleRoomsSlotState(task, self.config)
