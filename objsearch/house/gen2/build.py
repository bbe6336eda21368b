"""``build_spec`` of ``house-gen-2``: zoned floorplan -> doors and entrance -> walls ->
furniture and fill (selected by ``generate_house(..., generator="house-gen-2")``).
The stages after the doors are ``spec_of_plan``, which single rooms (``objsearch.house.rooms``)
share.

Randomness: ``numpy.random.default_rng([seed, attempt, split, STREAM])``, so ``house-gen-2``
houses are independent of ``house-gen-1`` houses of the same seed. The size class (3-4, 4-6
or 6-9 rooms) is drawn per seed as in ``house-gen-1``; the footprint then follows the rooms.
This version is frozen: a change that would give the same seed a different house is a new
generator package (``objsearch.house.generators``).
"""

from __future__ import annotations

import numpy as np

from objsearch.house.categories import CATEGORY_TABLE_VERSION
from objsearch.house.gen2.doors import edges, place_doors
from objsearch.house.gen2.floorplan import Plan, plan_house, room_program
from objsearch.house.gen2.furnish import furnish
from objsearch.house.layout import HouseContext
from objsearch.house.materials import EXTERIOR, room_materials
from objsearch.house.spec import Door, HouseSpec, Room
from objsearch.house.stages import SIZE_CLASSES, SPLITS, WALL_HEIGHT, WALL_THICKNESS, house_id
from objsearch.house.walls import build_walls

VERSION = "house-gen-2"
STREAM = 2


def build_spec(seed: int, size_class: str, split: str, attempt: int, furnished: bool = True) -> HouseSpec:
    """Run the ``house-gen-2`` stages once; raises ``StageFailure`` when a rule cannot be met.

    ``furnished=False`` stops after the walls (a house without objects: the floorplan stages only).
    """
    rng = np.random.default_rng([seed, attempt, SPLITS[split], STREAM])
    lo, hi = SIZE_CLASSES[size_class]["rooms"]
    types = room_program(int(rng.integers(lo, hi + 1)), rng)
    plan = plan_house(types, rng)
    doors = place_doors(plan, rng, WALL_THICKNESS)
    return spec_of_plan(plan, doors, rng, house_id(seed, split), seed, size_class, split, attempt, furnished=furnished)


def spec_of_plan(
    plan: Plan,
    doors: list[Door],
    rng: np.random.Generator,
    house_id: str,
    seed: int,
    size_class: str,
    split: str,
    attempt: int,
    furnished: bool = True,
    small_density: float = 0.0,
    extra: dict | None = None,
    version: str = VERSION,
    outline: tuple[tuple[float, float], ...] | None = None,
) -> HouseSpec:
    """The stages after the doors: materials, walls and (with ``furnished``) furniture and fill,
    drawn from ``rng``, as the ``HouseSpec`` of a ``house-gen-2`` house with these fields.

    ``small_density`` > 0 tops every room up with small objects to that many objects per m^2
    (``gen2.furnish.furnish``); ``extra`` is the spec's ``extra``; ``version`` the generator the
    spec records (``house-gen-3`` builds on these stages); ``outline`` the house's outline where
    it is not the footprint's rectangle (``house-gen-4``; ``walls.build_walls``). The defaults
    give the houses of ``build_spec``.
    """
    materials, rooms = [], []
    for i, (poly, t) in enumerate(zip(plan.polygons, plan.types)):
        floor, wall = room_materials(i, t, rng)
        materials += [floor, wall]
        rooms.append(Room(i, t, poly, floor.name, wall.name))
    materials.append(EXTERIOR)
    footprint = (plan.width, plan.depth)
    walls = build_walls(
        [edges(p) for p in plan.polygons],
        doors,
        footprint,
        WALL_THICKNESS,
        WALL_HEIGHT,
        [r.wall_material for r in rooms],
        EXTERIOR.name,
        outline,
    )
    objects = []
    if furnished:
        ctx = HouseContext(rng, split)
        objects = furnish(ctx, rooms, doors, WALL_HEIGHT, WALL_THICKNESS, small_density=small_density)
    return HouseSpec(
        house_id=house_id,
        seed=seed,
        split=split,
        size_class=size_class,
        attempt=attempt,
        generator_version=version,
        category_table_version=CATEGORY_TABLE_VERSION,
        footprint=footprint,
        wall_height=WALL_HEIGHT,
        wall_thickness=WALL_THICKNESS,
        rooms=tuple(rooms),
        doors=tuple(doors),
        walls=tuple(walls),
        objects=tuple(objects),
        materials=tuple(materials),
        extra=dict(extra or {}),
    )
