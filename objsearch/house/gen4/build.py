"""``build_spec`` of ``house-gen-4``: family and room program -> hub and wings
(``gen4.floorplan``) -> ``house-gen-2``'s doors and entrance, then an open plan with
``OPEN_PLAN`` -> walls along the house's outline, furniture and fill -> small targets thinned
to one a category (``house-gen-3``'s ``thin_targets``).

The room program is ``house-gen-3``'s (4-14 rooms; 2-5 bedrooms, 2-3 bathrooms and 1-2
offices from 9 rooms), with one hallway per corridor wing in place of its one hallway, so a
``rooms-N`` house still has N rooms. Randomness: ``numpy.random.default_rng([seed, attempt,
split, STREAM])``. Frozen once a suite ships on it: a change that gives a seed another house
is a new version.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from objsearch.house.gen2.build import spec_of_plan
from objsearch.house.gen2.doors import DOOR_MARGIN, place_doors, shared_segments
from objsearch.house.gen2.floorplan import PUBLIC, Plan, outline
from objsearch.house.gen3.build import AREA_RANGES, room_program, thin_targets
from objsearch.house.gen4.floorplan import FAMILIES, FAMILY_WEIGHTS, ROW_WING, Unit, plan_house, snap
from objsearch.house.spec import Door, HouseSpec, r4
from objsearch.house.stages import ROOM_COUNT_CLASSES, SPLITS, WALL_THICKNESS, StageFailure, house_id

VERSION = "house-gen-4"
STREAM = 4
DEFAULT_SIZE_CLASS = "xlarge"
ENSUITE_FIRST = 0.15  # the first bathroom is an en-suite with this probability
ENSUITE_OTHER = 0.6  # further bathrooms are, with this one
OPEN_PLAN = 0.45  # the hub's rooms open into each other across (nearly) whole walls
OPEN_MAX = 4.5  # m, the widest open-plan opening
OPEN_MIN_WALL = 2.6  # m of shared wall an open-plan opening needs
FAMILY_TRIES = 16
#: Areas (m^2) validation accepts: ``house-gen-3``'s, with the hub's rooms as large as a hub
#: that spans the wings beside it makes them.
AREA_LIMITS = {
    "living_room": (12.0, 62.0),
    "kitchen": (6.0, 34.0),
    "dining_room": (7.0, 34.0),
    "bedroom": (7.0, 32.0),
    "office": (5.0, 22.0),
    "bathroom": (3.0, 12.0),
    "hallway": (2.5, 60.0),
}


def default_size_class(seed: int) -> str:
    """The size class of a seed given none: ``xlarge`` (9-14 rooms, drawn in ``build_spec``)."""
    return DEFAULT_SIZE_CLASS


def draw_layout(num_rooms: int, rng: np.random.Generator) -> tuple[str, list[bool], list[str], list[Unit]]:
    """The family, which wings are rows (entered from the hub, no hallway), the hub's room
    types (living room first) and the wings' units of a house of ``num_rooms`` rooms: families
    are redrawn (``FAMILY_TRIES``) until the program has the private rooms their wings need."""
    corridors = num_rooms >= 6
    for _ in range(FAMILY_TRIES):
        names = [f for f in FAMILY_WEIGHTS if corridors or f in ("bar", "L")]
        w = np.array([FAMILY_WEIGHTS[f] for f in names])
        family = names[int(rng.choice(len(names), p=w / w.sum()))]
        sides = FAMILIES[family]
        rows = [
            not corridors or (k > 0 and family in ("bar2", "T") and rng.random() < ROW_WING) for k in range(len(sides))
        ]
        halls = sum(not r for r in rows)
        if corridors and num_rooms - halls + 1 < 6:
            continue
        types = room_program(num_rooms - halls + (1 if corridors else 0), rng)
        types = [t for t in types if t != "hallway"]
        public = ["living_room"] + [t for t in types if t in PUBLIC and t != "living_room"]
        units = _units([t for t in types if t not in PUBLIC], rng)
        if len(units) >= sum(1 if r else 2 for r in rows):
            return family, rows, public, [units[int(k)] for k in rng.permutation(len(units))]
    raise StageFailure(f"no floorplan family fits {num_rooms} rooms")


def _units(private: list[str], rng: np.random.Generator) -> list[Unit]:
    """Bedrooms, offices and bathrooms to place; a bathroom may be a bedroom's en-suite."""
    units = [Unit(t, rng.uniform(*AREA_RANGES[t])) for t in private if t != "bathroom"]
    for b in range(private.count("bathroom")):
        area = rng.uniform(*AREA_RANGES["bathroom"])
        hosts = [u for u in units if u.type == "bedroom" and u.bath is None]
        if hosts and rng.random() < (ENSUITE_FIRST if b == 0 else ENSUITE_OTHER):
            bw = snap(rng.uniform(1.7, 2.3))
            hosts[int(rng.integers(len(hosts)))].bath = (bw, snap(max(area / bw, 1.6, 3.2 / bw)))
        else:
            units.append(Unit("bathroom", area))
    return units


def open_plan(plan: Plan, doors: list[Door], rng: np.random.Generator, thickness: float) -> list[Door]:
    """With ``OPEN_PLAN``, the two hub rooms that share the longest wall (at least
    ``OPEN_MIN_WALL``) open into each other across nearly all of it (at most ``OPEN_MAX``):
    no door and almost no wall between them."""
    if rng.random() >= OPEN_PLAN:
        return doors
    hub = [i for i, t in enumerate(plan.types) if t in PUBLIC]
    walls = []
    for a in hub:
        for b in hub:
            segs = shared_segments(plan.polygons[a], plan.polygons[b]) if a < b else []
            walls += [((a, b), s) for s in segs if s[3] - s[2] >= OPEN_MIN_WALL]
    if not walls:
        return doors
    (a, b), (axis, fixed, lo, hi) = max(walls, key=lambda w: (w[1][3] - w[1][2], w[0]))
    width = r4(round(min(hi - lo - 2 * DOOR_MARGIN - thickness - 0.05, OPEN_MAX), 2))
    c = r4(round((lo + hi) / 2, 2))
    center = (c, r4(fixed)) if axis == "x" else (r4(fixed), c)
    opening = Door(0, (a, b), axis, center, width, doors[0].height)
    kept = [d for d in doors if set(d.rooms) != {a, b}]
    return [replace(d, id=k) for k, d in enumerate([opening, *kept])]


def build_spec(seed: int, size_class: str, split: str, attempt: int) -> HouseSpec:
    """Run the ``house-gen-4`` stages once; raises ``StageFailure`` when a rule cannot be met."""
    rng = np.random.default_rng([seed, attempt, SPLITS[split], STREAM])
    lo, hi = ROOM_COUNT_CLASSES[size_class]
    family, rows, public, units = draw_layout(int(rng.integers(lo, hi + 1)), rng)
    plan = plan_house(public, units, family, rows, rng, AREA_RANGES)
    for t, poly in zip(plan.types, plan.polygons):
        area = _area(poly)
        a_lo, a_hi = AREA_LIMITS[t]
        if not a_lo <= area <= a_hi:
            raise StageFailure(f"a {t} of {area:.1f} m^2 is outside {a_lo}-{a_hi} m^2")
    doors = open_plan(plan, place_doors(plan, rng, WALL_THICKNESS), rng, WALL_THICKNESS)
    spec = spec_of_plan(
        plan,
        doors,
        rng,
        house_id(seed, split),
        seed,
        size_class,
        split,
        attempt,
        extra={"floorplan": family},
        version=VERSION,
        outline=house_outline(plan.polygons),
    )
    return thin_targets(spec, rng)


def _area(poly) -> float:
    return abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]))) / 2


def house_outline(polygons) -> tuple[tuple[float, float], ...]:
    """The counter-clockwise outline of the union of the room ``polygons`` (``StageFailure``
    if it is not one simply connected shape)."""
    xs = sorted({x for p in polygons for x, _ in p})
    ys = sorted({y for p in polygons for _, y in p})
    cells = []
    for i in range(len(xs) - 1):
        for j in range(len(ys) - 1):
            cx, cy = (xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2
            if any(_inside(p, cx, cy) for p in polygons):
                cells.append((xs[i], ys[j], xs[i + 1], ys[j + 1]))
    return outline(cells)


def _inside(poly, x: float, y: float) -> bool:
    """Whether (x, y) lies inside the polygon (even-odd rule; never on an edge here)."""
    inside = False
    for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside
