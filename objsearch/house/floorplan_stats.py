"""What a floorplan is, read from its spec alone: the measures behind ``docs/houses.md``'s
floorplan families (``benchmarks/floorplan_families.py`` counts them over seeds).

``describe(spec)`` gives, for a house of any generator version:

* ``family``: the family its generator recorded (``extra["floorplan"]``, ``house-gen-4``), else
  ``band`` (``house-gen-2`` and ``-3``: one rectangle of three bands);
* ``footprint``: ``rectangle``, ``L`` (6 corners) or ``T/U`` (8 corners or more), from the
  rooms' outline, and ``corners``;
* ``hallways`` and ``one_straight_hallway``: how many hallways, and whether the house has
  exactly one and it is a rectangle;
* ``open_plan``: the widest opening between two of the living room, kitchen and dining room
  is at least ``OPEN_PLAN_WIDTH`` (wider than a door and than ``house-gen-2``'s openings);
* ``ensuite``: some bathroom's only door leads into a bedroom;
* ``through_rooms``: some bedroom or office is entered from a room that is not a hallway.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable

from objsearch.house.spec import OUTSIDE, HouseSpec

OPEN_PLAN_WIDTH = 2.5
PUBLIC = ("living_room", "kitchen", "dining_room")


def outline_corners(spec: HouseSpec) -> int:
    """How many corners the outline of the union of the rooms has (4: a rectangle)."""
    xs = sorted({x for r in spec.rooms for x, _ in r.polygon})
    ys = sorted({y for r in spec.rooms for _, y in r.polygon})
    covered = set()
    for i in range(len(xs) - 1):
        for j in range(len(ys) - 1):
            cx, cy = (xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2
            if any(r.contains(cx, cy) for r in spec.rooms):
                covered.add((i, j))
    corners = 0
    for i in range(len(xs)):
        for j in range(len(ys)):
            around = [(i - 1, j - 1) in covered, (i, j - 1) in covered, (i, j) in covered, (i - 1, j) in covered]
            n = sum(around)
            corners += n in (1, 3) or (n == 2 and around[0] == around[2])
    return corners


def describe(spec: HouseSpec) -> dict:
    """The floorplan measures of ``spec`` (the module docstring)."""
    types = {r.id: r.type for r in spec.rooms}
    types[OUTSIDE] = "outside"
    doors_of: dict[int, list] = {r.id: [] for r in spec.rooms}
    for d in spec.doors:
        for a, b in (d.rooms, d.rooms[::-1]):
            if a != OUTSIDE:
                doors_of[a].append((types[b], d.width))
    corners = outline_corners(spec)
    halls = [r for r in spec.rooms if r.type == "hallway"]
    hub_openings = [
        d.width for d in spec.doors if OUTSIDE not in d.rooms and {types[i] for i in d.rooms} <= set(PUBLIC)
    ]
    return {
        "family": spec.extra.get("floorplan", "band"),
        "footprint": "rectangle" if corners == 4 else "L" if corners == 6 else "T/U",
        "corners": corners,
        "hallways": len(halls),
        "one_straight_hallway": len(halls) == 1 and len(halls[0].polygon) == 4,
        "open_plan": max(hub_openings, default=0.0) >= OPEN_PLAN_WIDTH,
        "ensuite": any(r.type == "bathroom" and [t for t, _ in doors_of[r.id]] == ["bedroom"] for r in spec.rooms),
        "through_rooms": any(
            r.type in ("bedroom", "office") and "hallway" not in [t for t, _ in doors_of[r.id]] for r in spec.rooms
        ),
    }


def shares(specs: Iterable[HouseSpec]) -> dict:
    """Over ``specs``: the share of each family and footprint, and of houses with each feature."""
    rows = [describe(s) for s in specs]
    n = len(rows)
    if not n:
        raise ValueError("shares() needs at least one house")
    family, footprint = Counter(r["family"] for r in rows), Counter(r["footprint"] for r in rows)
    return {
        "houses": n,
        "family": {k: round(v / n, 4) for k, v in sorted(family.items())},
        "footprint": {k: round(v / n, 4) for k, v in sorted(footprint.items())},
        "not_rectangular": round(sum(r["footprint"] != "rectangle" for r in rows) / n, 4),
        "not_one_straight_hallway": round(sum(not r["one_straight_hallway"] for r in rows) / n, 4),
        **{k: round(sum(r[k] for r in rows) / n, 4) for k in ("open_plan", "ensuite", "through_rooms")},
        "hallways": {k: round(v / n, 4) for k, v in sorted(Counter(r["hallways"] for r in rows).items())},
    }
