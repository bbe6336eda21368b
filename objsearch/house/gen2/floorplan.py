"""Stages 1-2 of ``house-gen-2``: room program, per-type areas and a zoned floorplan.

After ProcTHOR's room specs (public and private zones, sizes per room type), written from
scratch as a band layout that guarantees the circulation rules by construction:

* **Program.** A living room, a kitchen, a bedroom and a bathroom (a 3-room house: living
  room, bedroom, bathroom); houses of 6 rooms or more add a hallway and a second bedroom;
  then bedrooms, a dining room, an office and a second bathroom by weight.
* **Sizes.** Every room draws a target area from ``AREA_RANGES`` (typical of real floor
  plans: a bathroom 3.5-7.5 m^2, a bedroom 9-15 m^2, ...); the footprint is the sum of the
  rooms, so it grows with their number.
* **Zones.** The footprint is three bands along its long axis: the *private band* (bedrooms,
  offices, bathrooms side by side), the *corridor* (the hallway, when there is one) and the
  *public band* (living room, kitchen, dining room, and bedrooms that do not fit in the
  private band). Every private room therefore touches the core (the corridor or a public
  room) with a full wall.
* **Bathrooms.** A bathroom either opens onto the core (a slot of the private band, as deep
  as its area asks; the strip behind it goes to the bedroom beside it, which becomes
  L-shaped) or is the en-suite of one bedroom (cut from a back corner of that bedroom, which
  becomes L-shaped; its only door is into the bedroom).
* **L-shaped living rooms.** With probability ``L_LIVING`` the living room also takes the
  end of the band below it: the first stretch of the corridor (an entrance hall) or of the
  private band.

The layout is finally mirrored and/or transposed at random. Room polygons are rectilinear
and counter-clockwise; a stage that cannot meet its rules raises ``StageFailure``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from objsearch.house.spec import r4
from objsearch.house.stages import StageFailure

GRID = 0.1
#: Target area (m^2) a room of each type draws from (hallways get what the corridor is).
AREA_RANGES = {
    "living_room": (16.0, 28.0),
    "kitchen": (7.0, 13.0),
    "dining_room": (10.0, 16.0),
    "bedroom": (9.0, 15.0),
    "office": (6.5, 10.0),
    "bathroom": (3.5, 7.5),
}
#: Areas (m^2) validation accepts: the targets widened for snapping and fitting the bands.
AREA_LIMITS = {
    "living_room": (12.0, 42.0),
    "kitchen": (6.0, 22.0),
    "dining_room": (7.0, 22.0),
    "bedroom": (7.0, 24.0),
    "office": (5.0, 16.0),
    "bathroom": (3.0, 9.0),
    "hallway": (2.5, 30.0),
}
PUBLIC = ("living_room", "kitchen", "dining_room")
CORE = ("living_room", "kitchen", "dining_room", "hallway")
PRIVATE = ("bedroom", "office")
EXTRA_WEIGHTS = {"bedroom": 3.0, "dining_room": 3.5, "office": 1.5, "bathroom": 1.5}
EXTRA_CAPS = {"bedroom": 4, "dining_room": 1, "office": 1, "bathroom": 2}
PRIVATE_BAND = (3.4, 4.4)  # depth of the private band, m
CORRIDOR = (1.5, 1.9)  # width of the corridor, m
PUBLIC_BAND = (3.8, 6.0)
MAX_PRIVATE_RUN = 13.0  # longer private bands move bedrooms to the public band (with a corridor)
MIN_WIDTH = {"living_room": 4.4, "kitchen": 2.9, "dining_room": 3.8, "bedroom": 2.6, "office": 2.6}
L_LIVING = 0.5
FRONT_FIRST_BATH = 0.85  # the first bathroom opens onto the core with this probability
ENSUITE_OTHER = 0.7  # further bathrooms are en-suite with this probability

Rect = tuple[float, float, float, float]
Polygon = tuple[tuple[float, float], ...]


MAX_PRIVATE_WIDTH = 4.6


def _snap(x: float) -> float:
    return r4(round(x / GRID) * GRID)


def _max_width(unit: dict) -> float:
    return MAX_PRIVATE_WIDTH + (unit["bath"][0] if unit["kind"] == "ensuite" else 0.0)


@dataclass
class Plan:
    """A floorplan: footprint (width, depth), and per room its type and ccw rectilinear polygon.

    ``ensuite`` maps a bathroom's index to the bedroom it is the en-suite of; ``hallway`` is
    the corridor's index (None without one).
    """

    width: float
    depth: float
    types: list[str]
    polygons: list[Polygon]
    ensuite: dict[int, int] = field(default_factory=dict)
    hallway: int | None = None


def room_program(num_rooms: int, rng: np.random.Generator) -> list[str]:
    """The multiset of room types for a ``house-gen-2`` house with ``num_rooms`` rooms."""
    if num_rooms == 3:
        return ["living_room", "bedroom", "bathroom"]
    types = ["living_room", "kitchen", "bedroom", "bathroom"]
    if num_rooms >= 6:
        types += ["hallway", "bedroom"]
    while len(types) < num_rooms:
        options = [t for t in EXTRA_WEIGHTS if types.count(t) < EXTRA_CAPS[t]]
        w = np.array([EXTRA_WEIGHTS[t] for t in options])
        types.append(options[int(rng.choice(len(options), p=w / w.sum()))])
    return types


def outline(rects: list[Rect]) -> Polygon:
    """The counter-clockwise outline of a simply connected union of axis-aligned rectangles."""
    xs = sorted({v for r in rects for v in (r[0], r[2])})
    ys = sorted({v for r in rects for v in (r[1], r[3])})

    def inside(i: int, j: int) -> bool:
        if not (0 <= i < len(xs) - 1 and 0 <= j < len(ys) - 1):
            return False
        cx, cy = (xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2
        return any(r[0] < cx < r[2] and r[1] < cy < r[3] for r in rects)

    nxt: dict[tuple[float, float], tuple[float, float]] = {}
    for i in range(len(xs) - 1):
        for j in range(len(ys) - 1):
            if not inside(i, j):
                continue
            x0, x1, y0, y1 = xs[i], xs[i + 1], ys[j], ys[j + 1]
            if not inside(i, j - 1):
                nxt[(x0, y0)] = (x1, y0)
            if not inside(i + 1, j):
                nxt[(x1, y0)] = (x1, y1)
            if not inside(i, j + 1):
                nxt[(x1, y1)] = (x0, y1)
            if not inside(i - 1, j):
                nxt[(x0, y1)] = (x0, y0)
    start = min(nxt, key=lambda p: (p[1], p[0]))
    pts, p = [start], nxt[start]
    while p != start:
        pts.append(p)
        p = nxt[p]
    if len(pts) != len(nxt):
        raise StageFailure("a room is not one simply connected shape")
    # drop the collinear points
    out = [
        pts[k]
        for k in range(len(pts))
        if not (pts[k - 1][0] == pts[k][0] == pts[(k + 1) % len(pts)][0])
        and not (pts[k - 1][1] == pts[k][1] == pts[(k + 1) % len(pts)][1])
    ]
    return tuple((r4(x), r4(y)) for x, y in out)


def _distribute(total: float, wants: list[float], mins: list[float]) -> list[float]:
    """Widths summing to ``total``, proportional to ``wants`` but each at least its minimum."""
    fixed = [False] * len(wants)
    widths = list(wants)
    for _ in range(len(wants) + 1):
        free = total - sum(m for m, f in zip(mins, fixed) if f)
        scale = free / max(sum(w for w, f in zip(wants, fixed) if not f), 1e-9)
        widths = [m if f else w * scale for w, m, f in zip(wants, mins, fixed)]
        low = [k for k, (w, m, f) in enumerate(zip(widths, mins, fixed)) if not f and w < m - 1e-9]
        if not low:
            break
        for k in low:
            fixed[k] = True
    return widths


def _cuts(x0: float, widths: list[float], x_end: float) -> list[tuple[float, float]]:
    """Snapped consecutive intervals from ``x0`` with these widths, the last ending at ``x_end``."""
    out, x, acc = [], x0, x0
    for k, w in enumerate(widths):
        acc += w
        x1 = x_end if k == len(widths) - 1 else _snap(acc)
        out.append((x, x1))
        x = x1
    return out


def plan_house(
    types: list[str],
    rng: np.random.Generator,
    max_private_run: float = MAX_PRIVATE_RUN,
    area_limits: dict[str, tuple[float, float]] = AREA_LIMITS,
    area_ranges: dict[str, tuple[float, float]] = AREA_RANGES,
) -> Plan:
    """Lay out the rooms of ``types`` (see the module docstring); raises ``StageFailure`` when it cannot.

    ``max_private_run`` (m), ``area_limits`` and ``area_ranges`` are ``house-gen-2``'s by default;
    ``house-gen-3`` passes its own (longer private bands, larger rooms and corridors) and draws
    the same way otherwise.
    """
    hall = "hallway" in types
    dp = _snap(rng.uniform(*PRIVATE_BAND))
    c = _snap(rng.uniform(*CORRIDOR)) if hall else 0.0
    privs = [t for t in types if t in PRIVATE]
    privs = [privs[int(k)] for k in rng.permutation(len(privs))]
    units = [{"kind": "room", "type": t, "area": rng.uniform(*area_ranges[t])} for t in privs]
    for b in range(types.count("bathroom")):
        area = rng.uniform(*area_ranges["bathroom"])
        hosts = [u for u in units if u["kind"] == "room" and u["type"] == "bedroom"]
        ensuite = bool(hosts) and dp >= 3.8 and rng.random() < (1 - FRONT_FIRST_BATH if b == 0 else ENSUITE_OTHER)
        if ensuite:
            host = hosts[int(rng.integers(len(hosts)))]
            bw = _snap(rng.uniform(1.7, 2.3))
            bd = _snap(min(max(area / bw, 1.6, 3.2 / bw), dp - 2.0))
            host.update(kind="ensuite", bath=(bw, bd), side=int(rng.integers(2)))
        else:
            bw = _snap(rng.uniform(1.8, 2.4))
            bd = _snap(max(area / bw, 1.6))
            if bd > dp - 1.0:
                bd, bw = dp, min(bw, np.floor(8.8 / dp / GRID) * GRID)
            units.insert(int(rng.integers(len(units) + 1)), {"kind": "bath", "width": r4(bw), "depth": bd})
    for u in units:
        if u["kind"] == "room":
            u["width"] = min(max(u["area"] / dp, MIN_WIDTH[u["type"]]), 5.0)
        elif u["kind"] == "ensuite":
            bw, bd = u["bath"]
            u["width"] = max((u["area"] + bw * bd) / dp, bw + 2.4)
    # a partial-depth bathroom gives the strip behind it to a plain neighbour
    for k, u in enumerate(units):
        if u["kind"] == "bath" and u["depth"] < dp:
            order = [k - 1, k + 1] if rng.random() < 0.5 else [k + 1, k - 1]
            host = next(
                (j for j in order if 0 <= j < len(units) and units[j]["kind"] == "room" and "strip" not in units[j]),
                None,
            )
            if host is None:
                u["depth"], u["width"] = dp, min(u["width"], np.floor(8.8 / dp / GRID) * GRID)
            else:
                units[host]["strip"] = k
                u["host"] = host
    top_privs: list[dict] = []
    if hall:  # a long private band sends plain rooms (without a strip) to the public band
        while sum(u["width"] for u in units) > max_private_run:
            movable = [j for j, u in enumerate(units) if u["kind"] == "room" and "strip" not in u]
            if not movable:
                break
            j = movable[-1]
            top_privs.append(units.pop(j))
            for u in units:  # indices of strip hosts shift
                if u.get("host", -1) > j:
                    u["host"] -= 1
            for u in units:
                if u.get("strip", -1) > j:
                    u["strip"] -= 1
    # public band
    pubs = [t for t in types if t in PUBLIC and t != "living_room"]
    pubs = ["living_room"] + [pubs[int(k)] for k in rng.permutation(len(pubs))]
    areas = [rng.uniform(*area_ranges[t]) for t in pubs]
    leg = rng.random() < L_LIVING
    x_a = _snap(rng.uniform(2.2, 3.2)) if leg else 0.0
    leg_depth = c if hall else dp
    if leg:
        areas[0] = max(areas[0] - x_a * leg_depth, 10.0)
    top_types = pubs + [u["type"] for u in top_privs]
    top_areas = areas + [u["area"] for u in top_privs]
    mins = [MIN_WIDTH[t] for t in top_types]
    if leg and hall:
        mins[0] = max(mins[0], x_a + 1.7)
    x0_bottom = x_a if (leg and not hall) else 0.0
    w_bottom = x0_bottom + sum(u["width"] for u in units)
    width = _snap(max(w_bottom, sum(mins) + 0.1, sum(top_areas) / PUBLIC_BAND[1]))
    dpub = _snap(min(max(sum(top_areas) / width, PUBLIC_BAND[0]), PUBLIC_BAND[1]))
    depth = r4(dp + c + dpub)
    # widen the bedrooms and offices of the private band to the footprint's width
    grow = [u for u in units if u["kind"] != "bath"]
    spare = width - w_bottom
    for _ in range(3):  # up to MAX_PRIVATE_WIDTH first, shared by width
        room_to_grow = [u for u in grow if u["width"] < _max_width(u) - 1e-6]
        if spare <= 1e-6 or not room_to_grow:
            break
        total = sum(u["width"] for u in room_to_grow)
        for u in room_to_grow:
            add = min(spare * u["width"] / total, _max_width(u) - u["width"])
            u["width"] += add
        spare = width - x0_bottom - sum(u["width"] for u in units)
    if spare > 1e-6 and not hall and (leg or spare >= 2.2):  # the rest goes to the living room's leg
        leg, x_a = True, r4(x0_bottom + spare)
        x0_bottom = x_a
    elif spare > 1e-6:
        if not grow:
            raise StageFailure("the private band has no room to widen")
        total = sum(u["width"] for u in grow)
        for u in grow:
            u["width"] += spare * u["width"] / total
    top_widths = _distribute(width, [a / dpub for a in top_areas], mins)
    if any(w < m - 0.05 for w, m in zip(top_widths, mins)):
        raise StageFailure("the public band is too narrow for its rooms")
    # rectangles
    rooms: list[tuple[str, list[Rect]]] = []
    y_top = r4(dp + c)
    for t, (a, b) in zip(top_types, _cuts(0.0, top_widths, width)):
        rooms.append((t, [(a, y_top, b, depth)]))
    if leg:
        rooms[0][1].append((0.0, dp if hall else 0.0, x_a, y_top))
    hallway = None
    if hall:
        hallway = len(rooms)
        rooms.append(("hallway", [(x_a, dp, width, y_top)]))
    ensuite: dict[int, int] = {}
    index: dict[int, int] = {}
    strips: list[tuple[int, Rect]] = []
    for k, (u, (a, b)) in enumerate(zip(units, _cuts(x0_bottom, [u["width"] for u in units], width))):
        index[k] = len(rooms)
        if u["kind"] == "room":
            rooms.append((u["type"], [(a, 0.0, b, dp)]))
        elif u["kind"] == "ensuite":
            bw, bd = u["bath"]
            if b - a < bw + 2.2:
                raise StageFailure("an en-suite bedroom is too narrow")
            if u["side"] == 0:
                bath, rest = (a, 0.0, r4(a + bw), bd), (r4(a + bw), 0.0, b, bd)
            else:
                bath, rest = (r4(b - bw), 0.0, b, bd), (a, 0.0, r4(b - bw), bd)
            rooms.append(("bedroom", [rest, (a, bd, b, dp)]))
            ensuite[len(rooms)] = len(rooms) - 1
            rooms.append(("bathroom", [bath]))
        else:
            bd = u["depth"]
            rooms.append(("bathroom", [(a, r4(dp - bd), b, dp)]))
            if bd < dp:
                strips.append((u["host"], (a, 0.0, b, r4(dp - bd))))
    for host, rect in strips:
        rooms[index[host]][1].append(rect)
    # mirror and transpose at random, for variety
    fx, fy, tr = rng.random() < 0.5, rng.random() < 0.5, rng.random() < 0.5

    def move(r: Rect) -> Rect:
        x0, y0, x1, y1 = r
        if fx:
            x0, x1 = r4(width - x1), r4(width - x0)
        if fy:
            y0, y1 = r4(depth - y1), r4(depth - y0)
        return (y0, x0, y1, x1) if tr else (x0, y0, x1, y1)

    polygons = [outline([move(r) for r in rects]) for _, rects in rooms]
    for t, rects in rooms:
        area = sum((r[2] - r[0]) * (r[3] - r[1]) for r in rects)
        lo, hi = area_limits[t]
        if not lo <= area <= hi:
            raise StageFailure(f"a {t} of {area:.1f} m^2 is outside {lo}-{hi} m^2")
    w, d = (depth, width) if tr else (width, depth)
    return Plan(w, d, [t for t, _ in rooms], polygons, ensuite, hallway)
