"""The rules a ``house-gen-4`` house must hold: ``house-gen-2``'s (``gen2.rules``) with this
version's area limits, except two that assumed one rectangle:

* ``footprint``: the rooms do not overlap and form one simply connected outline (an L, a T,
  a U or a rectangle), whose area per room lies in ``gen2.rules.AREA_PER_ROOM``;
* ``open_plan``: an opening wider than ``OPEN_PLAN_MIN`` joins two of the hub's rooms (living
  room, kitchen, dining room), any two;

and ``house-gen-3``'s ``targets``: at most one object of each small target category.
"""

from __future__ import annotations

from collections import Counter

from objsearch.house.gen2.floorplan import PUBLIC
from objsearch.house.gen2.rules import AREA_PER_ROOM, OPEN_PLAN_MIN, rule_problems
from objsearch.house.gen3.build import MAX_TARGET_INSTANCES, SMALL_TARGETS
from objsearch.house.gen4.build import AREA_LIMITS, house_outline
from objsearch.house.spec import OUTSIDE, HouseSpec
from objsearch.house.stages import StageFailure


def outline_area(poly) -> float:
    """The area of a simple polygon (shoelace)."""
    return abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]))) / 2


def footprint_problems(spec: HouseSpec) -> list[str]:
    """The ``footprint`` rule: one simply connected outline, no overlaps, a plausible area a room."""
    try:
        shape = house_outline([r.polygon for r in spec.rooms])
    except StageFailure as err:
        return [str(err)]
    total, area = sum(r.area for r in spec.rooms), outline_area(shape)
    out = []
    if abs(total - area) > 0.01 * area:
        out.append(f"rooms cover {total:.1f} m^2 of a {area:.1f} m^2 outline: some overlap")
    per_room = area / max(len(spec.rooms), 1)
    if not AREA_PER_ROOM[0] <= per_room <= AREA_PER_ROOM[1]:
        out.append(f"outline {per_room:.1f} m^2 per room, outside {AREA_PER_ROOM[0]}-{AREA_PER_ROOM[1]}")
    return out


def check_rules(spec: HouseSpec) -> list[str]:
    """Every problem of every rule, as one list (``validate_house`` appends it for ``house-gen-4``)."""
    problems = rule_problems(spec, AREA_LIMITS)
    types = {r.id: r.type for r in spec.rooms}
    problems["footprint"] = footprint_problems(spec)
    problems["open_plan"] = [
        f"door {d.id} is {d.width} m wide between {types.get(d.rooms[0])} and {types.get(d.rooms[1])}"
        for d in spec.doors
        if d.width > OPEN_PLAN_MIN and (OUTSIDE in d.rooms or not {types[d.rooms[0]], types[d.rooms[1]]} <= set(PUBLIC))
    ]
    counts = Counter(o.category for o in spec.objects if o.category in SMALL_TARGETS)
    return [f"{rule}: {msg}" for rule, msgs in problems.items() for msg in msgs] + [
        f"targets: {n} {cat} objects, more than {MAX_TARGET_INSTANCES}"
        for cat, n in sorted(counts.items())
        if n > MAX_TARGET_INSTANCES
    ]
