"""``build_spec`` of ``house-gen-1``: footprint and rooms, room types, doors and walls,
furniture, materials, drawn from ``numpy.random.default_rng([seed, attempt, split])``.
"""

from __future__ import annotations

import numpy as np

from objsearch.house.categories import CATEGORY_TABLE_VERSION
from objsearch.house.gen1.doors import place_doors, rect_edges
from objsearch.house.gen1.floorplan import assign_types, footprint, room_program, split_rooms
from objsearch.house.gen1.furnish import furnish
from objsearch.house.layout import HouseContext
from objsearch.house.materials import EXTERIOR, room_materials
from objsearch.house.spec import HouseSpec, Room, r4
from objsearch.house.stages import SIZE_CLASSES, SPLITS, WALL_HEIGHT, WALL_THICKNESS, house_id
from objsearch.house.walls import build_walls

VERSION = "house-gen-1"


def build_spec(seed: int, size_class: str, split: str, attempt: int) -> HouseSpec:
    """Run the stages once; raises ``StageFailure`` when a rule cannot be met."""
    rng = np.random.default_rng([seed, attempt, SPLITS[split]])
    lo, hi = SIZE_CLASSES[size_class]["rooms"]
    n = int(rng.integers(lo, hi + 1))
    types = room_program(n, rng)
    width, depth = footprint(size_class, rng)
    rects = split_rooms(width, depth, n, rng)
    types = assign_types(rects, types, rng)
    doors = place_doors(rects, types, rng, WALL_THICKNESS)
    materials, rooms = [], []
    for i, (rect, t) in enumerate(zip(rects, types)):
        floor, wall = room_materials(i, t, rng)
        materials += [floor, wall]
        x0, y0, x1, y1 = (r4(v) for v in rect)
        rooms.append(Room(i, t, ((x0, y0), (x1, y0), (x1, y1), (x0, y1)), floor.name, wall.name))
    materials.append(EXTERIOR)
    walls = build_walls(
        [rect_edges(r) for r in rects],
        doors,
        (width, depth),
        WALL_THICKNESS,
        WALL_HEIGHT,
        [r.wall_material for r in rooms],
        EXTERIOR.name,
    )
    h = WALL_THICKNESS / 2
    interiors = [(r4(x0 + h), r4(y0 + h), r4(x1 - h), r4(y1 - h)) for x0, y0, x1, y1 in rects]
    objects = furnish(HouseContext(rng, split), rooms, interiors, doors, WALL_HEIGHT)
    return HouseSpec(
        house_id=house_id(seed, split),
        seed=seed,
        split=split,
        size_class=size_class,
        attempt=attempt,
        generator_version=VERSION,
        category_table_version=CATEGORY_TABLE_VERSION,
        footprint=(width, depth),
        wall_height=WALL_HEIGHT,
        wall_thickness=WALL_THICKNESS,
        rooms=tuple(rooms),
        doors=tuple(doors),
        walls=tuple(walls),
        objects=tuple(objects),
        materials=tuple(materials),
    )
