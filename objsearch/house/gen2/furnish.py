"""Stages 4-5 of ``house-gen-2``: the furniture groups and fill of ``objsearch.house.groups``, in rooms of any
rectilinear shape, topped up so that the number of objects follows the room's area.

* The groups go into the room's largest rectangle (``main_rect``); the top-up then sees the
  whole room: its bounding box less its walls, with the parts of the box outside the room
  (the notch of an L) blocked, grown by the wall, so nothing stands in them.
* Door keep-outs (``objsearch.house.clearances``) lie on the room's side of each door, found with the room's polygon (an L has
  doors on edges that are not on its bounding box).
* A corridor keeps a free passage along its middle (``PASSAGE`` wide).
* Large kitchens get a table with chairs (``KITCHEN_TABLE``), so a kitchen is not an empty floor.
* Fill: after the groups and the per-type fill (``groups.furnish_room``), categories of the room's type
  (weighted by their affinity) are tried until the room holds ``FILL_DENSITY`` objects per
  square metre; small objects go onto the receptacles their category names (``parents``).
"""

from __future__ import annotations

import math

from objsearch.house import groups
from objsearch.house.categories import CATEGORIES
from objsearch.house.clearances import NARROW, NARROW_HALLWAY, door_keepouts, passage, shrunk, whole_layout
from objsearch.house.groups import BED_CORRIDOR, dining_group, furnish_room, toilet_and_sink, tub_with_towel
from objsearch.house.layout import HouseContext, RoomLayout
from objsearch.house.spec import Door, ObjectInstance, Room
from objsearch.house.stages import StageFailure

FILL_DENSITY = 0.4  # objects per square metre the top-up aims at
WIDE = 3.2  # a room's main rectangle is at least this wide on both sides where it can be
JUNCTION = 0.55  # free depth kept inside the main rectangle where it opens into the rest of an L
TUB_AREA = 5.5  # interior m^2 from which a bathroom may get a bathtub
KITCHEN_TABLE = (9.5, 0.7)  # (minimum area m^2, probability) of a table in a kitchen
SMALL = ("on_top", "on_wall")  # the placements of small objects (a dense room's second top-up)


def bathroom_group(L: RoomLayout, gid: str) -> bool:
    """Bathroom group for small bathrooms: toilet (+ paper) and sink (+ mirror) first, then a bathtub
    (from ``TUB_AREA``) and a towel (above the tub, else on a free wall); False without toilet or sink."""
    if not toilet_and_sink(L, gid):
        return False
    tub_with_towel(L, gid, min_area=TUB_AREA)
    return True


def bed_group(L: RoomLayout, gid: str) -> bool:
    """``house-gen-1``'s bed group, and the floor at the foot of the bed kept free across the bed and
    both of its side corridors (so that later furniture cannot close a corridor off); False if it does not fit."""
    if not groups.bed_group(L, gid):
        return False
    bed = next(o for o in reversed(L.objects) if o.category == "bed")
    x0, y0, x1, y1 = bed.footprint
    fx, fy = bed.front
    side, depth = BED_CORRIDOR + 0.6, 0.6
    if abs(fx) > 0.5:
        rect = (x1, y0 - side, x1 + depth, y1 + side) if fx > 0 else (x0 - depth, y0 - side, x0, y1 + side)
    else:
        rect = (x0 - side, y1, x1 + side, y1 + depth) if fy > 0 else (x0 - side, y0 - depth, x1 + side, y0)
    L.block((rect[0], rect[1], 0.0, rect[2], rect[3], 10.0))
    return True


#: ``groups.MANDATORY`` with this module's bathroom and bed groups.
MANDATORY = {**groups.MANDATORY, "bathroom": [("bathroom", bathroom_group)], "bedroom": [("bed", bed_group)]}


def top_up(L: RoomLayout, area: float, density: float = FILL_DENSITY, placements: tuple[str, ...] = ()) -> None:
    """Try fill categories of the room's type (by affinity; of ``placements`` only, if given) until
    it holds ``density`` objects per m^2."""
    rng = L.rng
    fill = [
        c
        for c in CATEGORIES
        if L.type in c.rooms and c.placement != "group" and (not placements or c.placement in placements)
    ]
    if not fill:
        return
    weights = [c.rooms[L.type] for c in fill]
    total = sum(weights)
    target = math.ceil(density * area)
    for _ in range(3 * target):
        if len(L.objects) >= target:
            break
        cat = fill[int(rng.choice(len(fill), p=[w / total for w in weights]))]
        L.try_category(cat.name)


def main_rect(room: Room) -> tuple[float, float, float, float]:
    """The largest rectangle (x0, y0, x1, y1) of the room's vertex grid that lies inside the room,
    among those at least ``WIDE`` on both sides if there are any."""
    if len(room.polygon) == 4:
        return room.bounds
    xs = sorted({p[0] for p in room.polygon})
    ys = sorted({p[1] for p in room.polygon})
    inside = {
        (i, j): room.contains((xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2)
        for i in range(len(xs) - 1)
        for j in range(len(ys) - 1)
    }
    best, best_area = room.bounds, -1.0
    for i0 in range(len(xs) - 1):
        for i1 in range(i0 + 1, len(xs)):
            for j0 in range(len(ys) - 1):
                for j1 in range(j0 + 1, len(ys)):
                    w, d = xs[i1] - xs[i0], ys[j1] - ys[j0]
                    area = w * d + (100.0 if min(w, d) >= WIDE else 0.0)  # wide enough for a group first
                    if area > best_area and all(inside[i, j] for i in range(i0, i1) for j in range(j0, j1)):
                        best, best_area = (xs[i0], ys[j0], xs[i1], ys[j1]), area
    return best


def _open_sides(room: Room, rect, h: float) -> list[tuple[float, float, float, float, float, float]]:
    """Keep-outs ``JUNCTION`` deep along the parts of ``rect``'s sides that open into the rest of the room:
    no wall to stand things against, and the way between the parts of an L stays free."""
    x0, y0, x1, y1 = rect
    out, d = [], JUNCTION
    for px0, py0, px1, py1 in room.rects():
        if (px0, py0, px1, py1) == tuple(rect) or (x0 <= px0 and px1 <= x1 and y0 <= py0 and py1 <= y1):
            continue
        a, b = max(x0, px0), min(x1, px1)
        if b - a > 1e-6 and abs(py0 - y1) < 1e-6:
            out.append((a, y1 - h - d, 0.0, b, y1, 10.0))
        if b - a > 1e-6 and abs(py1 - y0) < 1e-6:
            out.append((a, y0, 0.0, b, y0 + h + d, 10.0))
        a, b = max(y0, py0), min(y1, py1)
        if b - a > 1e-6 and abs(px0 - x1) < 1e-6:
            out.append((x1 - h - d, a, 0.0, x1, b, 10.0))
        if b - a > 1e-6 and abs(px1 - x0) < 1e-6:
            out.append((x0, a, 0.0, x0 + h + d, b, 10.0))
    return out


def furnish(
    ctx: HouseContext,
    rooms: list[Room],
    doors: list[Door],
    wall_height: float,
    thickness: float,
    small_density: float = 0.0,
) -> list[ObjectInstance]:
    """Furnish every room of a ``house-gen-2`` house and return all objects placed.

    The groups and the per-type fill go into the room's largest rectangle (the whole room
    unless it is an L; the sides where it opens into the rest of the room count as no wall);
    the top-up then fills the whole room, around what stands. ``small_density`` > 0 (dense
    rooms, ``objsearch.house.rooms``) tops it up further with small objects (``SMALL``: on
    receptacles or walls) to that many objects per m^2; 0 (``house-gen-2``) draws nothing more.
    """
    types = [r.type for r in rooms]
    h = thickness / 2
    for room in rooms:
        main = main_rect(room)
        L = RoomLayout(ctx, room.id, room.type, shrunk(main, h), wall_height)
        door_keepouts(L, room, doors)
        for box in _open_sides(room, main, h):
            L.block(box)
        if room.type == "hallway" and min(main[2] - main[0], main[3] - main[1]) < NARROW_HALLWAY:
            passage(L, L.interior)
        placed = len(ctx.objects)
        try:
            furnish_room(L, types, MANDATORY)
        except StageFailure:
            if len(room.polygon) == 4 or len(ctx.objects) != placed:
                raise
            # the group (which placed nothing) may fit across the whole L
            L = whole_layout(ctx, room, doors, wall_height, h, [])
            furnish_room(L, types, MANDATORY)
            main = room.bounds
        if (
            room.type == "kitchen"
            and room.area >= KITCHEN_TABLE[0]
            and not any(o.category == "dining_table" for o in L.objects)
            and ctx.rng.random() < KITCHEN_TABLE[1]
        ):
            dining_group(L, f"dining_{room.id}")
        if len(room.polygon) > 4 and main != room.bounds:  # the top-up sees the whole room
            whole = whole_layout(ctx, room, doors, wall_height, h, L.blocks)
            whole.objects = list(L.objects)
            for px0, py0, px1, py1 in room.rects():
                if min(px1 - px0, py1 - py0) < NARROW:
                    whole.block((px0, py0, 0.0, px1, py1, 10.0))
            L = whole
        top_up(L, room.area)
        if small_density > 0:
            top_up(L, room.area, small_density, SMALL)
    return ctx.objects
