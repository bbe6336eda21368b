"""The hub of a ``house-gen-4`` house (``gen4.floorplan``): its public rooms (living room,
kitchen, dining room) tiling one rectangle, side by side or the living room beside the other
two, with the walls between them kept clear of the hallways that meet the hub.
"""

from __future__ import annotations

import numpy as np

from objsearch.house.gen4.wings import GRID, Rect, snap
from objsearch.house.spec import r4
from objsearch.house.stages import StageFailure

#: The narrowest a hub room may be (m): ``house-gen-2``'s widths plus room for the openings
#: a hub's rooms have on several sides.
HUB_MIN_WIDTH = {"living_room": 4.6, "kitchen": 3.3, "dining_room": 4.2}
HUB_MIN_DEPTH = 4.0
HUB_SLACK = 1.4  # a hub may be this much wider than it must, so that its walls miss the hallways
CORRIDOR_KEEP_CLEAR = 0.9  # a wall between hub rooms stays this far from a hallway's mouth


def _cut(lo: float, hi: float, share: float, mins: tuple[float, float], keep_clear: list[tuple[float, float]]) -> float:
    """A cut between ``lo`` and ``hi`` near ``share`` of the way, at least ``mins`` from either
    end, and either ``CORRIDOR_KEEP_CLEAR`` from every ``keep_clear`` span (a hallway's mouth)
    or in line with one of its walls; ``StageFailure`` if none."""
    a, b = r4(lo + mins[0]), r4(hi - mins[1])
    if a > b + 1e-6:
        raise StageFailure("the hub is too small for its rooms")
    b = max(a, b)
    want = min(max(lo + share * (hi - lo), a), b)

    def clear(y: float) -> bool:
        return a - 1e-6 <= y <= b + 1e-6 and all(
            not s0 - CORRIDOR_KEEP_CLEAR < y < s1 + CORRIDOR_KEEP_CLEAR or abs(y - s0) < 1e-6 or abs(y - s1) < 1e-6
            for s0, s1 in keep_clear
        )

    options = [want] + [
        y for s0, s1 in keep_clear for y in (s0 - CORRIDOR_KEEP_CLEAR, s0, s1, s1 + CORRIDOR_KEEP_CLEAR)
    ]
    options = [y for y in options if clear(y)]
    if not options:
        raise StageFailure("a wall of the hub would meet a hallway's mouth")
    return snap(min(options, key=lambda y: abs(y - want)))


def _arrangements(public: list[str], along: float, across: float) -> list[str]:
    """The hub arrangements that fit ``along`` x ``across`` m: ``slices`` (side by side along
    the long axis), ``beside`` (three rooms: the living room beside the other two)."""
    mins = [HUB_MIN_WIDTH[t] for t in public]
    out = ["slices"] if along >= sum(mins) - 1e-6 and across >= HUB_MIN_DEPTH - 1e-6 else []
    if len(public) == 3 and along >= mins[0] + max(mins[1:]) - 1e-6 and across >= mins[1] + mins[2] - 1e-6:
        out.append("beside")
    return out


def hub_width(public: list[str], hh: float, at_least: float, mouth_sides: set[str]) -> float:
    """The narrowest hub width, at least ``at_least``, whose hub of depth ``hh`` fits its rooms
    with walls that meet no hallway's mouth, if one within ``HUB_SLACK`` of the narrowest does."""
    mins = [HUB_MIN_WIDTH[t] for t in public]
    at_least = r4(np.ceil(at_least / GRID - 1e-6) * GRID)
    widths = [at_least] + sorted(
        w for w in {snap(v) for v in (sum(mins), mins[0] + max(mins[1:]), sum(mins[1:]))} if w > at_least
    )
    fits = [(w, min(c[0] for c in cs)) for w in widths if (cs := _candidates(public, w, hh, mouth_sides))]
    if not fits:
        raise StageFailure("no hub fits the public rooms")
    clean = [w for w, hits in fits if hits == 0 and w <= fits[0][0] * HUB_SLACK]
    return clean[0] if clean else fits[0][0]


def _candidates(types: list[str], hw: float, hh: float, mouth_sides: set[str]) -> list[tuple]:
    """The hub arrangements that fit: (how many sides with a hallway's mouth its walls meet,
    orientation, arrangement, living room first, the sides its slices' walls meet, the side
    the kitchen-dining wall meets)."""
    out = []
    for orient in ("x", "y"):
        along, across = (hw, hh) if orient == "x" else (hh, hw)
        main = ("N",) if orient == "x" else ("E", "W")  # the sides the walls between slices meet
        for arrangement in _arrangements(types, along, across):
            for first in (True, False) if arrangement == "beside" else (True,):
                far = (
                    (("E" if first else "W") if orient == "x" else ("N" if first else "S"))
                    if arrangement == "beside"
                    else ""
                )
                hits = sum(sd in mouth_sides for sd in main) + (far in mouth_sides)
                out.append((hits, orient, arrangement, first, main, far))
    return out


def hub_rooms(
    types: list[str], areas: list[float], hw: float, hh: float, mouths: dict[str, list[tuple[float, float]]], rng
) -> list[tuple[str, list[Rect]]]:
    """The public rooms ``types`` (living room first) tiling the hub ``[0, hw] x [0, hh]``:
    side by side, or (three rooms) the living room beside the other two.

    ``mouths`` holds, per side of the hub (``N``, ``E``, ``W``), the spans along it where a
    hallway meets the hub. Of the arrangements that fit, one whose walls meet the fewest sides
    with a mouth is drawn, and a wall that meets one keeps clear of the mouth (``_cut``).
    """
    candidates = _candidates(types, hw, hh, {sd for sd, spans in mouths.items() if spans})
    if not candidates:
        raise StageFailure(f"a {hw:.1f} x {hh:.1f} m hub does not fit {', '.join(types)}")
    fewest = min(c[0] for c in candidates)
    candidates = [c for c in candidates if c[0] == fewest]
    _, orient, arrangement, first, main, far = candidates[int(rng.integers(len(candidates)))]
    along, across = (hw, hh) if orient == "x" else (hh, hw)
    clear_main = [m for sd in main for m in mouths.get(sd, [])]
    total = sum(areas)
    if arrangement == "beside":
        rest = max(HUB_MIN_WIDTH[t] for t in types[1:])
        share = areas[0] / total if first else 1 - areas[0] / total
        mins = (HUB_MIN_WIDTH[types[0]], rest) if first else (rest, HUB_MIN_WIDTH[types[0]])
        x = _cut(0.0, along, share, mins, clear_main)
        y = _cut(
            0.0,
            across,
            areas[1] / (areas[1] + areas[2]),
            (HUB_MIN_WIDTH[types[1]], HUB_MIN_WIDTH[types[2]]),
            mouths.get(far, []),
        )
        (la, lb), (ka, kb) = ((0.0, x), (x, along)) if first else ((x, along), (0.0, x))
        local = [(types[0], (la, 0.0, lb, across)), (types[1], (ka, 0.0, kb, y)), (types[2], (ka, y, kb, across))]
    else:
        order = [types[int(k)] for k in rng.permutation(len(types))]
        share = {t: a for t, a in zip(types, areas)}
        cuts, lo = [], 0.0
        for k, t in enumerate(order[:-1]):
            rest = sum(HUB_MIN_WIDTH[s] for s in order[k + 1 :])
            lo = _cut(lo, along, share[t] / sum(share[s] for s in order[k:]), (HUB_MIN_WIDTH[t], rest), clear_main)
            cuts.append(lo)
        edges = [0.0, *cuts, along]
        local = [(t, (edges[k], 0.0, edges[k + 1], across)) for k, t in enumerate(order)]
    return [(t, [(a, b, c, d) if orient == "x" else (b, a, d, c)]) for t, (a, b, c, d) in local]
