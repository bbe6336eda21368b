"""Stage 6: floor and wall materials per room type, with variation, and object colours.

Each room type has floor and wall palettes (wood or carpet in living rooms and bedrooms,
tiles in kitchens and bathrooms); a room picks one entry and jitters its colour a little.
Objects pick a colour from their category's palette (``categories.Category.colors``) and
jitter it the same way.
"""

from __future__ import annotations

import numpy as np

from objsearch.house.categories import Category
from objsearch.house.spec import Material, r4

WOOD_FLOOR = [("flat", (0.55, 0.4, 0.27)), ("flat", (0.68, 0.52, 0.36)), ("flat", (0.42, 0.3, 0.2))]
CARPET = [("flat", (0.55, 0.55, 0.6)), ("flat", (0.7, 0.65, 0.58)), ("flat", (0.45, 0.5, 0.45))]
TILES = [("checker", (0.9, 0.9, 0.88)), ("checker", (0.7, 0.75, 0.8)), ("checker", (0.8, 0.72, 0.6))]
PAINT = [(0.93, 0.92, 0.88), (0.85, 0.88, 0.9), (0.9, 0.85, 0.78), (0.8, 0.86, 0.8), (0.95, 0.95, 0.95)]
BATH_WALL = [(0.85, 0.92, 0.95), (0.95, 0.95, 0.95), (0.8, 0.85, 0.88)]

FLOORS = {
    "living_room": WOOD_FLOOR + CARPET[:1],
    "dining_room": WOOD_FLOOR,
    "kitchen": TILES,
    "bathroom": TILES,
    "bedroom": WOOD_FLOOR + CARPET,
    "office": WOOD_FLOOR + CARPET[:1],
    "hallway": WOOD_FLOOR + TILES[:1],
}
WALLS = {t: (BATH_WALL if t == "bathroom" else PAINT) for t in FLOORS}
EXTERIOR = Material("exterior", (0.75, 0.72, 0.68, 1.0))


def jitter(rgb, rng: np.random.Generator, amount: float = 0.05) -> tuple[float, float, float, float]:
    """``rgb`` with each channel moved by up to ``amount`` (clipped to [0, 1]), as opaque RGBA."""
    c = np.clip(np.asarray(rgb, dtype=float) + rng.uniform(-amount, amount, 3), 0.0, 1.0)
    return (r4(c[0]), r4(c[1]), r4(c[2]), 1.0)


def room_materials(room_id: int, room_type: str, rng: np.random.Generator) -> tuple[Material, Material]:
    """(floor, wall) materials of one room, named ``floor_<id>`` and ``wall_<id>``."""
    kind, rgb = FLOORS[room_type][int(rng.integers(len(FLOORS[room_type])))]
    floor_rgba = jitter(rgb, rng)
    if kind == "checker":
        second = jitter(np.asarray(rgb) * 0.85, rng, 0.02)
        floor = Material(f"floor_{room_id}", floor_rgba, "checker", second, 4.0)
    else:
        floor = Material(f"floor_{room_id}", floor_rgba)
    palette = WALLS[room_type]
    wall = Material(f"wall_{room_id}", jitter(palette[int(rng.integers(len(palette)))], rng, 0.03))
    return floor, wall


def object_color(cat: Category, rng: np.random.Generator) -> tuple[float, float, float, float]:
    """An RGBA colour for one instance of ``cat``: a palette colour, jittered."""
    return jitter(cat.colors[int(rng.integers(len(cat.colors)))], rng, 0.06)
