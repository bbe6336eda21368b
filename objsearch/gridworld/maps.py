"""Grid-world maps of the HRL-GRG paper: generation, validation and the map file format.

A map is a 16x16 grid whose border is obstacle, with 16 goals on distinct free cells. The
goals form two chains, g0..g7 and g8..g15: g0 and g8 are placed anywhere free, and every
other g(i) lies inside the 7x7 window centred on g(i-1) but not in its inner 3x3 (the
published maps always have Chebyshev distance 2 or 3 between chain neighbours). All goals
are mutually reachable (4-connected), as in the maps the authors published with their code.

File format (a directory of maps): ``map_XXXX.npz`` with
``obstacles``: uint8 HxW, 1 = obstacle, and ``goals``: int Gx2 (row, col), index = goal id.
"""

from __future__ import annotations

import os
import zipfile
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import atomic_write

SIZE = 16
NUM_GOALS = 16
CHAIN_STARTS = (0, 8)
# The published maps have 51-63 obstacle cells among the 196 interior cells.
INTERIOR_OBSTACLES = (51, 63)
MAX_GENERATION_TRIES = 1000

# Actions: up, down, left, right as (drow, dcol).
MOVES = np.array([[-1, 0], [1, 0], [0, -1], [0, 1]], dtype=np.int64)
UNREACHABLE = -1


@dataclass(frozen=True, eq=False)
class GridMap:
    """One grid-world map.

    Attributes:
        name: the file stem, e.g. ``map_0105``; tasks refer to maps by it.
        obstacles: uint8 array (H, W), 1 = obstacle.
        goals: int64 array (G, 2) of (row, col); row index = goal id.
    """

    name: str
    obstacles: np.ndarray
    goals: np.ndarray

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W) of the map."""
        return self.obstacles.shape

    @property
    def num_goals(self) -> int:
        """Number of goals on the map."""
        return len(self.goals)

    def distances_to(self, cell: tuple[int, int]) -> np.ndarray:
        """Minimal steps from every cell to ``cell`` (4-connected BFS; -1 = unreachable)."""
        return bfs_distances(self.obstacles, cell)


def bfs_distances(obstacles: np.ndarray, source: tuple[int, int]) -> np.ndarray:
    """4-connected BFS distances over free cells from ``source`` (-1 where unreachable).

    Moves are symmetric, so this is also the distance from every cell *to* ``source``.
    """
    height, width = obstacles.shape
    dist = np.full((height, width), UNREACHABLE, dtype=np.int64)
    r0, c0 = int(source[0]), int(source[1])
    if obstacles[r0, c0]:
        return dist
    dist[r0, c0] = 0
    queue = deque([(r0, c0)])
    while queue:
        r, c = queue.popleft()
        for dr, dc in MOVES:
            nr, nc = r + dr, c + dc
            if 0 <= nr < height and 0 <= nc < width and not obstacles[nr, nc] and dist[nr, nc] < 0:
                dist[nr, nc] = dist[r, c] + 1
                queue.append((nr, nc))
    return dist


def _place_goals(obstacles: np.ndarray, rng: np.random.Generator) -> np.ndarray | None:
    free = np.argwhere(obstacles == 0)
    goals = np.zeros((NUM_GOALS, 2), dtype=np.int64)
    taken: set[tuple[int, int]] = set()
    for i in range(NUM_GOALS):
        if i in CHAIN_STARTS:
            candidates = [tuple(cell) for cell in free]
        else:
            pr, pc = goals[i - 1]
            candidates = [(r, c) for r, c in free if max(abs(r - pr), abs(c - pc)) in (2, 3)]
        candidates = [cell for cell in candidates if cell not in taken]
        if not candidates:
            return None
        cell = candidates[rng.integers(len(candidates))]
        goals[i] = cell
        taken.add((int(cell[0]), int(cell[1])))
    dist = bfs_distances(obstacles, tuple(goals[0]))
    if np.any(dist[goals[:, 0], goals[:, 1]] < 0):
        return None
    return goals


def generate_map(rng: np.random.Generator, name: str = "map") -> GridMap:
    """Generate one map: border obstacles, 51-63 interior obstacles, two goal chains.

    A draw whose goals cannot be placed or are not mutually reachable is redrawn, at most
    ``MAX_GENERATION_TRIES`` times (in practice a handful).
    """
    interior = [(r, c) for r in range(1, SIZE - 1) for c in range(1, SIZE - 1)]
    for _ in range(MAX_GENERATION_TRIES):
        obstacles = np.ones((SIZE, SIZE), dtype=np.uint8)
        obstacles[1:-1, 1:-1] = 0
        count = int(rng.integers(INTERIOR_OBSTACLES[0], INTERIOR_OBSTACLES[1] + 1))
        for k in rng.choice(len(interior), size=count, replace=False):
            obstacles[interior[k]] = 1
        goals = _place_goals(obstacles, rng)
        if goals is not None:
            return GridMap(name=name, obstacles=obstacles, goals=goals)
    raise RuntimeError(f"no valid map after {MAX_GENERATION_TRIES} tries")


def validate_map(grid_map: GridMap, source: str) -> None:
    """Raise ``UserError`` naming ``source`` if the map breaks the file format's rules."""
    obstacles, goals = grid_map.obstacles, grid_map.goals
    if obstacles.ndim != 2 or obstacles.dtype != np.uint8 or not np.isin(obstacles, (0, 1)).all():
        raise UserError(f"{source}: 'obstacles' must be a 2-D uint8 array of 0/1")
    if goals.ndim != 2 or goals.shape[1] != 2 or not np.issubdtype(goals.dtype, np.integer):
        raise UserError(f"{source}: 'goals' must be an integer array of shape (G, 2) (row, col)")
    height, width = obstacles.shape
    for goal_id, (r, c) in enumerate(goals):
        if not (0 <= r < height and 0 <= c < width):
            raise UserError(f"{source}: goal {goal_id} at ({r}, {c}) lies outside the {height}x{width} map")
        if obstacles[r, c]:
            raise UserError(f"{source}: goal {goal_id} at ({r}, {c}) is on an obstacle")
    if len({(int(r), int(c)) for r, c in goals}) != len(goals):
        raise UserError(f"{source}: two goals share a cell; goals must be on distinct cells")


def load_map(path: str | os.PathLike) -> GridMap:
    """Load and validate one ``map_XXXX.npz`` file."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            obstacles, goals = data["obstacles"], data["goals"]
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as err:
        raise UserError(f"cannot read map file {path}: {err}; expected an .npz with 'obstacles' and 'goals'") from None
    except KeyError as err:
        raise UserError(
            f"map file {path} has no array {err}; expected 'obstacles' (uint8 HxW) and 'goals' (int Gx2)"
        ) from None
    grid_map = GridMap(name=path.stem, obstacles=obstacles, goals=goals.astype(np.int64))
    validate_map(grid_map, str(path))
    return grid_map


def load_map_dir(directory: str | os.PathLike) -> dict[str, GridMap]:
    """Load every ``map_*.npz`` in ``directory``, keyed and sorted by name."""
    directory = Path(directory)
    if not directory.is_dir():
        raise UserError(f"map directory {directory} does not exist; pass a directory of map_XXXX.npz files")
    paths = sorted(directory.glob("map_*.npz"))
    if not paths:
        raise UserError(f"map directory {directory} holds no map_*.npz files")
    return {path.stem: load_map(path) for path in paths}


def save_map(grid_map: GridMap, directory: str | os.PathLike) -> Path:
    """Write ``directory/<name>.npz`` atomically (temp file, then rename)."""
    path = Path(directory) / f"{grid_map.name}.npz"
    with atomic_write(path, "wb") as f:
        np.savez_compressed(f, obstacles=grid_map.obstacles.astype(np.uint8), goals=grid_map.goals.astype(np.int64))
    return path


def shortest_path_actions(
    obstacles: np.ndarray, start: tuple[int, int], goal: tuple[int, int], dist: np.ndarray | None = None
) -> list[int]:
    """Actions (indices into ``MOVES``) of one shortest path from ``start`` to ``goal``.

    Ties are broken by action order (up, down, left, right), so the path is deterministic.
    ``dist``: the goal's ``bfs_distances`` if already at hand (e.g. ``GridTables.goal_distances``).
    """
    if dist is None:
        dist = bfs_distances(obstacles, goal)
    height, width = dist.shape
    d = dist.tolist()  # Python lists: the walk reads one cell at a time
    r, c = int(start[0]), int(start[1])
    if d[r][c] < 0:
        raise ValueError(f"goal {goal} cannot be reached from {start}")
    actions = []
    while d[r][c] > 0:
        for a, (dr, dc) in enumerate(_MOVE_LIST):
            nr, nc = r + dr, c + dc
            if 0 <= nr < height and 0 <= nc < width and d[nr][nc] == d[r][c] - 1:
                actions.append(a)
                r, c = nr, nc
                break
    return actions


_MOVE_LIST = [tuple(move) for move in MOVES.tolist()]
