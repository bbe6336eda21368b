"""Stages 4-5 of ``house-gen-1``: every rectangle room furnished by ``objsearch.house.groups``
(its functional groups, then the fill of its type), the floor in front of its doors kept free.
"""

from __future__ import annotations

from objsearch.house.clearances import DOOR_CLEARANCE
from objsearch.house.groups import furnish_room
from objsearch.house.layout import HouseContext, RoomLayout
from objsearch.house.spec import Door, ObjectInstance


def door_keepouts(L: RoomLayout, room_bounds, doors: list[Door]) -> None:
    """Keep the floor in front of every door of this room free, full height."""
    rx0, ry0, rx1, ry1 = room_bounds
    for d in doors:
        if L.room_id not in d.rooms:
            continue
        cx, cy = d.center
        w = d.width / 2 + 0.1
        if d.axis == "x":
            y_in = (cy - DOOR_CLEARANCE, cy) if abs(cy - ry1) < 1e-6 else (cy, cy + DOOR_CLEARANCE)
            L.block((cx - w, y_in[0], 0.0, cx + w, y_in[1], 10.0))
        else:
            x_in = (cx - DOOR_CLEARANCE, cx) if abs(cx - rx1) < 1e-6 else (cx, cx + DOOR_CLEARANCE)
            L.block((x_in[0], cy - w, 0.0, x_in[1], cy + w, 10.0))


def furnish(ctx: HouseContext, rooms, interiors, doors: list[Door], wall_height: float) -> list[ObjectInstance]:
    """Furnish every room of the house (door keep-outs first) and return all objects placed."""
    types = [r.type for r in rooms]
    for room, interior in zip(rooms, interiors):
        L = RoomLayout(ctx, room.id, room.type, interior, wall_height)
        door_keepouts(L, room.bounds, doors)
        furnish_room(L, types)
    return ctx.objects
