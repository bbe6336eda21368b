"""The placement-fidelity dial: ``anywhere-P`` and ``roomwise-P``, houses with a share P of their
objects moved out of their functional places.

``generate_house(seed, ..., placement="anywhere-50")`` takes the functional house of the seed
and generator (floorplan, rooms, doors, walls, materials and every object's identity: category,
instance, variant, size, colour) and moves half of its objects; ``roomwise-50`` moves the same
half, each into a room of the type it stood in. P is a percent (``spec.DIAL_SHARES``: 25, 50,
75, 100); P = 0 is ``functional`` itself, P = 100 moves every object (a corrected ``shuffled``
or ``roomwise``: below).

Which objects move (``moving_objects``): all kinds of object, furniture too, as ``shuffled``
does. One order of a house's objects is drawn (``move_order``: a uniform permutation in which
an object comes after everything that stands on it), and setting P moves its first
``moved_count(n, P)`` objects (P * n / 100 rounded half up), so that

* the dial is nested: what moves at 25 also moves at 50, 75 and 100, in both families (the
  order is drawn from one stream, ``generate.DIAL_ORDER_STREAM``), so a curve over P, and a
  comparison of the two families at one P, are paired on the same houses and objects;
* what stands on a moved object moves too (it is before it in the order), so nothing floats:
  an object on top is a little likelier to move than one on the floor, and the count is exact.

Objects that stay keep their functional pose, byte for byte (``group`` included); a moved
object loses its ``group``. Where a moved object goes follows ``shuffle``'s rules (room quotas,
floor objects along a wall, in a corner or free-standing by their category, wall-mounted ones
at their height, the functional house's keep-outs, largest first, ``StageFailure`` when one
fits nowhere) around the objects that stay, whose boxes block and whose front strips stay free
if they stand against a wall (``ACCESS_DEPTH``, ``CORNER_ACCESS`` in a corner). A moved object is
first tried with the box it stood in blocked, so that it moves clear of its functional place
(a lamp back in the corner it stood in has not moved), and without that block only where nothing
fits with it. Three rules differ from ``shuffle``'s:

* a moved object that stood on another stands on a receptacle drawn uniformly among those of
  the house (``roomwise``: of rooms of its room's type), its functional parent tried last, at a
  spot drawn as the functional house draws one (``RoomLayout.try_on_top``: uniform over the
  whole top surface; near a long edge on a dining table), not near the front edge as
  ``shuffle.FRONT_BAND`` puts it, which made moved objects easier to see than functional ones;
* each room's quota counts only its objects that move;
* of an L-shaped room only the arms narrower than ``NARROW`` are kept free (``narrow_arms``), not
  every narrow cell of its grid (``shuffle.narrow_cells``), which also cuts a strip off its main
  part and left many a bedroom's bed no place in ``roomwise`` (on 10 seeds each of house-gen-2
  medium and large and house-gen-3 xlarge: 9 seeds with no valid ``roomwise`` house, none
  without a valid ``roomwise-100`` one).

``shuffled`` and ``roomwise`` themselves stay as they are (shipped suites record their hashes).
The spec's ``extra`` records ``{"placement": "anywhere-50"}``.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from dataclasses import replace

import numpy as np

from objsearch.house.categories import category
from objsearch.house.clearances import NARROW
from objsearch.house.layout import ACCESS_DEPTH, RoomLayout
from objsearch.house.shuffle import (
    CORNER_ACCESS,
    ON_TOP_TRIES,
    MovingContext,
    move_kind,
    place_in,
    room_layouts,
    room_order,
)
from objsearch.house.spec import DIAL_FAMILIES, DIAL_SHARES, HouseSpec, ObjectInstance, Room
from objsearch.house.stages import StageFailure

#: Every dial placement name and its (family, share in percent): ``anywhere-25`` ... ``roomwise-100``.
DIAL_PLACEMENTS = {f"{family}-{share}": (family, share) for family in DIAL_FAMILIES for share in DIAL_SHARES}


def dial_setting(placement: str) -> tuple[str, int]:
    """The (family, share in percent) of dial placement ``placement``; ``ValueError`` for another name."""
    if placement not in DIAL_PLACEMENTS:
        raise ValueError(f"placement must be one of {tuple(DIAL_PLACEMENTS)}, not {placement!r}")
    return DIAL_PLACEMENTS[placement]


def moved_count(n: int, share: int) -> int:
    """How many of ``n`` objects setting ``share`` (percent) moves: ``share * n / 100`` rounded half up."""
    return (share * n + 50) // 100


def move_order(spec: HouseSpec, rng: np.random.Generator) -> list[str]:
    """``spec``'s object names in the order the dial moves them: a uniform permutation in which what
    stands on an object (transitively) is pulled forward to just before it where it was drawn later,
    so a prefix of the order holds whatever stands on an object it holds."""
    children = defaultdict(list)
    for obj in spec.objects:
        if obj.parent is not None:
            children[obj.parent].append(obj.name)
    drawn = [spec.objects[i].name for i in rng.permutation(len(spec.objects))]
    rank = {name: i for i, name in enumerate(drawn)}
    order: list[str] = []
    seen: set[str] = set()

    def add(name: str) -> None:
        seen.add(name)
        for child in sorted(children[name], key=rank.__getitem__):
            if child not in seen:
                add(child)
        order.append(name)

    for name in drawn:
        if name not in seen:
            add(name)
    return order


def moving_objects(spec: HouseSpec, share: int, rng: np.random.Generator) -> frozenset[str]:
    """The names of the objects setting ``share`` (percent) moves: the first ``moved_count`` of ``move_order``."""
    order = move_order(spec, rng)
    return frozenset(order[: moved_count(len(order), share)])


def narrow_arms(room: Room) -> list[tuple[float, float, float, float]]:
    """The rectangles of a rectilinear room's grid (``Room.rects``) that lie in no part of the room at
    least ``NARROW`` wide: neither with the cells beside it in its row nor with those in its column.
    (``shuffle.narrow_cells`` keeps every narrow cell free, and so also the strip of an L's main
    part that its grid cuts off: a bedroom's bed may find no wall left.)"""
    rects = room.rects()
    if len(rects) == 1:
        return []

    def run(cell, axis: int) -> float:  # the extent along ``axis`` of the cells in line with ``cell``
        lo, hi = cell[axis], cell[axis + 2]
        line = sorted(
            (r for r in rects if (r[1 - axis], r[3 - axis]) == (cell[1 - axis], cell[3 - axis])), key=lambda r: r[axis]
        )
        for r in reversed(line):  # grow down, then up: the cells are sorted, so one pass each way
            if abs(r[axis + 2] - lo) < 1e-9:
                lo = r[axis]
        for r in line:
            if abs(r[axis] - hi) < 1e-9:
                hi = r[axis + 2]
        return hi - lo

    def wide(cell) -> bool:
        w, d = cell[2] - cell[0], cell[3] - cell[1]
        return min(run(cell, 0), d) >= NARROW or min(w, run(cell, 1)) >= NARROW

    return [r for r in rects if not wide(r)]


def _stay(L: RoomLayout, obj: ObjectInstance) -> None:
    """Block the box of ``obj``, which stays, in its room's layout, and the strip in front of it if it
    stands against a wall (so a moved object does not bar the way to it)."""
    L.block(obj.box, obj.name)
    if obj.parent is None and obj.placement in ("wall", "corner"):
        L.keep_front(obj, CORNER_ACCESS if obj.placement == "corner" else ACCESS_DEPTH)


def _on_top(layouts: dict[int, RoomLayout], obj: ObjectInstance, receptacles: list[ObjectInstance], rng):
    """Stand ``obj`` on one of ``receptacles`` (in a drawn order, its functional parent last) at a spot
    drawn as the functional house draws one; None if none has room."""
    others = [o for o in receptacles if o.name != obj.parent]
    tries = [others[i] for i in rng.permutation(len(others))] + [o for o in receptacles if o.name == obj.parent]
    for parent in tries:
        placed = layouts[parent.room].try_on_top(
            category(obj.category), parents=[parent], size=obj.size, face_parent=False, tries=ON_TOP_TRIES
        )
        if placed:
            return placed
    return None


def _elsewhere(L: RoomLayout, obj: ObjectInstance, place) -> ObjectInstance | None:
    """``place(obj)``, first with the box ``obj`` stood in blocked in its room's layout ``L`` (so that it
    moves clear of its functional place where anything else fits), then, if nothing fitted, without."""
    i = len(L.blocks)
    L.block(obj.box, None)
    try:
        placed = place(obj)
    finally:
        del L.blocks[i]  # what placing appended comes after it
    return placed or place(obj)


def dial_objects(
    spec: HouseSpec, moving: frozenset[str], rng: np.random.Generator, family: str
) -> list[ObjectInstance]:
    """``spec``'s objects in ``spec``'s order, those named in ``moving`` moved to a random place in the
    house (family ``anywhere``) or in a room of their room's type (``roomwise``), the others as they
    were (the module docstring); raises ``StageFailure`` when one finds no place."""
    if family not in DIAL_FAMILIES:
        raise ValueError(f"family must be one of {DIAL_FAMILIES}, not {family!r}")
    room_type = {r.id: r.type for r in spec.rooms}

    def allowed(obj: ObjectInstance, room: int) -> bool:
        return family == "anywhere" or room_type[room] == room_type[obj.room]

    ctx = MovingContext(rng, spec.split)
    layouts = room_layouts(ctx, spec, narrow=narrow_arms)
    for obj in spec.objects:
        if obj.name not in moving:
            _stay(layouts[obj.room], obj)
            ctx.objects.append(obj)
    movers = [o for o in spec.objects if o.name in moving]
    quota = Counter(o.room for o in movers if move_kind(o) < 2)

    def place(obj: ObjectInstance) -> ObjectInstance | None:
        if move_kind(obj) == 2:
            receptacles = [o for o in ctx.objects if category(o.category).receptacle and allowed(obj, o.room)]
            return _on_top(layouts, obj, receptacles, rng)
        for room in room_order(rng, [r for r in spec.rooms if allowed(obj, r.id)], quota):
            placed = place_in(layouts[room.id], obj)
            if placed:
                quota[room.id] -= 1
                return placed
        return None

    for obj in sorted(movers, key=lambda o: (move_kind(o), -o.size[0] * o.size[1])):
        ctx.moving = obj
        placed = _elsewhere(layouts[obj.room], obj, place)
        if not placed:
            raise StageFailure(f"no place for {obj.name} in the house")
    placed = {o.name: o for o in ctx.objects}
    return [placed[o.name] for o in spec.objects]


def dial_house(spec: HouseSpec, moving: frozenset[str], rng: np.random.Generator, placement: str) -> HouseSpec:
    """``spec`` with the objects named in ``moving`` moved by dial placement ``placement``
    (``dial_objects``), recorded as ``extra["placement"]``."""
    family, _ = dial_setting(placement)
    objects = tuple(dial_objects(spec, moving, rng, family))
    return replace(spec, objects=objects, extra={**spec.extra, "placement": placement})
