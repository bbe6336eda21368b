"""Stage 3 of ``house-gen-1``: doors (so that every room can be reached), and the edges of its rectangle rooms.

Door rules (after ProcTHOR's): rooms that share a wall long enough for a door are
neighbours. A spanning tree over neighbours is grown from the living room, cheapest edge
first, where public rooms (living, kitchen, dining, hallway) connect cheaply to each other,
private rooms (bedroom, office, bathroom) hang off public ones, two private rooms connect
only when nothing else does (an en-suite bedroom-bathroom is mildly preferred over that),
and a bathroom is almost never a passage to another room. Extra doors then join some
neighbouring public rooms (open plan). Doors are ``DOOR_WIDTH`` wide (>= 0.9 m), at least
``DOOR_MARGIN`` from the ends of the shared wall.

Walls: ``objsearch.house.walls.build_walls`` over ``rect_edges`` of each room (every side a
box of half the wall thickness inside that room, door openings cut out, an outer skin on the
footprint boundary).
"""

from __future__ import annotations

import numpy as np

from objsearch.house.spec import Door, r4
from objsearch.house.stages import StageFailure
from objsearch.house.walls import Edge

DOOR_WIDTH = (0.9, 1.1)
DOOR_HEIGHT = 2.1
DOOR_MARGIN = 0.3
PUBLIC = {"living_room", "kitchen", "dining_room", "hallway"}

Rect = tuple[float, float, float, float]


def shared_wall(a: Rect, b: Rect, eps: float = 1e-6):
    """(axis, fixed coordinate, lo, hi) of the wall a and b share, or None."""
    for axis, (ia, ib) in (("y", (2, 0)), ("y", (0, 2)), ("x", (3, 1)), ("x", (1, 3))):
        if abs(a[ia] - b[ib]) < eps:
            if axis == "y":  # vertical wall at x = const, running along y
                lo, hi = max(a[1], b[1]), min(a[3], b[3])
            else:
                lo, hi = max(a[0], b[0]), min(a[2], b[2])
            if hi - lo > eps:
                return axis, a[ia], lo, hi
    return None


def _edge_cost(ta: str, tb: str) -> float:
    pa, pb = ta in PUBLIC, tb in PUBLIC
    if pa and pb:
        return 1.0
    if pa or pb:
        return 2.0 if "bathroom" not in (ta, tb) or "hallway" in (ta, tb) or "living_room" in (ta, tb) else 5.0
    if {ta, tb} == {"bedroom", "bathroom"}:
        return 3.0
    return 6.0


def place_doors(rects: list[Rect], types: list[str], rng: np.random.Generator, thickness: float) -> list[Door]:
    """Doors connecting every room: a spanning tree from the living room over shared walls, plus some
    extra doors between public rooms.

    Raises ``StageFailure`` if the rooms cannot all be connected (no shared wall long enough).
    """
    n = len(rects)
    need = DOOR_WIDTH[1] + 2 * DOOR_MARGIN + thickness
    nbrs: dict[tuple[int, int], tuple] = {}
    for i in range(n):
        for j in range(i + 1, n):
            s = shared_wall(rects[i], rects[j])
            if s and s[3] - s[2] >= need:
                nbrs[(i, j)] = s
    # Prim's algorithm from the living room.
    root = types.index("living_room")
    in_tree = {root}
    edges: list[tuple[int, int]] = []
    noise = {e: rng.uniform(0, 0.5) for e in sorted(nbrs)}
    while len(in_tree) < n:
        best = None
        for i, j in sorted(nbrs):
            if (i in in_tree) == (j in in_tree):
                continue
            inside = i if i in in_tree else j
            cost = _edge_cost(types[i], types[j]) + noise[(i, j)] + (20.0 if types[inside] == "bathroom" else 0.0)
            if best is None or cost < best[0]:
                best = (cost, (i, j))
        if best is None:
            raise StageFailure("rooms cannot all be connected by doors (no shared wall long enough)")
        edges.append(best[1])
        in_tree.update(best[1])
    for i, j in sorted(nbrs):
        if (i, j) not in edges and types[i] in PUBLIC and types[j] in PUBLIC and rng.random() < 0.4:
            edges.append((i, j))
    doors = []
    for k, (i, j) in enumerate(edges):
        axis, fixed, lo, hi = nbrs[(i, j)]
        width = r4(round(rng.uniform(*DOOR_WIDTH), 2))
        pad = DOOR_MARGIN + thickness / 2 + width / 2
        c = r4(round(rng.uniform(lo + pad, hi - pad), 2))
        # ``axis`` from shared_wall names the wall's *normal* side; Door.axis is its direction.
        if axis == "y":  # wall at x = fixed runs along y
            doors.append(Door(k, (i, j), "y", (r4(fixed), c), width, DOOR_HEIGHT))
        else:
            doors.append(Door(k, (i, j), "x", (c, r4(fixed)), width, DOOR_HEIGHT))
    return doors


def rect_edges(rect: Rect) -> list[Edge]:
    """The 4 edges of a rectangle room, in ``house-gen-1``'s wall order: bottom, top, left, right."""
    x0, y0, x1, y1 = rect
    return [("x", y0, x0, x1, 1), ("x", y1, x0, x1, -1), ("y", x0, y0, y1, 1), ("y", x1, y0, y1, -1)]
