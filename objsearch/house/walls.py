"""Walls, the one wall builder of every generator: each room's edges become boxes of half the
wall thickness on the room's side, cut at the doors; edges on the footprint boundary get a
second half outside (the house's outer skin, room -1), cut at an entrance door too, so an
entrance is a real opening through the outer wall.
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


def build_walls(
    room_edges: list[list[Edge]],
    doors: list[Door],
    footprint: tuple[float, float],
    thickness: float,
    height: float,
    wall_materials: list[str],
    exterior_material: str,
) -> list[Wall]:
    """The walls of every room (inner half-walls, outer ones on the footprint edge), cut at the
    doors, from each room's edges (``gen1.doors.rect_edges`` of a rectangle, ``gen2.doors.edges`` of a polygon) in the
    order given: the order numbers the walls."""
    t = thickness / 2
    width, depth = footprint
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
            end = width if axis == "x" else depth
            exterior = abs(fixed) < 1e-6 or abs(fixed - (depth if axis == "x" else width)) < 1e-6
            for a, b in _cut(lo, hi, holes):
                f0, f1 = sorted((fixed, fixed + side * t))
                add(rid, (a, f0, b, f1) if axis == "x" else (f0, a, f1, b), wall_materials[rid])
                if exterior:
                    g0, g1 = sorted((fixed, fixed - side * t))
                    a2 = a - t if a <= 1e-6 else a
                    b2 = b + t if b >= end - 1e-6 else b
                    add(-1, (a2, g0, b2, g1) if axis == "x" else (g0, a2, g1, b2), exterior_material)
    return walls
