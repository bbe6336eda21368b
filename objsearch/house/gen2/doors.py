"""Stage 3 of ``house-gen-2``: doors by circulation rules, the entrance, and the edges of any rectilinear room.

Door rules (the rules ``objsearch.house.gen2.rules`` checks):

* the core (hallway, living room, kitchen, dining room) is joined by a spanning tree of
  doors over the core rooms that share a wall, grown from the hallway (else the living
  room), hallway walls first; a kitchen-dining or living-dining pair may instead be joined
  by a wide opening (open plan, ``OPEN_PLAN``), and other core pairs get an extra door with
  ``EXTRA_CORE_DOOR``;
* every bedroom and office gets one door onto the core room it shares the best wall with
  (the hallway first), never onto another bedroom;
* a bathroom gets exactly one door: onto the core, or (en-suite) into its bedroom;
* a hallway with fewer than two doors gets a door to one more core room;
* a door sits near one end of its wall with probability ``NEAR_END`` (else anywhere on it);
* the entrance is a door in an outer wall of a core room (the hallway first), its ``rooms``
  being ``(room, OUTSIDE)``.

Walls (``objsearch.house.walls.build_walls`` over ``edges``, the one wall builder of every
generator): each edge of each room polygon is a box of half the wall thickness on the room's side
of the edge, with its door openings cut out; edges on the footprint boundary get a second
half outside (the outer skin, room -1), cut at the entrance too, so the entrance is a real
opening through the outer wall.
"""

from __future__ import annotations

import numpy as np

from objsearch.house.gen2.floorplan import CORE, PRIVATE, Plan
from objsearch.house.spec import OUTSIDE, Door, r4
from objsearch.house.stages import StageFailure
from objsearch.house.walls import Edge

DOOR_WIDTH = (0.9, 1.0)
ENTRANCE_WIDTH = (0.95, 1.05)
OPENING_WIDTH = (1.6, 2.4)  # open-plan opening between kitchen or living room and dining room
DOOR_HEIGHT = 2.1
DOOR_MARGIN = 0.2  # from the ends of the shared wall
ENTRANCE_MARGIN = 0.15
NEAR_END = 0.75  # a door sits within 0.3 m of one end of its wall with this probability
OPEN_PLAN = 0.8
EXTRA_CORE_DOOR = 0.3
OPEN_PAIRS = ({"kitchen", "dining_room"}, {"living_room", "dining_room"})
#: Which core room a private room prefers to open onto.
CORE_PREFERENCE = {"hallway": 3.0, "living_room": 2.0, "dining_room": 1.5, "kitchen": 1.0}

Segment = tuple[str, float, float, float]  # (door axis, fixed coordinate, lo, hi)


def edges(polygon) -> list[Edge]:
    """Edges of a ccw rectilinear polygon (``walls.Edge``: axis the edge runs along, fixed
    coordinate, lo, hi, side), in the polygon's order."""
    out = []
    for k in range(len(polygon)):
        (xa, ya), (xb, yb) = polygon[k], polygon[(k + 1) % len(polygon)]
        if ya == yb:  # runs along x; ccw: going +x has the room above
            out.append(("x", ya, min(xa, xb), max(xa, xb), 1 if xb > xa else -1))
        else:  # going +y has the room to the west
            out.append(("y", xa, min(ya, yb), max(ya, yb), -1 if yb > ya else 1))
    return out


def shared_segments(pa, pb, eps: float = 1e-6) -> list[Segment]:
    """The wall segments two room polygons share (rooms on opposite sides)."""
    out = []
    for axis, f, lo, hi, side in edges(pa):
        for axis2, f2, lo2, hi2, side2 in edges(pb):
            if axis == axis2 and abs(f - f2) < eps and side != side2:
                a, b = max(lo, lo2), min(hi, hi2)
                if b - a > eps:
                    out.append((axis, f, a, b))
    return out


def exterior_segments(polygon, footprint: tuple[float, float], eps: float = 1e-6) -> list[Segment]:
    """The edges of a room polygon that lie on the footprint boundary (outer walls)."""
    width, depth = footprint
    return [
        (axis, f, lo, hi)
        for axis, f, lo, hi, _ in edges(polygon)
        if (axis == "x" and (abs(f) < eps or abs(f - depth) < eps))
        or (axis == "y" and (abs(f) < eps or abs(f - width) < eps))
    ]


def _door(k: int, rooms, seg: Segment, width: float, margin: float, thickness: float, rng) -> Door | None:
    axis, fixed, lo, hi = seg
    pad = margin + thickness / 2 + width / 2
    if hi - lo < 2 * pad + 0.02:
        return None
    a, b = lo + pad + 0.01, hi - pad - 0.01
    if rng.random() < NEAR_END:  # near one end of the wall, as doors mostly are: the middle stays for furniture
        c = a + rng.uniform(0, min(0.3, b - a)) if rng.random() < 0.5 else b - rng.uniform(0, min(0.3, b - a))
    else:
        c = rng.uniform(a, b)
    c = r4(round(c, 2))
    center = (c, r4(fixed)) if axis == "x" else (r4(fixed), c)
    return Door(k, tuple(rooms), axis, center, r4(width), DOOR_HEIGHT)


def place_doors(plan: Plan, rng: np.random.Generator, thickness: float) -> list[Door]:
    """Doors and the entrance of ``plan`` by the rules above; raises ``StageFailure`` when one cannot be met."""
    n, types = len(plan.types), plan.types
    segs: dict[tuple[int, int], Segment] = {}
    for i in range(n):
        for j in range(i + 1, n):
            s = shared_segments(plan.polygons[i], plan.polygons[j])
            if s:
                segs[(i, j)] = max(s, key=lambda v: (v[3] - v[2], v[1], v[2]))
    widths = {e: r4(round(rng.uniform(*DOOR_WIDTH), 2)) for e in sorted(segs)}
    need = {e: widths[e] + 2 * DOOR_MARGIN + thickness + 0.04 for e in widths}
    ok = {e for e in segs if segs[e][3] - segs[e][2] >= need[e]}
    core = [i for i in range(n) if types[i] in CORE]
    edges_out: list[tuple[tuple[int, int], float]] = []  # (pair, width)

    def pair(i, j):
        return (i, j) if i < j else (j, i)

    # core spanning tree
    root = plan.hallway if plan.hallway is not None else types.index("living_room")
    tree = {root}
    noise = {e: rng.uniform(0, 0.5) for e in sorted(segs)}
    while len(tree) < len(core):
        best = None
        for e in sorted(ok):
            i, j = e
            if types[i] not in CORE or types[j] not in CORE or (i in tree) == (j in tree):
                continue
            cost = noise[e] - (1.0 if "hallway" in (types[i], types[j]) else 0.0)
            if best is None or cost < best[0]:
                best = (cost, e)
        if best is None:
            raise StageFailure("the core rooms cannot be joined by doors")
        edges_out.append((best[1], widths[best[1]]))
        tree.update(best[1])
    for e in sorted(ok):
        i, j = e
        if types[i] not in CORE or types[j] not in CORE:
            continue
        open_pair = {types[i], types[j]} in OPEN_PAIRS
        lo, hi = segs[e][2], segs[e][3]
        if open_pair and rng.random() < OPEN_PLAN:
            w = r4(round(min(rng.uniform(*OPENING_WIDTH), hi - lo - 2 * DOOR_MARGIN - thickness - 0.04), 2))
            if w >= OPENING_WIDTH[0]:
                edges_out = [(p, wd) for p, wd in edges_out if p != e] + [(e, w)]
                continue
        if e not in [p for p, _ in edges_out] and rng.random() < EXTRA_CORE_DOOR:
            edges_out.append((e, widths[e]))
    # private rooms onto the core, bathrooms onto the core or into their bedroom
    for i in range(n):
        if types[i] in PRIVATE or (types[i] == "bathroom" and i not in plan.ensuite):
            cands = [j for j in core if pair(i, j) in ok]
            if not cands:
                raise StageFailure(f"room {i} ({types[i]}) has no wall onto the core long enough for a door")
            j = max(cands, key=lambda j: (CORE_PREFERENCE[types[j]] + noise[pair(i, j)], -j))
            edges_out.append((pair(i, j), widths[pair(i, j)]))
        elif types[i] == "bathroom":
            e = pair(i, plan.ensuite[i])
            if e not in ok:
                raise StageFailure(f"en-suite bathroom {i} has no wall into its bedroom long enough for a door")
            edges_out.append((e, widths[e]))
    if plan.hallway is not None:
        h = plan.hallway
        if sum(h in p for p, _ in edges_out) < 2:
            more = [j for j in core if j != h and pair(h, j) in ok and pair(h, j) not in [p for p, _ in edges_out]]
            if not more:
                raise StageFailure("the hallway joins fewer than two rooms")
            edges_out.append((pair(h, more[0]), widths[pair(h, more[0])]))
    doors = []
    for e, w in edges_out:
        d = _door(len(doors), e, segs[e], w, DOOR_MARGIN, thickness, rng)
        if d is None:
            raise StageFailure(f"no place for the door between rooms {e}")
        doors.append(d)
    doors.append(_entrance(plan, len(doors), rng, thickness))
    return doors


def _entrance(plan: Plan, k: int, rng: np.random.Generator, thickness: float) -> Door:
    width = r4(round(rng.uniform(*ENTRANCE_WIDTH), 2))
    need = width + 2 * ENTRANCE_MARGIN + thickness + 0.04
    cands = []
    for i, t in enumerate(plan.types):
        if t not in CORE:
            continue
        for s in exterior_segments(plan.polygons[i], (plan.width, plan.depth)):
            if s[3] - s[2] >= need:
                cands.append((i, s, CORE_PREFERENCE[t]))
    if not cands:
        raise StageFailure("no outer wall of a core room is long enough for the entrance")
    best = max(c[2] for c in cands)
    top = [c for c in cands if c[2] == best]
    i, seg, _ = top[int(rng.integers(len(top)))]
    door = _door(k, (i, OUTSIDE), seg, width, ENTRANCE_MARGIN, thickness, rng)
    assert door is not None
    return door
