"""What a room keeps free, whatever its generator: the floor in front of its doors, a passage
along a corridor, the notches of an L-shaped room; and a layout over a whole room with them.

``house-gen-2``'s furnishing (``gen2.furnish``) and the shuffled placement (``shuffle``, for
the houses of every generator) keep these free; ``house-gen-1`` keeps its doors free with
``DOOR_CLEARANCE`` too.
"""

from __future__ import annotations

from objsearch.house.layout import HouseContext, RoomLayout
from objsearch.house.spec import Door, Room, r4

DOOR_CLEARANCE = 0.9  # free depth kept in front of a door
NARROW = 1.6  # parts of an L narrower than this stay free (a passage, not a place for things)
PASSAGE = 0.75  # free width kept along a corridor's middle
NARROW_HALLWAY = 2.4  # a hallway narrower than this keeps the passage


def inward(room_polygon, door: Door, depth: float = 0.05) -> tuple[float, float]:
    """The unit direction (dx, dy) from ``door``'s centre into the room of ``room_polygon``."""
    room = Room(0, "", room_polygon, "", "")
    cx, cy = door.center
    if door.axis == "x":
        return (0.0, 1.0) if room.contains(cx, cy + depth) else (0.0, -1.0)
    return (1.0, 0.0) if room.contains(cx + depth, cy) else (-1.0, 0.0)


def notches(room: Room) -> list[tuple[float, float, float, float]]:
    """The parts (x0, y0, x1, y1) of the room's bounding box that are outside its polygon."""
    if len(room.polygon) == 4:
        return []
    xs = sorted({p[0] for p in room.polygon})
    ys = sorted({p[1] for p in room.polygon})
    return [
        (x0, y0, x1, y1)
        for y0, y1 in zip(ys, ys[1:])
        for x0, x1 in zip(xs, xs[1:])
        if not room.contains((x0 + x1) / 2, (y0 + y1) / 2)
    ]


def door_keepouts(L: RoomLayout, room: Room, doors: list[Door]) -> None:
    """Keep the floor in front of every door of ``room`` free, full height, on the room's side."""
    for d in doors:
        if room.id not in d.rooms:
            continue
        cx, cy = d.center
        w = d.width / 2 + 0.1
        dx, dy = inward(room.polygon, d)
        if d.axis == "x":
            y0, y1 = sorted((cy, cy + dy * DOOR_CLEARANCE))
            L.block((cx - w, y0, 0.0, cx + w, y1, 10.0))
        else:
            x0, x1 = sorted((cx, cx + dx * DOOR_CLEARANCE))
            L.block((x0, cy - w, 0.0, x1, cy + w, 10.0))


def passage(L: RoomLayout, rect) -> None:
    """Keep a ``PASSAGE``-wide strip free along the middle of ``rect`` (x0, y0, x1, y1), the long way."""
    x0, y0, x1, y1 = rect
    if x1 - x0 >= y1 - y0:
        m = (y0 + y1) / 2
        L.block((x0, m - PASSAGE / 2, 0.0, x1, m + PASSAGE / 2, 10.0))
    else:
        m = (x0 + x1) / 2
        L.block((m - PASSAGE / 2, y0, 0.0, m + PASSAGE / 2, y1, 10.0))


def shrunk(rect, h: float):
    """``rect`` (x0, y0, x1, y1) less ``h`` on every side: a room's interior within its walls."""
    x0, y0, x1, y1 = rect
    return (r4(x0 + h), r4(y0 + h), r4(x1 - h), r4(y1 - h))


def whole_layout(ctx: HouseContext, room: Room, doors: list[Door], wall_height: float, h: float, blocks) -> RoomLayout:
    """A layout over the room's whole bounding box, its notches blocked (and ``blocks``, or its door keep-outs)."""
    L = RoomLayout(ctx, room.id, room.type, shrunk(room.bounds, h), wall_height)
    if blocks:
        L.blocks = list(blocks)
    else:
        door_keepouts(L, room, doors)
    for nx0, ny0, nx1, ny1 in notches(room):
        L.block((nx0 - h, ny0 - h, 0.0, nx1 + h, ny1 + h, 10.0))
    return L
