"""Stages 1-2 of ``house-gen-4``: a public hub and private wings, in floorplan families.

Real homes are not one rectangle with one corridor. ``house-gen-4`` builds a house from a
**hub** (the public rooms: living room, kitchen, dining room, tiled in one rectangle) and
one to three **wings** (the private rooms) attached to its sides. Where the wings go is the
house's floorplan **family** (``FAMILIES``):

* ``bar``: one wing, as deep as the hub: a rectangle with one straight hallway;
* ``bar2``: two wings on opposite sides of the hub: two hallways, the hub between them;
* ``L``: two wings on adjacent sides: an L-shaped footprint, two hallways;
* ``U``: two wings on the same side, a courtyard between them: a U-shaped footprint;
* ``T``: three wings: a T-shaped footprint, up to three hallways.

A wing is either a **corridor wing** (a hallway along its axis, from the hub to its far
end; rooms on one side of it or on both; sometimes a room across its far end) or, in a
house too small for a hallway and in some ``bar2`` and ``T`` houses, a **row** of rooms
entered straight from the hub's rooms (rooms entered through rooms). Bathrooms either
open onto a hallway (a slot of a wing) or are the en-suite of a bedroom (cut from its back
corner). How the hub's rooms meet is drawn too: side by side or the living room beside a
kitchen and a dining room; the open plan (wide openings between them) is drawn with the
doors (``gen4.build``).

Everything here is in metres on a 0.1 m grid, rooms are rectilinear and counter-clockwise,
and a rule that cannot be met raises ``StageFailure`` (``generate_house`` draws another
attempt). The plan is finally mirrored and/or transposed at random, as ``house-gen-2``'s.
"""

from __future__ import annotations

import numpy as np

from objsearch.house.gen2.floorplan import Plan, outline
from objsearch.house.gen4.hub import HUB_MIN_DEPTH, hub_rooms, hub_width
from objsearch.house.gen4.wings import Rect, Unit, Wing, corridor_wing, row_wing, snap
from objsearch.house.spec import r4
from objsearch.house.stages import StageFailure

#: Each family's sides of the hub that carry a wing (E/W: the hub's east and west sides, N: north).
FAMILIES = {"bar": ("E",), "bar2": ("E", "W"), "L": ("E", "N"), "U": ("N", "N"), "T": ("E", "W", "N")}
#: How often each family is drawn where the house has the rooms for it (large houses: all).
FAMILY_WEIGHTS = {"bar": 0.2, "bar2": 0.28, "L": 0.2, "U": 0.1, "T": 0.22}
ROW_WING = 0.35  # a second or third wing of bar2 / T is a row of rooms entered from the hub
PRIVATE_DEPTH = (3.4, 4.4)  # how deep the rooms of a wing are, m
CORRIDOR = (1.6, 2.0)  # hallway width, m
COURTYARD = (2.4, 4.5)  # the gap between the two wings of a U, m
ENSUITE_MIN_DEPTH = 3.8
HUB_TRIES = 8
MAX_ASPECT = 3.0  # a house's bounding box is at most this much longer than it is wide


def _offset(spare: float, rng: np.random.Generator) -> float:
    """Where along a hub side with ``spare`` m more than its wing the wing starts: flush with
    one end or the other."""
    return 0.0 if spare < 0.05 or rng.random() < 0.5 else r4(spare)


def _place(rect: Rect, side: str, offset: float, hw: float, hh: float) -> Rect:
    """A wing's rect (u, v) in the hub's frame, for a wing on ``side`` at ``offset`` along it."""
    u0, v0, u1, v1 = rect
    if side == "E":
        return (r4(hw + u0), r4(offset + v0), r4(hw + u1), r4(offset + v1))
    if side == "W":
        return (r4(-u1), r4(offset + v0), r4(-u0), r4(offset + v1))
    return (r4(offset + v0), r4(hh + u0), r4(offset + v1), r4(hh + u1))  # N


def plan_house(
    public: list[str], private: list[Unit], family: str, rows: list[bool], rng: np.random.Generator, area_ranges
) -> Plan:
    """The floorplan of a ``family`` house with these rooms.

    ``public``: the hub's room types (living room first); ``private``: the wings' units,
    dealt to the wings in the order given; ``rows``: which wings are rows of rooms entered
    from the hub (the others have a hallway). Raises ``StageFailure`` when a rule cannot be met.
    """
    sides = FAMILIES[family]
    depth = snap(rng.uniform(*PRIVATE_DEPTH))
    corridor = snap(rng.uniform(*CORRIDOR))
    private = list(private)
    for u in list(private):  # wings too shallow for an en-suite give its bathroom a slot of its own
        if u.bath is not None and depth < ENSUITE_MIN_DEPTH:
            private.append(Unit("bathroom", u.bath[0] * u.bath[1]))
            u.bath = None
        elif u.bath is not None:
            u.bath = (u.bath[0], min(u.bath[1], r4(depth - 2.0)))
    deal = _deal(private, rows)
    wings: list[Wing] = []
    for units, row, side in zip(deal, rows, sides):
        if row:
            wings.append(row_wing(units, depth, rng))
            continue
        # the wings on the hub's east and west sides are alike, so that they line up
        twin = (
            next((w for w, s in zip(wings, sides) if s in "EW" and w.hallway is not None), None)
            if side in "EW"
            else None
        )
        double = None if twin is None else twin.width > depth + corridor + 1e-6
        wings.append(corridor_wing(units, depth, corridor, rng, double))
    areas = [rng.uniform(*area_ranges[t]) for t in public]
    need = sum(areas)
    if family == "U":
        gap = snap(rng.uniform(*COURTYARD))
        hw = r4(wings[0].width + gap + wings[1].width)
        hh = snap(max(need / hw, HUB_MIN_DEPTH))
        offsets = [0.0, r4(hw - wings[1].width)]
    else:
        ew = [w.width for w, s in zip(wings, sides) if s in "EW"]
        nw = [w.width for w, s in zip(wings, sides) if s == "N"]
        hh = max(ew) if family in ("bar", "bar2") else max(ew + [HUB_MIN_DEPTH])
        hw = hub_width(public, hh, max(nw + [need / hh]), {sd for w, sd in zip(wings, sides) if w.mouth is not None})
        offsets = None
    for _ in range(HUB_TRIES):  # where the wings meet the hub, until the hub's walls miss their hallways
        wings = [w.mirrored() if rng.random() < 0.5 else w for w in wings]
        at = offsets or [_offset((hw if sd == "N" else hh) - w.width, rng) for w, sd in zip(wings, sides)]
        mouths: dict[str, list[tuple[float, float]]] = {"N": [], "E": [], "W": []}
        for w, sd, off in zip(wings, sides, at):
            if w.mouth is not None:
                mouths[sd].append((r4(off + w.mouth[0]), r4(off + w.mouth[1])))
        try:
            rooms = hub_rooms(public, areas, hw, hh, mouths, rng)
            break
        except StageFailure:
            continue
    else:
        raise StageFailure("the hub's walls meet a hallway's mouth wherever the wings go")
    offsets = at
    ensuite: dict[int, int] = {}
    hallways: list[int] = []
    for w, s, off in zip(wings, sides, offsets):
        base = len(rooms)
        rooms += [(t, [_place(r, s, off, hw, hh) for r in rects]) for t, rects in w.rooms]
        ensuite |= {base + b: base + r for b, r in w.ensuite.items()}
        if w.hallway is not None:
            hallways.append(base + w.hallway)
    xs = [r[k] for _, rects in rooms for r in rects for k in (0, 2)]
    ys = [r[k] for _, rects in rooms for r in rects for k in (1, 3)]
    x0, y0 = min(xs), min(ys)
    width, dep = r4(max(xs) - x0), r4(max(ys) - y0)
    if max(width, dep) > MAX_ASPECT * min(width, dep):
        raise StageFailure(f"a {width:.1f} x {dep:.1f} m house is longer than {MAX_ASPECT} times its width")
    fx, fy, tr = rng.random() < 0.5, rng.random() < 0.5, rng.random() < 0.5

    def move(r: Rect) -> Rect:
        a, b, c, d = r4(r[0] - x0), r4(r[1] - y0), r4(r[2] - x0), r4(r[3] - y0)
        if fx:
            a, c = r4(width - c), r4(width - a)
        if fy:
            b, d = r4(dep - d), r4(dep - b)
        return (b, a, d, c) if tr else (a, b, c, d)

    polygons = [outline([move(r) for r in rects]) for _, rects in rooms]
    w, d = (dep, width) if tr else (width, dep)
    return Plan(w, d, [t for t, _ in rooms], polygons, ensuite, hallways[0] if hallways else None)


def _deal(units: list[Unit], rows: list[bool]) -> list[list[Unit]]:
    """``units`` dealt to the wings: a corridor wing takes at least 2, a row wing 1-3."""
    n = len(rows)
    need = [1 if r else 2 for r in rows]
    if sum(need) > len(units):
        raise StageFailure(f"{len(units)} private rooms for {n} wings")
    out: list[list[Unit]] = [[] for _ in range(n)]
    pool = list(units)
    for k in range(n):
        out[k] = [pool.pop(0) for _ in range(need[k])]
    for u in pool:  # the rest go to corridor wings (rows stop at 3), the emptier first
        open_ = [k for k in range(n) if not rows[k] or len(out[k]) < 3]
        k = min(open_, key=lambda k: (sum(x.area for x in out[k]), k))
        out[k].append(u)
    return out
