"""Where an agent can stand: occupancy grids of a house for a cylinder agent.

``occupancy_grid(spec, resolution, agent_radius)`` rasterises walls and every object whose
bottom is below ``agent_height`` (things on receptacles lie inside their receptacle's
footprint; wall-mounted things above the agent do not block it) and returns the cells
where the agent's *centre* may be: at least ``agent_radius + resolution / 2`` from every
obstacle cell centre (the half cell makes it conservative). Validation uses a fine grid
(0.05 m); navigation can use its own resolution (e.g. 0.2 m cells) or sample this grid.
Rows run along y, columns along x; cell (r, c) has its centre at
``origin + ((c + 0.5) * resolution, (r + 0.5) * resolution)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from objsearch.house.spec import HouseSpec

AGENT_RADIUS = 0.2
AGENT_HEIGHT = 1.6


@dataclass(frozen=True)
class OccupancyGrid:
    """Where the agent can stand: cells of ``resolution`` metres from ``origin`` (row = y, col = x)."""

    free: np.ndarray  # bool (rows, cols): the agent's centre may be here
    obstacles: np.ndarray  # bool (rows, cols): a wall or object covers the cell centre
    origin: tuple[float, float]
    resolution: float
    agent_radius: float

    def centers(self) -> tuple[np.ndarray, np.ndarray]:
        """World x (cols,) and y (rows,) of cell centres."""
        rows, cols = self.free.shape
        return (
            self.origin[0] + (np.arange(cols) + 0.5) * self.resolution,
            self.origin[1] + (np.arange(rows) + 0.5) * self.resolution,
        )

    def cell(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the cell containing world point (x, y)."""
        return int((y - self.origin[1]) // self.resolution), int((x - self.origin[0]) // self.resolution)

    def is_free(self, x: float, y: float) -> bool:
        """Whether the agent's centre may be at world point (x, y) (False off the grid)."""
        r, c = self.cell(x, y)
        rows, cols = self.free.shape
        return 0 <= r < rows and 0 <= c < cols and bool(self.free[r, c])


def _fill(mask: np.ndarray, box, origin, res) -> None:
    """Mark cells whose centres lie inside the axis-aligned box (x0, y0, x1, y1)."""
    x0, y0, x1, y1 = box
    c0 = max(int(np.ceil((x0 - origin[0]) / res - 0.5)), 0)
    c1 = min(int(np.floor((x1 - origin[0]) / res - 0.5)), mask.shape[1] - 1)
    r0 = max(int(np.ceil((y0 - origin[1]) / res - 0.5)), 0)
    r1 = min(int(np.floor((y1 - origin[1]) / res - 0.5)), mask.shape[0] - 1)
    if c1 >= c0 and r1 >= r0:
        mask[r0 : r1 + 1, c0 : c1 + 1] = True


def obstacle_mask(spec: HouseSpec, resolution: float, agent_height: float = AGENT_HEIGHT):
    """Bool (rows, cols) mask of cells under walls and objects below ``agent_height``, and its origin."""
    width, depth = spec.footprint
    origin = (0.0, 0.0)
    shape = (int(np.ceil(depth / resolution)), int(np.ceil(width / resolution)))
    mask = np.zeros(shape, dtype=bool)
    for w in spec.walls:
        _fill(mask, w.box, origin, resolution)
    for o in spec.objects:
        if o.position[2] < agent_height:
            _fill(mask, o.footprint, origin, resolution)
    if sum(r.area for r in spec.rooms) < 0.999 * width * depth:  # an L, T or U: outside its rooms is no floor
        mask |= ~_inside_rooms(spec, shape, resolution)
    return mask, origin


def _inside_rooms(spec: HouseSpec, shape: tuple[int, int], res: float) -> np.ndarray:
    """Bool (rows, cols): cell centres inside some room (each room's rectilinear polygon by the
    even-odd rule over its vertical edges)."""
    ys = (np.arange(shape[0]) + 0.5) * res
    xs = (np.arange(shape[1]) + 0.5) * res
    inside = np.zeros(shape, dtype=bool)
    for r in spec.rooms:
        room = np.zeros(shape, dtype=bool)
        poly = r.polygon
        for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]):
            if x0 != x1:
                continue
            rows = (ys >= min(y0, y1)) & (ys < max(y0, y1))
            room[np.ix_(rows, xs < x0)] ^= True
        inside |= room
    return inside


def occupancy_grid(
    spec: HouseSpec, resolution: float = 0.05, agent_radius: float = AGENT_RADIUS, agent_height: float = AGENT_HEIGHT
) -> OccupancyGrid:
    """The house's occupancy grid: free cells at least ``agent_radius`` (plus half a cell) from any obstacle."""
    mask, origin = obstacle_mask(spec, resolution, agent_height)
    # Border of the grid counts as obstacle too (nothing outside the footprint is reachable).
    padded = np.pad(~mask, 1, constant_values=False).astype(np.uint8)
    dist = cv2.distanceTransform(padded, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[1:-1, 1:-1]
    free = dist * resolution >= agent_radius + resolution / 2
    return OccupancyGrid(free, mask, origin, resolution, agent_radius)


def components(free: np.ndarray) -> tuple[int, np.ndarray]:
    """8-connected components of free cells: (count including background 0, labels)."""
    n, labels = cv2.connectedComponents(free.astype(np.uint8), connectivity=8)
    return n, labels
