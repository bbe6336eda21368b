"""Placements ``shuffled`` and ``roomwise``: houses whose object relations are broken.

``roomwise`` is ``shuffled`` within room types: every object moves to a random place in a
room of the type it stood in (any bedroom for a bedroom's lamp, the kitchen for the kettle),
on any receptacle of such rooms for an object that stood on another. Object-object relations
(the lamp on the nightstand, the pot on the stove) are broken; room priors are kept. What an
agent loses from functional to roomwise it owed to object relations, from roomwise to
shuffled to room priors. The rules below hold for both, within the rooms allowed.

``generate_house(seed, ..., placement="shuffled")`` takes the functional house of the seed
and generator (floorplan, rooms, doors, walls, materials, and its objects: categories,
counts, mesh variants, sizes and colours) and moves every object with ``shuffle_objects``
to a random place anywhere in the house, whatever the functional groups and the room priors
say: a toilet may stand in the kitchen, a lamp by the bathtub. Whether an agent uses
object relations shows in how much it loses on such houses.

Where an object goes:

* its room: each room takes as many floor and wall-mounted objects as it held in the
  functional house (so clutter per room, and ``house-gen-2``'s fill rule, stay as they were),
  but which ones is drawn: an object tries the rooms still short of their number first (drawn
  by how many they lack), then the others (drawn by area);
* an object that stood on the floor stands there in a corner or free-standing if its
  category is placed so, else with its back against a wall, facing into the room;
* a wall-mounted object hangs on a wall at the height it had;
* an object that stood on another stands on a receptacle drawn uniformly among every
  receptacle of the house (the category's ``parents`` are a prior too: ignored), near its
  front edge (``FRONT_BAND``), where the agent can come near it. That made moved objects
  easier to see than functional ones; the fidelity dial (``objsearch.house.dial``:
  ``anywhere-P``, ``roomwise-P``, P = 100 for every object) draws the spot as the functional
  house does, and reuses this module's helpers. These two placements stay as they are.

The layout rules of the functional house hold (``objsearch.house.layout``): nothing in
front of a door, a strip kept free in front of wall furniture, a passage along narrow
hallways, no furniture in the narrow parts of an L-shaped room. Objects are placed largest
first (floor objects by footprint, then wall-mounted ones, then those on top), each tried
in the rooms (receptacles) in the order drawn until it fits; one that fits nowhere fails
the shuffle (``StageFailure``) and ``generate_house`` draws another, as it does for a
shuffle that fails validation. The spec keeps the functional house's object order and
names; its ``extra`` records ``{"placement": "shuffled"}`` (or ``"roomwise"``; a functional house's ``extra``
stays empty, so its bytes never change). A change here changes every shuffled house: the
spec hashes recorded by the ``house-gen-v2-shuffled`` suite file catch it (rebuild that
suite deliberately, with a new version).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import replace
from functools import partial

import numpy as np

from objsearch.house.categories import category
from objsearch.house.clearances import NARROW, NARROW_HALLWAY, passage, whole_layout
from objsearch.house.layout import HouseContext, RoomLayout
from objsearch.house.spec import HouseSpec, ObjectInstance, Room, r4
from objsearch.house.stages import StageFailure

#: The placements this module makes: each object anywhere in the house, or in a room of its room's type.
PLACEMENTS = ("shuffled", "roomwise")
ON_TOP_TRIES = 4  # spots tried on each receptacle
FRONT_BAND = 0.6  # an object on top stands this near its receptacle's front edge (deep beds, tables)
CORNER_ACCESS = 0.3  # free strip in front of an object in a corner (as the functional fill keeps)


class MovingContext(HouseContext):
    """A ``HouseContext`` whose next instance is ``moving`` at its new place: the object keeps
    its identity (category, instance, variant, size, colour), no rng draw for it."""

    moving: ObjectInstance

    def new_instance(self, cat, room, pos, yaw, size, placement, parent=None, group=None) -> ObjectInstance:
        """The object being moved (``moving``) at its new place, pose and parent."""
        obj = replace(
            self.moving,
            room=room,
            position=tuple(r4(v) for v in pos),
            yaw=int(yaw) % 360,
            placement=placement,
            parent=parent,
            group=None,
        )
        self.objects.append(obj)
        return obj


def narrow_cells(room: Room) -> list[tuple[float, float, float, float]]:
    """The rectangles of an L-shaped (or other rectilinear) room's grid (``Room.rects``) narrower than
    ``NARROW``: kept free of furniture by ``shuffled`` and ``roomwise``."""
    rects = room.rects()
    return [r for r in rects if len(rects) > 1 and min(r[2] - r[0], r[3] - r[1]) < NARROW]


def room_layouts(ctx: HouseContext, spec: HouseSpec, narrow=narrow_cells) -> dict[int, RoomLayout]:
    """An empty layout of every room (its whole interior) with the functional house's keep-outs, and
    the parts ``narrow(room)`` returns (default: ``narrow_cells``) kept free."""
    h = spec.wall_thickness / 2
    layouts = {}
    for room in spec.rooms:
        L = whole_layout(ctx, room, list(spec.doors), spec.wall_height, h, [])
        blocked = narrow(room)
        for x0, y0, x1, y1 in room.rects():
            if (x0, y0, x1, y1) in blocked:
                L.block((x0, y0, 0.0, x1, y1, 10.0))
            elif room.type == "hallway" and min(x1 - x0, y1 - y0) < NARROW_HALLWAY:
                passage(L, (x0, y0, x1, y1))
        layouts[room.id] = L
    return layouts


def weighted_order(rng: np.random.Generator, items: list, weights: list[float]) -> list:
    """``items`` in an order drawn without replacement, each next one with probability proportional to its weight."""
    if not items:
        return []
    p = np.asarray(weights, dtype=float)
    return [items[i] for i in rng.choice(len(items), size=len(items), replace=False, p=p / p.sum())]


def room_order(rng: np.random.Generator, rooms, quota: Counter) -> list[Room]:
    """The rooms to try a floor or wall object in: those still short of their quota first (drawn
    by how many they are short of), then the others (drawn by area)."""
    short = [r for r in rooms if quota[r.id] > 0]
    rest = [r for r in rooms if quota[r.id] <= 0]
    return weighted_order(rng, short, [quota[r.id] for r in short]) + weighted_order(rng, rest, [r.area for r in rest])


def move_kind(obj: ObjectInstance) -> int:
    """The order objects are moved in: 0 on the floor, 1 on a wall, 2 on another object."""
    return 2 if obj.parent is not None else 1 if obj.placement == "on_wall" else 0


def place_in(L: RoomLayout, obj: ObjectInstance) -> ObjectInstance | None:
    """Put ``obj`` (a floor or wall-mounted object) somewhere in ``L``'s room; None if it does not fit."""
    cat = category(obj.category)
    if obj.placement == "on_wall":
        return L.try_on_wall(cat, obj.size, z=obj.position[2])
    if cat.placement == "middle":
        return L.try_middle(cat, obj.size)
    if cat.placement == "corner":  # in a corner, else anywhere along a wall
        return L.try_wall(cat, obj.size, corner=True, access=CORNER_ACCESS) or L.try_wall(
            cat, obj.size, access=CORNER_ACCESS
        )
    return L.try_wall(cat, obj.size)


def _near_front(L: RoomLayout, parent: ObjectInstance, w: float, d: float, rect) -> tuple[float, float]:
    """A spot for a ``w`` x ``d`` footprint on ``rect`` (the parent's surface), within ``FRONT_BAND`` of
    the parent's front edge (the side kept free), so that the agent can come near it."""
    x0, y0, x1, y1 = rect
    fx, fy = parent.front
    if fx > 0.5:
        x0 = max(x0, min(x1 - FRONT_BAND, x1 - w - 0.02))
    elif fx < -0.5:
        x1 = min(x1, max(x0 + FRONT_BAND, x0 + w + 0.02))
    elif fy > 0.5:
        y0 = max(y0, min(y1 - FRONT_BAND, y1 - d - 0.02))
    else:
        y1 = min(y1, max(y0 + FRONT_BAND, y0 + d + 0.02))
    return L.span(x0 + 0.01 + w / 2, x1 - 0.01 - w / 2), L.span(y0 + 0.01 + d / 2, y1 - 0.01 - d / 2)


def shuffle_objects(spec: HouseSpec, rng: np.random.Generator, placement: str = "shuffled") -> list[ObjectInstance]:
    """``spec``'s objects, each moved to a random place in the house (``shuffled``) or in a room of
    its room's type (``roomwise``; the module docstring), in ``spec``'s order; raises
    ``StageFailure`` when one finds no place."""
    if placement not in PLACEMENTS:
        raise ValueError(f"placement must be one of {PLACEMENTS}, not {placement!r}")
    room_type = {r.id: r.type for r in spec.rooms}

    def allowed(obj: ObjectInstance, room: int) -> bool:
        return placement == "shuffled" or room_type[room] == room_type[obj.room]

    ctx = MovingContext(rng, spec.split)
    layouts = room_layouts(ctx, spec)
    quota = Counter(o.room for o in spec.objects if move_kind(o) < 2)
    order = sorted(spec.objects, key=lambda o: (move_kind(o), -o.size[0] * o.size[1]))
    for obj in order:
        ctx.moving = obj
        placed = None
        if move_kind(obj) == 2:
            receptacles = [o for o in ctx.objects if category(o.category).receptacle and allowed(obj, o.room)]
            for i in rng.permutation(len(receptacles)):
                parent = receptacles[i]
                placed = layouts[parent.room].try_on_top(
                    category(obj.category),
                    parents=[parent],
                    size=obj.size,
                    face_parent=False,
                    tries=ON_TOP_TRIES,
                    where=partial(_near_front, layouts[parent.room]),
                )
                if placed:
                    break
        else:
            for room in room_order(rng, [r for r in spec.rooms if allowed(obj, r.id)], quota):
                placed = place_in(layouts[room.id], obj)
                if placed:
                    quota[room.id] -= 1
                    break
        if not placed:
            raise StageFailure(f"no place for {obj.name} in the house")
    moved = {o.name: o for o in ctx.objects}
    return [moved[o.name] for o in spec.objects]


def shuffle_house(spec: HouseSpec, rng: np.random.Generator, placement: str = "shuffled") -> HouseSpec:
    """``spec`` with its objects moved (``shuffle_objects``), recorded as ``extra["placement"]``."""
    objects = tuple(shuffle_objects(spec, rng, placement))
    return replace(spec, objects=objects, extra={**spec.extra, "placement": placement})
