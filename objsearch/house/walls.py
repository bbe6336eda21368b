"""Walls, the one wall builder of every generator: each room's edges become boxes of half the
wall thickness on the room's side, cut at the doors; edges on the house's outline get a
second half outside (the house's outer skin, room -1), cut at an entrance door too, so an
entrance is a real opening through the outer wall. The outline is the footprint rectangle
unless a generator passes another (``house-gen-4``'s L, T and U houses); the outer skin runs
on past the outline's convex corners, so that it closes there.
"""

from __future__ import annotations

from objsearch.house.spec import Door, Wall, r4

# (axis the edge runs along, fixed coordinate, lo, hi, side): side +1 when the room lies on
# the + side of the edge (above an ``x`` edge, east of a ``y`` edge), -1 otherwise
Edge = tuple[str, float, float, float, int]


def _cut(lo: float, hi: float, holes: list[tuple[float, float]]) -> list[tuple[float, float]]:
    pieces, cur = [], lo
    for a, b in sorted(holes):
        if a > cur:
            pieces.append((cur, a))
        cur = max(cur, b)
    if hi > cur:
        pieces.append((cur, hi))
    return [(a, b) for a, b in pieces if b - a > 1e-6]


def _outline_sides(outline) -> tuple[list[tuple[str, float, float, float]], list[tuple[float, float]]]:
    """The sides (axis, fixed, lo, hi) of a counter-clockwise rectilinear ``outline`` and its
    convex corners."""
    sides, convex = [], []
    n = len(outline)
    for k in range(n):
        (xa, ya), (xb, yb), (xc, yc) = outline[k - 1], outline[k], outline[(k + 1) % n]
        if (xb - xa) * (yc - yb) - (yb - ya) * (xc - xb) > 0:  # a left turn: convex, counter-clockwise
            convex.append((xb, yb))
        (x0, y0), (x1, y1) = outline[k], outline[(k + 1) % n]
        sides.append(("x", y0, min(x0, x1), max(x0, x1)) if y0 == y1 else ("y", x0, min(y0, y1), max(y0, y1)))
    return sides, convex


def build_walls(
    room_edges: list[list[Edge]],
    doors: list[Door],
    footprint: tuple[float, float],
    thickness: float,
    height: float,
    wall_materials: list[str],
    exterior_material: str,
    outline: tuple[tuple[float, float], ...] | None = None,
) -> list[Wall]:
    """The walls of every room (inner half-walls, outer ones on the outline), cut at the
    doors, from each room's edges (``gen1.doors.rect_edges`` of a rectangle, ``gen2.doors.edges`` of a polygon) in the
    order given: the order numbers the walls. ``outline``: the house's counter-clockwise outline
    (None: the footprint's rectangle)."""
    t = thickness / 2
    width, depth = footprint
    sides, convex = _outline_sides(outline or ((0.0, 0.0), (width, 0.0), (width, depth), (0.0, depth)))
    walls: list[Wall] = []

    def add(room, box, material):
        walls.append(Wall(len(walls), room, tuple(r4(v) for v in box), height, material))

    for rid, edges in enumerate(room_edges):
        for axis, fixed, lo, hi, side in edges:
            holes = []
            for d in doors:
                if rid not in d.rooms or d.axis != axis:
                    continue
                c_fixed, c_along = (d.center[1], d.center[0]) if axis == "x" else (d.center[0], d.center[1])
                if abs(c_fixed - fixed) < 1e-6 and lo < c_along < hi:
                    holes.append((c_along - d.width / 2, c_along + d.width / 2))
            outer = [(s0, s1) for ax, f, s0, s1 in sides if ax == axis and abs(f - fixed) < 1e-6]
            for a, b in _cut(lo, hi, holes):
                f0, f1 = sorted((fixed, fixed + side * t))
                add(rid, (a, f0, b, f1) if axis == "x" else (f0, a, f1, b), wall_materials[rid])
                for s0, s1 in outer:
                    a1, b1 = max(a, s0), min(b, s1)
                    if b1 - a1 <= 1e-6:
                        continue
                    g0, g1 = sorted((fixed, fixed - side * t))
                    a2 = a1 - t if _corner(a1, fixed, axis, convex) else a1
                    b2 = b1 + t if _corner(b1, fixed, axis, convex) else b1
                    add(-1, (a2, g0, b2, g1) if axis == "x" else (g0, a2, g1, b2), exterior_material)
    return walls


def _corner(along: float, fixed: float, axis: str, convex: list[tuple[float, float]]) -> bool:
    """Whether the point ``along`` an edge on line ``fixed`` is a convex corner of the outline."""
    x, y = (along, fixed) if axis == "x" else (fixed, along)
    return any(abs(x - cx) < 1e-6 and abs(y - cy) < 1e-6 for cx, cy in convex)
