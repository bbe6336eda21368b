"""The rules a ``house-gen-2`` house must hold, beside ``objsearch.house.validate``'s compile,
overlap, reachability and visibility checks (``validate_house`` adds them: ``Generator.check_rules``).

``rule_problems(spec)`` returns ``{rule: [problems]}`` for every rule of ``RULES``:

* ``core``: the core rooms (hallway, living room, kitchen, dining room) are connected by the
  doors between core rooms alone;
* ``private``: every bedroom and office has a door onto a core room, and its other doors lead
  only to the core or into its own en-suite bathroom (never through another bedroom);
* ``bathroom``: every bathroom has exactly one door, onto a core room or into one bedroom
  (en-suite);
* ``hallway``: every hallway joins at least two rooms;
* ``open_plan``: an opening wider than ``OPEN_PLAN_MIN`` joins kitchen-dining or living-dining;
* ``area``: every room's area lies in ``AREA_LIMITS`` of its type;
* ``footprint``: the rooms tile the footprint, whose area per room lies in ``AREA_PER_ROOM``;
* ``entrance``: exactly one door leads outside (``OUTSIDE``), from a core room, in the outer
  wall, and no wall box covers its opening;
* ``fill`` (houses with objects): every room holds at least ``MIN_OBJECTS`` objects and
  ``MIN_DENSITY`` objects per square metre (rounded down).
"""

from __future__ import annotations

import math

from objsearch.house.gen2.floorplan import AREA_LIMITS, CORE, PRIVATE
from objsearch.house.spec import OUTSIDE, HouseSpec

RULES = ("core", "private", "bathroom", "hallway", "open_plan", "area", "footprint", "entrance", "fill")
FLOORPLAN_RULES = RULES[:-1]
OPEN_PLAN_MIN = 1.5
AREA_PER_ROOM = (8.0, 30.0)
MIN_OBJECTS = 2
MIN_DENSITY = 0.25


def _neighbours(spec: HouseSpec) -> dict[int, list[int]]:
    out: dict[int, list[int]] = {r.id: [] for r in spec.rooms}
    out[OUTSIDE] = []
    for d in spec.doors:
        a, b = d.rooms
        out[a].append(b)
        out[b].append(a)
    return out


def rule_problems(spec: HouseSpec, area_limits: dict[str, tuple[float, float]] = AREA_LIMITS) -> dict[str, list[str]]:
    """Problems per rule of ``RULES`` (an empty list: the rule holds); ``fill`` only for a house with
    objects. ``area_limits``: ``house-gen-2``'s by default (``house-gen-3`` passes its own)."""
    types = {r.id: r.type for r in spec.rooms}
    types[OUTSIDE] = "outside"
    nb = _neighbours(spec)
    p: dict[str, list[str]] = {rule: [] for rule in RULES}
    core = [r.id for r in spec.rooms if r.type in CORE]
    if core:
        seen, todo = {core[0]}, [core[0]]
        while todo:
            for j in nb[todo.pop()]:
                if types[j] in CORE and j not in seen:
                    seen.add(j)
                    todo.append(j)
        p["core"] += [f"core room {i} ({types[i]}) is not joined to the core" for i in core if i not in seen]
    else:
        p["core"].append("the house has no core room")
    for r in spec.rooms:
        doors_to = nb[r.id]
        if r.type in PRIVATE:
            if not any(types[j] in CORE for j in doors_to):
                p["private"].append(f"room {r.id} ({r.type}) has no door onto the core")
            for j in doors_to:
                ensuite = types[j] == "bathroom" and nb[j] == [r.id]
                if types[j] not in CORE and not ensuite:
                    p["private"].append(f"room {r.id} ({r.type}) opens onto room {j} ({types[j]})")
        elif r.type == "bathroom":
            if len(doors_to) != 1:
                p["bathroom"].append(f"bathroom {r.id} has {len(doors_to)} doors, not 1")
            elif types[doors_to[0]] not in CORE and types[doors_to[0]] != "bedroom":
                p["bathroom"].append(f"bathroom {r.id} opens onto room {doors_to[0]} ({types[doors_to[0]]})")
        elif r.type == "hallway" and len(doors_to) < 2:
            p["hallway"].append(f"hallway {r.id} joins {len(doors_to)} room(s), not at least 2")
        lo, hi = area_limits[r.type]
        if not lo <= r.area <= hi:
            p["area"].append(f"room {r.id} ({r.type}) is {r.area:.1f} m^2, outside {lo}-{hi}")
    for d in spec.doors:
        if d.width > OPEN_PLAN_MIN and {types[d.rooms[0]], types[d.rooms[1]]} not in (
            {"kitchen", "dining_room"},
            {"living_room", "dining_room"},
        ):
            p["open_plan"].append(
                f"door {d.id} is {d.width} m wide between {types[d.rooms[0]]} and {types[d.rooms[1]]}"
            )
    width, depth = spec.footprint
    total = sum(r.area for r in spec.rooms)
    if abs(total - width * depth) > 0.01 * width * depth:
        p["footprint"].append(f"rooms cover {total:.1f} m^2 of a {width * depth:.1f} m^2 footprint")
    per_room = width * depth / max(len(spec.rooms), 1)
    if not AREA_PER_ROOM[0] <= per_room <= AREA_PER_ROOM[1]:
        p["footprint"].append(f"footprint {per_room:.1f} m^2 per room, outside {AREA_PER_ROOM[0]}-{AREA_PER_ROOM[1]}")
    p["entrance"] += _entrance_problems(spec, types)
    if spec.objects:
        counts = {r.id: 0 for r in spec.rooms}
        for o in spec.objects:
            counts[o.room] += 1
        for r in spec.rooms:
            need = max(MIN_OBJECTS, math.floor(MIN_DENSITY * r.area))
            if counts[r.id] < need:
                p["fill"].append(f"room {r.id} ({r.type}, {r.area:.1f} m^2) holds {counts[r.id]} objects, not {need}")
    return p


def _entrance_problems(spec: HouseSpec, types: dict[int, str]) -> list[str]:
    doors = [d for d in spec.doors if OUTSIDE in d.rooms]
    if len(doors) != 1:
        return [f"{len(doors)} entrance doors, not 1"]
    d = doors[0]
    room = max(d.rooms)
    out = []
    if types[room] not in CORE:
        out.append(f"the entrance opens into room {room} ({types[room]}), not the core")
    width, depth = spec.footprint
    cx, cy = d.center
    on_edge = (d.axis == "x" and min(abs(cy), abs(cy - depth)) < 1e-6) or (
        d.axis == "y" and min(abs(cx), abs(cx - width)) < 1e-6
    )
    if not on_edge:
        out.append(f"the entrance {d.center} is not in an outer wall")
    for w in spec.walls:
        x0, y0, x1, y1 = w.box
        if x0 < cx < x1 and y0 < cy < y1 or (x0 <= cx <= x1 and y0 <= cy <= y1 and w.room == OUTSIDE):
            out.append(f"wall {w.id} covers the entrance")
    return out


def check_rules(spec: HouseSpec) -> list[str]:
    """Every problem of every rule, as one list (``validate_house`` appends it for ``house-gen-2``)."""
    return [f"{rule}: {msg}" for rule, msgs in rule_problems(spec).items() for msg in msgs]
