"""The discrete pose graph an agent moves on in a house, and shortest paths over it.

Poses are (cell, heading): cells are the centres of a square grid of ``GRID`` = 0.25 m laid
from the house's corner (0, 0) (rows along y, columns along x), headings are 0 = +x (east),
1 = +y, 2 = -x, 3 = -y, i.e. yaw = heading * 90 degrees counter-clockwise. The agent is a
cylinder of radius 0.2 m (``objsearch.house.occupancy``): a cell is free when the agent's
centre may stand there on the fine (0.05 m) occupancy grid, and a move between two free
cells is allowed when every point of the straight segment between them is free too.

We use 0.25 m rather than the paper's 0.2 m (House3D): the step of ObjectNav agents, and 36%
fewer poses to render and cache; goal poses and episode lengths are defined on this grid.

Actions (the paper's six, in its order, plus an optional STOP):
0 move ahead, 1 rotate left, 2 rotate right, 3 move back, 4 move left, 5 move right,
6 stop. A move into a blocked pose leaves the agent where it is.
"""

from __future__ import annotations

from array import array
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from objsearch.house.occupancy import OccupancyGrid, occupancy_grid
from objsearch.house.spec import HouseSpec

NAVGRAPH_VERSION = "navgraph-v1"
GRID = 0.25
FINE = 0.05
SEGMENT_SAMPLES = 6  # points checked along a move (every ~0.05 m)
ACTIONS = ("move_ahead", "rotate_left", "rotate_right", "move_back", "move_left", "move_right", "stop")
NUM_MOVE_ACTIONS = 6
STOP = 6
HEADING_VECTORS = np.array([[1, 0], [0, 1], [-1, 0], [0, -1]])  # (dx, dy) in cells per heading


@dataclass(frozen=True, eq=False)
class PoseGraph:
    """All poses of one house and the transition of every action.

    Attributes:
        rows, cols: grid shape (cells of ``GRID`` metres).
        cells: int (P // 4, 2) (row, col) of every free cell, in row-major order.
        next_pose: int32 (P, 7) pose reached by each action (STOP keeps the pose).
        cell_index: int32 (rows, cols) index of each free cell in ``cells``, -1 elsewhere.
    """

    rows: int
    cols: int
    cells: np.ndarray
    next_pose: np.ndarray
    cell_index: np.ndarray

    @property
    def num_poses(self) -> int:
        """Number of poses: 4 headings per free cell."""
        return len(self.cells) * 4

    def pose_id(self, row: int, col: int, heading: int) -> int:
        """The id of pose (row, col, heading mod 4); ValueError if the cell is not free."""
        index = int(self.cell_index[row, col]) if 0 <= row < self.rows and 0 <= col < self.cols else -1
        if index < 0:
            raise ValueError(f"cell ({row}, {col}) is not a free cell of the pose graph")
        return index * 4 + int(heading) % 4

    def pose_of(self, pose_id: int) -> tuple[int, int, int]:
        """(row, col, heading) of a pose id."""
        return self.pose_tuples[pose_id]

    @cached_property
    def pose_tuples(self) -> list[tuple[int, int, int]]:
        """Every pose as (row, col, heading), indexed by pose id."""
        return [(int(r), int(c), h) for r, c in self.cells.tolist() for h in range(4)]

    @cached_property
    def next_pose_flat(self) -> array:
        """``next_pose`` row by row in an ``array('i')``, ``next_pose_flat[pose * len(ACTIONS) +
        action]``: the env's per-step transition as a Python int, without a numpy scalar (4 bytes
        an entry, where Python lists of ints would take ten times that)."""
        return _int_array(self.next_pose)

    def world_poses(self, pose_ids=None) -> np.ndarray:
        """(N, 3) world (x, y, yaw) of poses (default: all), for the renderer."""
        ids = np.arange(self.num_poses) if pose_ids is None else np.asarray(pose_ids)
        rc = self.cells[ids // 4]
        return np.stack([(rc[:, 1] + 0.5) * GRID, (rc[:, 0] + 0.5) * GRID, (ids % 4) * (np.pi / 2)], axis=1)

    def shortest_steps(self, goal_poses) -> np.ndarray:
        """Minimal actions from every pose to the nearest of ``goal_poses`` (-1: unreachable).

        BFS backwards over the transition table, one frontier per distance: the values of
        ``_backward_bfs(next_pose[:, :NUM_MOVE_ACTIONS], goal_poses)``, walked in Python over
        each pose's predecessors, which visits every move once (several times faster than a
        vectorised pass over all poses per distance on a house's few thousand poses)."""
        bounds, sources = self.move_predecessors
        start = np.zeros(self.num_poses, dtype=bool)
        start[np.asarray(goal_poses, dtype=np.int64)] = True
        frontier = np.flatnonzero(start).tolist()
        dist = [-1] * self.num_poses
        for pose in frontier:
            dist[pose] = 0
        d = 0
        while frontier:
            d += 1
            reached = []
            for pose in frontier:
                for before in sources[bounds[pose] : bounds[pose + 1]]:
                    if dist[before] < 0:
                        dist[before] = d
                        reached.append(before)
            frontier = reached
        return np.array(dist, dtype=np.int32)

    @cached_property
    def move_predecessors(self) -> tuple[array, array]:
        """(bounds, sources): the poses from which one of the 6 moves leads to pose p are
        ``sources[bounds[p]:bounds[p + 1]]`` (repeats and p itself included: harmless to a
        BFS), in ``array('i')``s."""
        moves = self.next_pose[:, :NUM_MOVE_ACTIONS]
        sources = np.repeat(np.arange(len(moves)), moves.shape[1])[np.argsort(moves.ravel(), kind="stable")]
        bounds = np.concatenate([[0], np.cumsum(np.bincount(moves.ravel(), minlength=len(moves)))])
        return _int_array(bounds), _int_array(sources)

    def shortest_path(self, start: int, goal_poses) -> list[int]:
        """Actions of one shortest path from ``start`` to the goal set (ties: lowest action)."""
        dist = self.shortest_steps(goal_poses)
        if dist[start] < 0:
            raise ValueError(f"no goal pose can be reached from pose {start}")
        actions, pose = [], int(start)
        while dist[pose] > 0:
            options = self.next_pose[pose, :NUM_MOVE_ACTIONS]
            action = int(np.flatnonzero(dist[options] == dist[pose] - 1)[0])
            actions.append(action)
            pose = int(options[action])
        return actions

    def geodesic_distance(self, start: int, goal_poses) -> float:
        """Shortest walking distance in metres from a pose's cell to the nearest goal cell
        (4-connected cell moves, headings ignored); inf when unreachable."""
        return float(self.geodesic_metres(goal_poses)[start])

    def geodesic_metres(self, goal_poses) -> np.ndarray:
        """``geodesic_distance`` of every pose (float (P,), inf where unreachable)."""
        # cell -> the 4 neighbour cells: moves ahead/back of the heading-0 (+-x) and
        # heading-1 (+-y) pose of each cell (blocked moves lead back to the cell itself)
        cell_moves = np.concatenate([self.next_pose[0::4, [0, 3]], self.next_pose[1::4, [0, 3]]], axis=1) // 4
        steps = _backward_bfs(cell_moves, np.asarray(goal_poses) // 4)
        metres = np.where(steps < 0, np.inf, steps * GRID)
        return np.repeat(metres, 4)


def _int_array(values: np.ndarray) -> array:
    """``values`` flattened into an ``array('i')`` (C int: 32 bits)."""
    out = array("i")
    out.frombytes(np.ascontiguousarray(values, dtype=np.dtype(f"i{out.itemsize}")).tobytes())
    return out


def _backward_bfs(transitions: np.ndarray, targets) -> np.ndarray:
    """Steps from every node to the nearest target (-1: none), where ``transitions[n]``
    lists the nodes reachable from n in one step; one vectorised frontier per distance."""
    dist = np.full(len(transitions), -1, dtype=np.int32)
    frontier = np.zeros(len(transitions), dtype=bool)
    frontier[np.asarray(targets, dtype=np.int64)] = True
    dist[frontier] = 0
    d = 0
    while frontier.any():
        d += 1
        reached = frontier[transitions].any(axis=1) & (dist < 0)
        dist[reached] = d
        frontier = reached
    return dist


def _free_points(grid: OccupancyGrid, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    r = np.floor((y - grid.origin[1]) / grid.resolution).astype(int)
    c = np.floor((x - grid.origin[0]) / grid.resolution).astype(int)
    inside = (r >= 0) & (r < grid.free.shape[0]) & (c >= 0) & (c < grid.free.shape[1])
    out = np.zeros(r.shape, dtype=bool)
    out[inside] = grid.free[r[inside], c[inside]]
    return out


def build_pose_graph(spec: HouseSpec) -> PoseGraph:
    """The pose graph of a house: free 0.25 m cells for a 0.2 m-radius agent."""
    fine = occupancy_grid(spec, FINE)
    width, depth = spec.footprint
    rows, cols = int(np.floor(depth / GRID)), int(np.floor(width / GRID))
    rr, cc = np.mgrid[0:rows, 0:cols]
    free = _free_points(fine, (cc + 0.5) * GRID, (rr + 0.5) * GRID)
    cells = np.argwhere(free)
    cell_index = np.full((rows, cols), -1, dtype=np.int32)
    cell_index[cells[:, 0], cells[:, 1]] = np.arange(len(cells))

    # can_move[i, k]: the agent can translate from cell i one cell along HEADING_VECTORS[k]
    t = np.linspace(0.0, 1.0, SEGMENT_SAMPLES)
    x0, y0 = (cells[:, 1] + 0.5) * GRID, (cells[:, 0] + 0.5) * GRID
    target = np.full((len(cells), 4), -1, dtype=np.int64)
    for k, (dx, dy) in enumerate(HEADING_VECTORS):
        r2, c2 = cells[:, 0] + dy, cells[:, 1] + dx
        inside = (r2 >= 0) & (r2 < rows) & (c2 >= 0) & (c2 < cols)
        neighbour = np.where(inside, cell_index[np.clip(r2, 0, rows - 1), np.clip(c2, 0, cols - 1)], -1)
        xs = x0[:, None] + t[None, :] * dx * GRID
        ys = y0[:, None] + t[None, :] * dy * GRID
        clear = _free_points(fine, xs, ys).all(axis=1)
        target[:, k] = np.where((neighbour >= 0) & clear, neighbour, -1)

    num_poses = len(cells) * 4
    pose = np.arange(num_poses)
    cell, heading = pose // 4, pose % 4
    next_pose = np.empty((num_poses, len(ACTIONS)), dtype=np.int32)

    def translate(direction):
        moved = target[cell, direction % 4]
        return np.where(moved >= 0, moved * 4 + heading, pose)

    next_pose[:, 0] = translate(heading)  # ahead
    next_pose[:, 1] = cell * 4 + (heading + 1) % 4  # rotate left (counter-clockwise)
    next_pose[:, 2] = cell * 4 + (heading - 1) % 4  # rotate right
    next_pose[:, 3] = translate(heading + 2)  # back
    next_pose[:, 4] = translate(heading + 1)  # left
    next_pose[:, 5] = translate(heading - 1)  # right
    next_pose[:, 6] = pose  # stop
    return PoseGraph(rows=rows, cols=cols, cells=cells, next_pose=next_pose, cell_index=cell_index)
