"""The wings of a ``house-gen-4`` house (``gen4.floorplan``): a corridor wing (a hallway from
the hub outwards, rooms on one side of it or both, maybe a bedroom across its far end) or a
row of rooms entered straight from the hub; bedrooms may have an en-suite bathroom cut from
their back corner. A wing is laid out in its own frame (``u`` from the hub, ``v`` across).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from objsearch.house.gen2.floorplan import MIN_WIDTH
from objsearch.house.spec import r4

GRID = 0.1
DOUBLE_LOADED = 0.7  # a corridor wing of 3 rooms or more has rooms on both sides of its hallway
END_ROOM = 0.5  # a corridor wing of 4 rooms or more ends in a bedroom across its far end
MAX_ROOM_WIDTH = 5.2

Rect = tuple[float, float, float, float]


def snap(x: float) -> float:
    """``x`` on the 0.1 m grid."""
    return r4(round(x / GRID) * GRID)


@dataclass
class Unit:
    """A private room to place: its type, target area (m^2) and, for a bedroom with an
    en-suite bathroom, the bathroom's (width, depth); ``width`` along the wing, once drawn."""

    type: str
    area: float
    bath: tuple[float, float] | None = None
    width: float = 0.0


@dataclass
class Wing:
    """A wing in its own frame: ``u`` from the hub (0) outwards to ``length``, ``v`` across it
    (0 to ``width``). ``rooms`` holds (type, [rects]); ``ensuite`` maps a bathroom's index to
    its bedroom's; ``hallway`` is the corridor's index, None for a row wing."""

    length: float
    width: float
    rooms: list[tuple[str, list[Rect]]]
    ensuite: dict[int, int]
    hallway: int | None
    mouth: tuple[float, float] | None  # the corridor's span along v where it meets the hub

    def mirrored(self) -> Wing:
        """The wing mirrored across its axis (``v`` -> ``width - v``)."""
        w = self.width

        def flip(r: Rect) -> Rect:
            return (r[0], r4(w - r[3]), r[2], r4(w - r[1]))

        rooms = [(t, [flip(r) for r in rects]) for t, rects in self.rooms]
        mouth = None if self.mouth is None else (r4(w - self.mouth[1]), r4(w - self.mouth[0]))
        return Wing(self.length, w, rooms, self.ensuite, self.hallway, mouth)


def _room_width(unit: Unit, depth: float) -> float:
    if unit.type == "bathroom":
        return snap(min(max(unit.area / depth, 1.8), 2.6))
    extra = unit.bath[0] * unit.bath[1] if unit.bath else 0.0
    lo = max(MIN_WIDTH[unit.type], unit.bath[0] + 2.4 if unit.bath else 0.0)
    return snap(min(max((unit.area + extra) / depth, lo), MAX_ROOM_WIDTH + (unit.bath[0] if unit.bath else 0.0)))


def _side(units: list[Unit], back: float, front: float, rng) -> list[tuple[str, list[Rect]]]:
    """Rooms of one side of a wing, consecutive along ``u`` from the hub; ``back`` is the v of
    the outer wall, ``front`` of the corridor (either may be the larger)."""
    rooms: list[tuple[str, list[Rect]]] = []
    v_lo, v_hi = min(back, front), max(back, front)
    u = 0.0
    for unit in units:
        a, b = r4(u), r4(u + unit.width)
        if unit.bath is None:
            rooms.append((unit.type, [(a, v_lo, b, v_hi)]))
        else:
            bw, bd = unit.bath
            left = rng.random() < 0.5
            ba, bb = (a, r4(a + bw)) if left else (r4(b - bw), b)
            bv = (v_lo, r4(v_lo + bd)) if back == v_lo else (r4(v_hi - bd), v_hi)
            rest_v = (bv[1], v_hi) if back == v_lo else (v_lo, bv[0])
            rest_u = (bb, b) if left else (a, ba)
            rooms.append(("bedroom", [(rest_u[0], bv[0], rest_u[1], bv[1]), (a, rest_v[0], b, rest_v[1])]))
            rooms.append(("bathroom", [(ba, bv[0], bb, bv[1])]))
        u += unit.width
    return rooms


def _stretch(units: list[Unit], length: float) -> None:
    """Widen ``units`` (bedrooms and offices first) so that they run ``length`` along the wing."""
    spare = length - sum(u.width for u in units)
    grow = [u for u in units if u.type != "bathroom"] or units
    total = sum(u.width for u in grow)
    for u in grow:
        u.width += spare * u.width / total
    acc, out = 0.0, 0.0
    for u in units:  # snap the running sum, so that the rooms still end exactly at ``length``
        acc += u.width
        u.width = r4(snap(acc) - out)
        out = snap(acc)
    units[-1].width = r4(units[-1].width + length - out)


def corridor_wing(
    units: list[Unit], depth: float, corridor: float, rng: np.random.Generator, double: bool | None = None
) -> Wing:
    """A hallway with ``units`` on one side or both (``double``; None: drawn), and maybe a
    bedroom across its far end."""
    units = list(units)
    if double is None:
        double = len(units) >= 3 and rng.random() < DOUBLE_LOADED
    width = r4(depth * (2 if double else 1) + corridor)
    end = None
    plain = [k for k, u in enumerate(units) if u.type == "bedroom" and u.bath is None]
    if double and len(units) >= 4 and plain and rng.random() < END_ROOM:
        end = units.pop(plain[int(rng.integers(len(plain)))])
    for u in units:
        u.width = _room_width(u, depth)
    sides: list[list[Unit]] = [[], []]
    for u in units:  # the next room to the shorter side
        k = 0 if not double else int(np.argmin([sum(x.width for x in s) for s in sides]))
        sides[k].append(u)
    length = snap(max(sum(u.width for u in s) for s in sides))
    rooms: list[tuple[str, list[Rect]]] = []
    for k, side in enumerate(sides):
        if not side:
            continue
        _stretch(side, length)
        back, front = (0.0, depth) if k == 0 else (width, r4(width - depth))
        rooms += _side(side, back, front, rng)
    hallway = len(rooms)
    rooms.append(("hallway", [(0.0, depth, length, r4(depth + corridor))]))
    if end is not None:
        e = snap(min(max(end.area / width, 2.8), 3.6))
        rooms.append(("bedroom", [(length, 0.0, r4(length + e), width)]))
        length = r4(length + e)
    return Wing(length, width, rooms, _ensuites(rooms), hallway, (depth, r4(depth + corridor)))


def row_wing(units: list[Unit], depth: float, rng: np.random.Generator) -> Wing:
    """``units`` side by side along the hub, each entered from the hub room it touches."""
    for u in units:
        u.width = _room_width(u, depth)
    rooms: list[tuple[str, list[Rect]]] = []
    v = 0.0
    for u in units:
        a, b = r4(v), r4(v + u.width)
        if u.bath is None:
            rooms.append((u.type, [(0.0, a, depth, b)]))
        else:  # the bathroom in the back corner, away from the hub
            bw, bd = u.bath
            bu = r4(depth - bd)
            lo = rng.random() < 0.5
            bath = (bu, a, depth, r4(a + bw)) if lo else (bu, r4(b - bw), depth, b)
            rest = (bu, r4(a + bw), depth, b) if lo else (bu, a, depth, r4(b - bw))
            rooms.append(("bedroom", [(0.0, a, bu, b), rest]))
            rooms.append(("bathroom", [bath]))
        v += u.width
    return Wing(depth, r4(v), rooms, _ensuites(rooms), None, None)


def _ensuites(rooms) -> dict[int, int]:
    """Each bathroom cut from a bedroom (the room before it, with two rectangles) -> that bedroom."""
    return {k: k - 1 for k, (t, _) in enumerate(rooms) if t == "bathroom" and k and len(rooms[k - 1][1]) == 2}
