"""A training-free reference agent for the houses: frontier exploration on a metric map.

The modular ObjectNav recipe (Yamauchi's frontiers; SemExp and DWFE without the learning),
on what every house suite gives an agent: ``depth``, ``semantic``, ``target``, the
``pose`` sensor (x forward, y left, heading, relative to the start) and the camera's
parameters (``task.camera``). No checkpoint, no training, CPU only.

Each step, for every episode of the batch:

1. **Map.** The depth image becomes points (planar depth, pinhole camera). Points between
   ``obstacle_low`` and ``obstacle_high`` metres above the floor, other than floor and
   ceiling pixels, are obstacles: a map cell (0.25 m, aligned with the pose graph's cells)
   is blocked when ``min_points`` of a frame's lie within ``block_radius`` of its centre.
   ``block_radius`` is a little below the agent's radius, so a cell the agent can stand on
   is never blocked (checked against the true floor plan in the tests). How far depth is
   trusted comes from the frame itself: where the floor's pixels lie flat (rendered depth)
   every point counts; where they scatter (predicted depth), only points within
   ``block_range`` block, and those within ``obstacle_range`` make a cell cost
   ``soft_cost`` more to cross. Each image column is a ray of a planar scan: the cells it
   crosses before its nearest obstacle (and floor points) are seen free. A move that comes
   back ``collided`` blocks that edge.
2. **Target.** Pixels of the target's id become points, kept in 0.1 m voxels
   (``frontier_target.TargetMemory``).
3. **Approach on sight.** With target voxels in memory, every reachable pose within
   ``approach_radius`` gets a score: the image area the voxels would cover from it
   (each voxel ``1 / depth**2``, counted when inside the camera's frustum and not hidden by
   a wall). Goal poses are the poses where the target fills the view, so the agent goes to
   the nearest pose scoring at least ``approach_share`` of the best, and faces the target
   there. This is what finds the far views that paintings and mirrors (mounted high) and
   coffee tables and TV stands (low) need. A pose reached without ending the episode is
   struck off; when no untried pose is left, it explores on for another instance.
4. **Frontier exploration.** Otherwise it goes to the nearest frontier pose: a free cell
   beside an unseen one, facing it. Path costs are the env's: one step a cell (the agent
   can strafe), one a quarter turn; a run of ``face_run`` cells turns to face it first.
   The goal is kept while it stays a candidate.
5. **Recovery.** With nothing to go to (no frontier reachable), or after ``stuck_steps``
   steps on two poses or fewer, it takes a random action from ``task.rng``.
6. **STOP** (suites of the ObjectNav protocol, where ``task.stop_action`` is set): before
   deciding, it calls STOP when the frame shows the goal rule's ``min_pixels`` target pixels
   at most ``max_distance`` metres deep; on predicted perception the STOP is earned
   (``frontier_target``). docs/frontier.md measures each rule on validation splits.

The batched form (``act_batch``) projects every slot's frame in one array pass; planning
is per slot, on the slot's own map. The map's geometry (projection, paths, view scores) is
``frontier_geometry``. Records do not depend on the batch: the agent is
deterministic but for recovery moves, which draw from the slot's ``task.rng``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from objsearch.eval.agent import AgentTask, OneSlotBatch
from objsearch.house.categories import CATEGORY_IDS
from objsearch_agents.baselines.frontier_geometry import (
    CELL,
    RADIUS,
    SIZE,
    STEPS,
    VOXEL,
    bfs,
    column_angles,
    neighbours,
    project,
    turns,
    view_scores,
)
from objsearch_agents.baselines.frontier_target import TargetMemory

CEILING = 2.6  # metres: points higher up are the ceiling (walls are 2.7 m high)
FLOOR, CEILING_ID = CATEGORY_IDS["floor"], CATEGORY_IDS["ceiling"]
MOVE_OFFSET = {0: 0, 4: 1, 3: 2, 5: 3}  # action -> direction relative to the heading (ahead, left, back, right)
ACTION_FOR_OFFSET = {v: k for k, v in MOVE_OFFSET.items()}
DIRECTION = {(int(di), int(dj)): k for k, (di, dj) in enumerate(STEPS)}
ROTATE_LEFT, ROTATE_RIGHT = 1, 2


@dataclass(frozen=True)
class FrontierConfig:
    """The agent's settings (the defaults are what the leaderboard ran)."""

    obstacle_low: float = 0.1
    """Points higher than this above the floor (metres) are obstacles."""
    obstacle_high: float = 1.6
    """... and lower than this (the agent's height)."""
    floor_high: float = 0.05
    """Points lower than this are floor."""
    block_radius: float = 0.18
    """A cell is blocked when an obstacle point lies this close to its centre (metres)."""
    flat_floor: float = 0.003
    """A frame whose floor pixels lie this close to height 0 (median, metres) has exact depth: its
    obstacle points block at any range. Otherwise ``block_range`` and ``obstacle_range`` apply."""
    block_range: float = 1.5
    """Obstacle points nearer than this (metres along the ground) block cells (predicted depth errs with range)."""
    obstacle_range: float = 3.0
    """Obstacle points nearer than this and farther than ``block_range`` make cells costly to cross."""
    min_points: int = 3
    """... when at least this many points of one frame lie within ``block_radius``."""
    soft_cost: float = 10.0
    """What a path pays for crossing a cell only far obstacle points block, beside its one step."""
    max_range: float = 5.0
    """Free space is traced this far along each image column (metres)."""
    min_target_pixels: int = 3
    """Fewer target pixels in a frame are ignored (noise of predicted segmentation)."""
    approach_radius: float = 3.5
    """Poses this close to a target voxel are scored for the approach (metres)."""
    approach_share: float = 0.8
    """The approach goes to the nearest untried pose scoring at least this share of the best."""
    face_run: int = 3
    """A path that runs this many cells in one direction turns to face it first."""
    stuck_steps: int = 6
    """This many steps on two poses or fewer (blocked, or turning to and fro) start a random move."""
    stop_views: int = 2
    """Predicted perception (floor not flat): STOP once the target passed the STOP test from this many cells."""
    stop_match: float = 0.75
    """... the passing pixels' centres lie this close (metres, along the ground) to be the same target."""
    stop_margin: float = 0.15
    """Predicted perception: the STOP test's depth limit is the goal rule's less this (metres)."""
    stop_pixels: float = 1.0
    """Predicted perception: the STOP test asks for this many times the goal rule's target pixels."""
    stop_share: float = 0.6
    """Predicted perception: at least this share of the labels all frames gave the passing pixels' voxels (pixels
    within ``vote_range``) is the target's: a thing read as the target from one view only is not confirmed."""
    vote_range: float = 2.0
    """... labels of pixels nearer than this (metres along the ground) vote."""


class SlotState:
    """One episode's memory and decisions: the map, the target voxels, the poses visited."""

    def __init__(self, task: AgentTask, config: FrontierConfig):
        self.rng, self.config = task.rng, config
        self.angles = column_angles(task.camera)
        self.camera = task.camera
        self.memory = TargetMemory(task, config)
        self.seen = np.zeros((SIZE, SIZE), bool)  # a ray or floor point fell in the cell
        self.blocked = np.zeros((SIZE, SIZE), bool)  # an obstacle seen near lies within block_radius of its centre
        self.soft = np.zeros((SIZE, SIZE), bool)  # ... one seen farther (less sure: paths may cross it, at a cost)
        self.top = np.zeros((SIZE, SIZE), np.float32)  # the highest point seen in the cell, below the ceiling
        self.edge = np.ones((4, SIZE, SIZE), bool)  # edge[d, i, j]: the move from (i, j) along d is not known blocked
        self.visited: set[tuple[int, int, int]] = set()  # poses stood on: none of them is a goal
        self.lo = np.array([RADIUS, RADIUS])  # bounding box of the mapped cells, inclusive
        self.hi = np.array([RADIUS, RADIUS])
        self.scores = np.full((SIZE, SIZE, 4), np.nan, np.float32)  # view_scores of cells, computed as needed
        self.scored_voxels = 0  # the voxel count the scores were computed for
        self.last = None  # (cell, heading, action) of the previous step
        self.recent: list[tuple[int, int, int]] = []  # the last ``stuck_steps`` poses
        self.goal = None  # the pose (map coordinates) it is heading for: kept while it stays a candidate
        self.exact = False  # a frame's floor lay flat: rendered depth, and one frame passing the STOP test is enough
        self.predicted = False  # a frame's floor scattered (and none lay flat): predicted depth, the STOP is earned

    # -- memory ---------------------------------------------------------------------------
    def observe_move(self, cell, heading: int, collided: int) -> None:
        """Block the edge of a move that came back ``collided``; remember the recent poses."""
        pose = (int(cell[0]), int(cell[1]), int(heading))
        self.visited.add(pose)
        self.recent = [*self.recent[-self.config.stuck_steps + 1 :], pose]
        if self.last is None:
            return
        last_cell, last_heading, action = self.last
        if collided and action in MOVE_OFFSET:
            d = (last_heading + MOVE_OFFSET[action]) % 4
            self.edge[d, last_cell[0], last_cell[1]] = False
            self.edge[(d + 2) % 4, last_cell[0] + STEPS[d][0], last_cell[1] + STEPS[d][1]] = False

    def update_map(self, cell, heading: int, p: dict, semantic: np.ndarray) -> None:
        """Add one frame's points (``project``) to the map and the target voxels."""
        cfg = self.config
        x, y, height, rng, valid = p["x"], p["y"], p["height"], p["range"], p["valid"]
        floor = valid & ((height < cfg.floor_high) | (semantic == FLOOR))
        structure = (semantic == FLOOR) | (semantic == CEILING_ID)
        # predicted depth errs in proportion to range: far points and floor pixels do not block
        obstacle = valid & (height > cfg.obstacle_low) & (height < cfg.obstacle_high) & ~structure
        r2 = (cfg.block_radius / CELL) ** 2
        # How far to trust depth: where the floor's pixels lie flat (rendered depth), every range; where they
        # scatter (predicted depth, whose error grows with range), near points block and farther ones cost
        on_floor = valid & (semantic == FLOOR)
        shows_floor = on_floor.sum() >= 50
        flat = shows_floor and np.median(np.abs(height[on_floor])) < cfg.flat_floor
        self.exact |= bool(flat)
        self.predicted |= bool(shows_floor and not flat)
        block_range, soft_range = (np.inf, np.inf) if flat else (cfg.block_range, cfg.obstacle_range)
        # the cells near each point that blocks or costs, found once for both grids
        points = obstacle & (rng < max(block_range, soft_range))
        ox, oy, r = x[points], y[points], rng[points]
        ri, rj = np.rint(ox).astype(int), np.rint(oy).astype(int)
        cells, whose = [], []
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                close = (ri + di - ox) ** 2 + (rj + dj - oy) ** 2 < r2
                cells.append((ri[close] + di) * SIZE + rj[close] + dj)
                whose.append(r[close])
        cells, whose = np.concatenate(cells), np.concatenate(whose)
        # a cell blocks when enough points of the frame lie near it: stray points of predicted depth do not
        for grid, limit in ((self.blocked, block_range), (self.soft, soft_range)):
            counts = np.bincount(cells[whose < limit], minlength=SIZE * SIZE).reshape(SIZE, SIZE)
            grid |= counts >= cfg.min_points
        solid = valid & (height > cfg.obstacle_low) & (height < CEILING)
        np.maximum.at(self.top, (np.rint(x[solid]).astype(int), np.rint(y[solid]).astype(int)), height[solid])
        # free space: along each column's ray up to its nearest obstacle, and every floor point
        reach = np.where(obstacle, rng, np.inf).min(axis=0) - 0.5 * CELL
        seen_floor = np.where(floor, rng, 0.0).max(axis=0)
        reach = np.minimum(reach, np.minimum(np.maximum(seen_floor, 1.0), cfg.max_range))
        t = np.arange(0.0, cfg.max_range, CELL / 2)
        along = t[None, :] <= reach[:, None]
        ray = heading * (np.pi / 2) + self.angles
        fi = np.rint(cell[0] + t[None, :] * np.cos(ray)[:, None] / CELL)[along]
        fj = np.rint(cell[1] + t[None, :] * np.sin(ray)[:, None] / CELL)[along]
        fi = np.concatenate([fi, np.rint(x[floor]), [cell[0]]]).astype(int)
        fj = np.concatenate([fj, np.rint(y[floor]), [cell[1]]]).astype(int)
        self.seen[fi, fj] = True
        self.blocked[cell[0], cell[1]] = self.soft[cell[0], cell[1]] = False  # it stands here
        self.lo = np.minimum(self.lo, [fi.min(), fj.min()])
        self.hi = np.maximum(self.hi, [fi.max(), fj.max()])
        self.memory.add_frame(p, semantic, self.exact)

    @property
    def voxels(self) -> np.ndarray:
        """The target voxels (i, j, k) of VOXEL metres from the map's origin that the approach goes to."""
        return self.memory.voxels

    @property
    def earned(self) -> bool:
        """Whether the STOP is earned: a frame's floor showed predicted depth and none rendered
        (until a frame's floor shows which, the goal rule's own test)."""
        return self.predicted and not self.exact

    # -- decisions ------------------------------------------------------------------------
    def decide(self, cell, heading: int) -> int:
        """The next action: towards the best view of the target if one is known, else the
        nearest frontier, else a random move."""
        lo = np.maximum(self.lo - 2, 0)
        hi = np.minimum(self.hi + 3, SIZE)
        box = (slice(lo[0], hi[0]), slice(lo[1], hi[1]))
        free = self.seen[box] & ~self.blocked[box]
        here = (int(cell[0] - lo[0]), int(cell[1] - lo[1]))
        free[here] = True
        cost = 1.0 + self.config.soft_cost * self.soft[box]
        dist, pred = bfs(free, self.edge[:, box[0], box[1]], here, cost)
        goal = self._approach(dist, lo, heading, self.config.approach_share) if len(self.voxels) else None
        if goal is None:
            goal = self._frontier(free, dist, lo, heading)
        if goal is None and len(self.voxels):
            goal = self._approach(dist, lo, heading, 0.0)
        stuck = len(self.recent) == self.config.stuck_steps and len(set(self.recent)) <= 2
        if goal is None or stuck:
            self.recent = []
            action = int(self.rng.integers(6))
        else:
            action = self._first_action(goal, here, heading, pred)
        self.last = ((int(cell[0]), int(cell[1])), int(heading), action)
        return action

    def _first_action(self, goal, here, heading: int, pred: np.ndarray) -> int:
        """The first action of a cheapest path to ``goal`` ((cell, heading), box coordinates):
        a move, or a turn towards the goal's heading once there. A path that runs
        ``face_run`` cells or more along one direction first turns to face it, so the camera
        sees where the agent goes."""
        (gi, gj), gh = goal
        if (gi, gj) == here:
            return ROTATE_RIGHT if (gh - heading) % 4 == 3 else ROTATE_LEFT
        path = []  # directions, last step first
        w = pred.shape[1]
        step = gi * w + gj
        while step != here[0] * w + here[1]:
            before = int(pred.flat[step])
            path.append(DIRECTION[(step // w - before // w, step % w - before % w)])
            step = before
        k = path[-1]
        run = next((n for n, d in enumerate(reversed(path)) if d != k), len(path))
        if k != heading and run >= self.config.face_run:
            return ROTATE_RIGHT if (k - heading) % 4 == 3 else ROTATE_LEFT
        return ACTION_FOR_OFFSET[(k - heading) % 4]

    def _best(self, cells: np.ndarray, headings: np.ndarray, cost: np.ndarray, lo) -> tuple | None:
        """The cheapest of these poses (box coordinates) not yet visited, or None."""
        keep = np.array(
            [(int(i + lo[0]), int(j + lo[1]), int(h)) not in self.visited for (i, j), h in zip(cells, headings)], bool
        )
        if not keep.any():
            return None
        if self.goal is not None:  # keep going where it was going while that is still a candidate
            mine = (cells[:, 0] + lo[0] == self.goal[0][0]) & (cells[:, 1] + lo[1] == self.goal[0][1])
            mine &= (headings == self.goal[1]) & keep
            if mine.any():
                return (int(cells[mine][0][0]), int(cells[mine][0][1])), int(self.goal[1])
        order = np.lexsort((headings[keep], cells[keep][:, 1], cells[keep][:, 0], cost[keep]))
        n = order[0]
        (i, j), h = cells[keep][n], int(headings[keep][n])
        self.goal = (int(i + lo[0]), int(j + lo[1])), h
        return (int(i), int(j)), h

    def _frontier(self, free, dist, lo, heading: int):
        """The nearest frontier pose: a reachable free cell facing an unseen, unblocked one."""
        box = (slice(lo[0], lo[0] + free.shape[0]), slice(lo[1], lo[1] + free.shape[1]))
        unknown = ~(self.seen[box] | self.blocked[box] | self.soft[box])
        cells, headings = [], []
        for k in range(4):
            here, beside = neighbours(k, free.shape)
            facing = np.zeros(free.shape, bool)  # the neighbour along k is unknown
            facing[here] = unknown[beside]
            ij = np.argwhere(facing & (dist >= 0))
            cells.append(ij)
            headings.append(np.full(len(ij), k))
        cells, headings = np.concatenate(cells), np.concatenate(headings)
        cost = dist[cells[:, 0], cells[:, 1]] + turns(heading, headings)
        if len(cells):
            cost = self.frontier_cost(cells + lo, cost)
        extra = self.extra_goals(dist, lo, heading)
        if extra is not None:
            cells, headings, cost = (np.concatenate(pair) for pair in zip((cells, headings, cost), extra))
        if not len(cells):
            return None
        return self._best(cells, headings, cost, lo)

    def frontier_cost(self, cells: np.ndarray, cost: np.ndarray) -> np.ndarray:
        """What choosing each frontier pose costs (``cells``: map coordinates, ``cost``: steps to
        it); the cheapest is explored. A hook: ``grg_frontier`` takes off a relation bonus."""
        return cost

    def extra_goals(self, dist: np.ndarray, lo, heading: int) -> tuple | None:
        """Poses to weigh beside the frontier poses: (cells (box coordinates), headings, costs), or
        None. A hook: ``object_prior_frontier`` adds close views of furniture the target stands by."""
        return None

    def _approach(self, dist, lo, heading: int, share: float):
        """The cheapest unvisited pose whose view of the target voxels scores at least ``share``
        of the best reachable pose's (``view_scores``)."""
        cfg = self.config
        reach = np.argwhere(dist >= 0)
        centres = (reach + lo) * CELL  # metres from the map's origin
        stride = max(1, len(self.voxels) // 200)
        vox = self.voxels[::stride]
        columns = np.unique(np.rint((vox[:, :2] + 0.5) * (VOXEL / CELL)), axis=0) * CELL
        near = ((centres[:, None, :] - columns[None, :, :]) ** 2).sum(-1).min(1) <= cfg.approach_radius**2
        if not near.any():
            return None
        cand = reach[near] + lo  # map coordinates
        if len(self.voxels) > 1.1 * self.scored_voxels:  # the target has grown: score afresh
            self.scores[:] = np.nan
            self.scored_voxels = len(self.voxels)
        todo = np.isnan(self.scores[cand[:, 0], cand[:, 1], 0])
        if todo.any():
            self.scores[cand[todo, 0], cand[todo, 1]] = stride * view_scores(cand[todo], vox, self.top, self.camera)
        score = self.scores[cand[:, 0], cand[:, 1]]  # (C, 4)
        cand = cand - lo
        best = score.max()
        if best <= 0:
            return None
        ci, hi = np.nonzero(score >= max(share * best, 1e-9))
        cells = cand[ci]
        return self._best(cells, hi, dist[cells[:, 0], cells[:, 1]] + turns(heading, hi), lo)


class FrontierAgent(OneSlotBatch):
    """Frontier exploration with approach on sight (``objsearch-eval --agent frontier``)."""

    config = FrontierConfig()
    # nothing learned (its subclasses that count a prior on training houses neither): the board
    # shows no training runs (objsearch.eval.registry.is_training_free)
    training_free = True

    @classmethod
    def worlds(cls) -> tuple[str, ...]:
        return ("house",)

    # the single-episode form is the batched one with one slot (OneSlotBatch)
    def start_batch(self, num_slots: int) -> None:
        self._slots: list[SlotState | None] = [None] * num_slots
        self._camera = None

    def reset_batch(self, tasks: dict) -> None:
        for i, task in tasks.items():
            if task.camera is None:
                raise ValueError(f"suite {task.suite!r} gives no camera parameters; the frontier agent needs them")
            self._camera = task.camera
            self._slots[i] = self.new_slot(task)

    def new_slot(self, task: AgentTask) -> SlotState:
        """One episode's state (a hook: subclasses keep more)."""
        return SlotState(task, self.config)

    def act_batch(self, observations: dict) -> dict:
        slots = list(observations)
        obs = [observations[i] for i in slots]
        pose = np.stack([np.asarray(o["pose"], np.float64) for o in obs])
        cell = RADIUS + np.rint(pose[:, :2] / CELL).astype(int)
        heading = np.rint(pose[:, 2] / (np.pi / 2)).astype(int) % 4
        points = project(np.stack([o["depth"] for o in obs]), pose, self._camera)
        actions = {}
        for n, i in enumerate(slots):
            state = self._slots[i]
            memory = state.memory
            memory.target = int(obs[n]["target"])
            state.observe_move(cell[n], heading[n], int(obs[n]["collided"]))
            frame = {k: v[n] for k, v in points.items()}
            semantic, depth = np.asarray(obs[n]["semantic"]), np.asarray(obs[n]["depth"])
            state.update_map(cell[n], heading[n], frame, semantic)
            if memory.sees_goal(cell[n], frame, semantic, depth, state.earned):
                actions[i] = memory.stop_action
            else:
                actions[i] = state.decide(cell[n], heading[n])
        return actions
