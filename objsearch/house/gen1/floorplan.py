"""Stages 1-2 of ``house-gen-1``: footprint, rooms (recursive splits of a rectangle) and room types.

A size class fixes the footprint range and the number of rooms (``stages.SIZE_CLASSES``). The
footprint rectangle is split recursively (largest room first, across its longer side, at
35-65 %, snapped to 0.1 m) until there are as many rooms as the room program asks for, no
room narrower than ``MIN_ROOM_SIDE``. Types then go to rooms by size: the living room gets
the largest, bathrooms the smallest, a hallway the most elongated (ProcTHOR's room specs,
reduced to a ranking).
"""

from __future__ import annotations

import numpy as np

from objsearch.house.spec import r4
from objsearch.house.stages import SIZE_CLASSES, StageFailure

GRID = 0.1
MIN_ROOM_SIDE = 2.2

# Relative size rank of each room type (largest first); noise keeps it from being rigid.
SIZE_RANK = {
    "living_room": 1.0,
    "dining_room": 0.62,
    "kitchen": 0.58,
    "bedroom": 0.5,
    "office": 0.36,
    "hallway": 0.3,
    "bathroom": 0.15,
}
EXTRA_WEIGHTS = {"bedroom": 3.0, "dining_room": 2.0, "office": 2.0, "bathroom": 1.5, "hallway": 1.5}
EXTRA_CAPS = {"bedroom": 4, "dining_room": 1, "office": 2, "bathroom": 3, "hallway": 1}


Rect = tuple[float, float, float, float]


def _snap(x: float) -> float:
    return r4(round(x / GRID) * GRID)


def room_program(num_rooms: int, rng: np.random.Generator) -> list[str]:
    """The multiset of room types for a house with ``num_rooms`` rooms."""
    if num_rooms == 3:
        return ["living_room", "bathroom", str(rng.choice(["kitchen", "bedroom"]))]
    types = ["living_room", "kitchen", "bathroom", "bedroom"]
    while len(types) < num_rooms:
        options = [t for t in EXTRA_WEIGHTS if types.count(t) < EXTRA_CAPS[t]]
        w = np.array([EXTRA_WEIGHTS[t] for t in options])
        types.append(options[int(rng.choice(len(options), p=w / w.sum()))])
    return types


def footprint(size_class: str, rng: np.random.Generator) -> tuple[float, float]:
    """A house footprint (width, depth) in metres for ``size_class``, drawn from ``rng`` and snapped."""
    lo, hi = SIZE_CLASSES[size_class]["side"]
    return _snap(rng.uniform(lo, hi)), _snap(rng.uniform(lo, hi))


def split_rooms(width: float, depth: float, num_rooms: int, rng: np.random.Generator) -> list[Rect]:
    """Split the footprint into ``num_rooms`` rectangles (x0, y0, x1, y1)."""
    rects: list[Rect] = [(0.0, 0.0, width, depth)]
    while len(rects) < num_rooms:
        areas = np.array([(r[2] - r[0]) * (r[3] - r[1]) for r in rects])
        order = np.argsort(-(areas * rng.uniform(0.8, 1.2, len(rects))), kind="stable")
        for i in order:
            x0, y0, x1, y1 = rects[i]
            w, d = x1 - x0, y1 - y0
            axes = ["x", "y"] if w >= d else ["y", "x"]
            if 0.8 < w / d < 1.25 and rng.random() < 0.5:
                axes.reverse()
            done = False
            for axis in axes:
                lo, hi = (x0, x1) if axis == "x" else (y0, y1)
                if hi - lo < 2 * MIN_ROOM_SIDE:
                    continue
                cut = _snap(lo + (hi - lo) * rng.uniform(0.35, 0.65))
                cut = min(max(cut, _snap(lo + MIN_ROOM_SIDE + GRID / 2)), _snap(hi - MIN_ROOM_SIDE - GRID / 2))
                if axis == "x":
                    rects[i : i + 1] = [(x0, y0, cut, y1), (cut, y0, x1, y1)]
                else:
                    rects[i : i + 1] = [(x0, y0, x1, cut), (x0, cut, x1, y1)]
                done = True
                break
            if done:
                break
        else:
            raise StageFailure(f"cannot split a {width}x{depth} m footprint into {num_rooms} rooms")
    return rects


def assign_types(rects: list[Rect], types: list[str], rng: np.random.Generator) -> list[str]:
    """Give each rectangle a type: by area rank, hallway to the most elongated mid-size room."""
    n = len(rects)
    areas = np.array([(r[2] - r[0]) * (r[3] - r[1]) for r in rects])
    assigned: list[str | None] = [None] * n
    free = list(range(n))
    pending = list(types)
    if "hallway" in pending:
        largest = int(np.argmax(areas))
        cands = [i for i in free if i != largest]
        aspect = [
            max(rects[i][2] - rects[i][0], rects[i][3] - rects[i][1])
            / min(rects[i][2] - rects[i][0], rects[i][3] - rects[i][1])
            for i in cands
        ]
        h = cands[int(np.argmax(aspect))]
        assigned[h] = "hallway"
        free.remove(h)
        pending.remove("hallway")
    by_area = sorted(free, key=lambda i: -areas[i])
    by_rank = sorted(pending, key=lambda t: -(SIZE_RANK[t] + rng.normal(0, 0.06)))
    for i, t in zip(by_area, by_rank):
        assigned[i] = t
    return [str(t) for t in assigned]
