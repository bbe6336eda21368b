"""The fixed, versioned category table shared by everything that reads segmentation.

Ids never change meaning within a ``CATEGORY_TABLE_VERSION``: renderers write them into
segmentation masks, perception models learn them, results quote them. Adding a category
appends a new id and bumps the version; renaming or reordering is not allowed.

Id 0 is background (no geom hit). Ids 1-7 are structure classes (wall, floor, door,
ceiling; 5-7 unused). The house models have no ceiling geom, so that a top-down camera sees
in; the agent's renderer closes every room with one (``RenderSettings.ceiling``), so ceiling
pixels are drawn and labelled 4 in every agent frame. Object categories start at ``FIRST_OBJECT_ID``.

Every object category carries its placement rule and priors:

* ``placement``: ``wall`` (back against a wall, facing into the room), ``corner`` (against
  two walls), ``middle`` (free-standing with clearance all round), ``on_wall`` (mounted on a
  wall at ``wall_z`` height), ``on_top`` (standing on a receptacle of ``parents``) or
  ``group`` (placed only as part of a functional group, see ``objsearch.house.groups``).
* ``rooms``: room type -> probability that a room of that type gets this category as a
  free "fill" object (group members get theirs from the group); ``count`` bounds how many.
* ``size_min`` / ``size_max``: full extents (width x, depth y, height z) in metres in the
  object's own frame, where +y is the object's front.
* ``receptacle``: other objects may stand on its top surface.
* ``round``: width == depth (cylinders, lamps, pots).
* ``colors``: base RGB palette; each instance picks one and jitters it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

CATEGORY_TABLE_VERSION = "categories-v1"

BACKGROUND_ID = 0
STRUCTURE = {"background": 0, "wall": 1, "floor": 2, "door": 3, "ceiling": 4}
FIRST_OBJECT_ID = 8

ROOM_TYPES = ("living_room", "kitchen", "dining_room", "bedroom", "bathroom", "office", "hallway")

PLACEMENTS = ("wall", "corner", "middle", "on_wall", "on_top", "group")


@dataclass(frozen=True)
class Category:
    """One object category: its id, name, placement rule, size bounds (metres), palette and room priors."""

    id: int
    name: str
    placement: str
    size_min: tuple[float, float, float]
    size_max: tuple[float, float, float]
    colors: tuple[tuple[float, float, float], ...]
    rooms: dict = field(default_factory=dict)
    count: tuple[int, int] = (1, 1)
    parents: tuple[str, ...] = ()
    receptacle: bool = False
    round: bool = False
    wall_z: tuple[float, float] = (0.0, 0.0)


WOOD = ((0.55, 0.38, 0.22), (0.72, 0.56, 0.38), (0.35, 0.24, 0.15), (0.85, 0.75, 0.6))
FABRIC = ((0.45, 0.5, 0.6), (0.6, 0.3, 0.25), (0.35, 0.45, 0.35), (0.75, 0.7, 0.62), (0.3, 0.3, 0.32))
WHITE = ((0.92, 0.92, 0.9), (0.85, 0.86, 0.88), (0.95, 0.93, 0.88))
METAL = ((0.7, 0.72, 0.75), (0.25, 0.25, 0.27), (0.55, 0.55, 0.58))
DARK = ((0.08, 0.08, 0.09), (0.15, 0.15, 0.17), (0.22, 0.22, 0.25))
CERAMIC = ((0.9, 0.9, 0.88), (0.6, 0.75, 0.85), (0.85, 0.55, 0.4), (0.4, 0.55, 0.45))
BRIGHT = ((0.85, 0.25, 0.2), (0.2, 0.45, 0.8), (0.95, 0.75, 0.2), (0.3, 0.65, 0.35))
GREEN = ((0.2, 0.5, 0.22), (0.3, 0.6, 0.3), (0.18, 0.42, 0.3))

_LIVING, _KITCHEN, _DINING, _BED, _BATH, _OFFICE, _HALL = ROOM_TYPES

# (name, placement, size_min, size_max, colors, extra keyword arguments). Order = id order.
# fmt: off
_TABLE = [
    ("sofa", "group", (1.6, 0.8, 0.75), (2.3, 1.0, 0.95), FABRIC, {}),
    ("armchair", "wall", (0.7, 0.7, 0.75), (0.95, 0.9, 1.0), FABRIC, dict(rooms={_LIVING: 0.6, _BED: 0.15, _OFFICE: 0.1})),
    ("coffee_table", "group", (0.9, 0.5, 0.35), (1.3, 0.7, 0.48), WOOD, dict(receptacle=True)),
    ("tv", "group", (0.9, 0.18, 0.55), (1.5, 0.25, 0.85), DARK, {}),
    ("tv_stand", "group", (1.2, 0.35, 0.4), (1.8, 0.5, 0.6), WOOD + DARK, dict(receptacle=True)),
    ("bookshelf", "wall", (0.6, 0.28, 1.2), (1.2, 0.4, 2.0), WOOD + WHITE, dict(rooms={_LIVING: 0.5, _OFFICE: 0.9, _BED: 0.2, _HALL: 0.1}, receptacle=True)),
    ("floor_lamp", "corner", (0.3, 0.3, 1.4), (0.45, 0.45, 1.8), METAL + WHITE, dict(rooms={_LIVING: 0.6, _BED: 0.3, _OFFICE: 0.3}, round=True)),
    ("side_table", "wall", (0.4, 0.4, 0.45), (0.55, 0.55, 0.6), WOOD, dict(rooms={_LIVING: 0.5, _HALL: 0.3, _BED: 0.1}, receptacle=True)),
    ("plant", "corner", (0.35, 0.35, 0.6), (0.6, 0.6, 1.4), GREEN, dict(rooms={_LIVING: 0.7, _OFFICE: 0.4, _HALL: 0.4, _BED: 0.3, _DINING: 0.4, _KITCHEN: 0.1, _BATH: 0.1}, round=True, count=(1, 2))),
    ("painting", "on_wall", (0.5, 0.03, 0.4), (1.2, 0.05, 0.9), BRIGHT + WOOD, dict(rooms={_LIVING: 0.9, _BED: 0.6, _DINING: 0.7, _HALL: 0.6, _OFFICE: 0.3}, count=(1, 2), wall_z=(1.25, 1.5))),
    ("ottoman", "middle", (0.45, 0.45, 0.38), (0.7, 0.7, 0.45), FABRIC, dict(rooms={_LIVING: 0.2, _BED: 0.2})),
    ("clock", "on_wall", (0.25, 0.04, 0.25), (0.4, 0.06, 0.4), WHITE + DARK, dict(rooms={_LIVING: 0.3, _KITCHEN: 0.4, _OFFICE: 0.3, _HALL: 0.2, _DINING: 0.2}, wall_z=(1.7, 1.9))),
    ("vase", "on_top", (0.12, 0.12, 0.2), (0.2, 0.2, 0.4), CERAMIC, dict(rooms={_LIVING: 0.5, _DINING: 0.5, _BED: 0.2, _HALL: 0.3}, parents=("side_table", "sideboard", "dresser", "coffee_table", "dining_table", "shoe_rack"), round=True)),
    ("book", "on_top", (0.15, 0.2, 0.03), (0.24, 0.3, 0.06), BRIGHT, dict(rooms={_LIVING: 0.6, _OFFICE: 0.8, _BED: 0.5}, parents=("bookshelf", "coffee_table", "nightstand", "desk", "side_table"), count=(1, 3))),
    ("remote_control", "group", (0.04, 0.15, 0.02), (0.06, 0.2, 0.03), DARK, {}),
    ("counter", "group", (0.6, 0.6, 0.88), (1.2, 0.65, 0.92), WHITE + WOOD, dict(receptacle=True)),
    ("kitchen_sink", "group", (0.5, 0.4, 0.2), (0.8, 0.5, 0.35), METAL, {}),
    ("stove", "group", (0.6, 0.6, 0.88), (0.76, 0.65, 0.92), WHITE + METAL, dict(receptacle=True)),
    ("fridge", "group", (0.7, 0.65, 1.7), (0.9, 0.75, 2.0), WHITE + METAL, {}),
    ("microwave", "group", (0.45, 0.32, 0.26), (0.6, 0.4, 0.32), WHITE + DARK, {}),
    ("toaster", "group", (0.25, 0.16, 0.18), (0.32, 0.2, 0.22), METAL + BRIGHT, {}),
    ("kettle", "on_top", (0.16, 0.16, 0.2), (0.22, 0.22, 0.28), METAL + WHITE, dict(rooms={_KITCHEN: 0.7}, parents=("counter",), round=True)),
    ("dishwasher", "group", (0.6, 0.6, 0.88), (0.6, 0.62, 0.92), WHITE + METAL, {}),
    ("trash_can", "corner", (0.25, 0.25, 0.35), (0.4, 0.4, 0.7), METAL + DARK, dict(rooms={_KITCHEN: 0.8, _OFFICE: 0.5, _BATH: 0.5, _BED: 0.2, _LIVING: 0.2}, round=True)),
    ("pot", "on_top", (0.2, 0.2, 0.12), (0.3, 0.3, 0.2), METAL + DARK, dict(rooms={_KITCHEN: 0.7}, parents=("stove",), round=True)),
    ("fruit_bowl", "on_top", (0.22, 0.22, 0.08), (0.32, 0.32, 0.14), CERAMIC + WOOD, dict(rooms={_KITCHEN: 0.5, _DINING: 0.4, _LIVING: 0.1}, parents=("dining_table", "counter", "coffee_table"), round=True)),
    ("bottle", "on_top", (0.07, 0.07, 0.22), (0.1, 0.1, 0.32), GREEN + ((0.5, 0.3, 0.1),), dict(rooms={_KITCHEN: 0.5, _DINING: 0.4}, parents=("dining_table", "counter", "sideboard"), round=True, count=(1, 2))),
    ("cup", "on_top", (0.07, 0.07, 0.08), (0.1, 0.1, 0.12), CERAMIC, dict(rooms={_KITCHEN: 0.5, _DINING: 0.4, _OFFICE: 0.4, _LIVING: 0.3}, parents=("dining_table", "counter", "desk", "coffee_table", "nightstand"), round=True, count=(1, 2))),
    ("plate", "on_top", (0.2, 0.2, 0.02), (0.28, 0.28, 0.03), CERAMIC, dict(rooms={_DINING: 0.7, _KITCHEN: 0.4}, parents=("dining_table",), round=True, count=(1, 4))),
    ("dining_table", "group", (0.9, 0.8, 0.72), (2.0, 1.0, 0.78), WOOD + WHITE, dict(receptacle=True)),
    ("chair", "group", (0.42, 0.45, 0.8), (0.5, 0.55, 1.0), WOOD + FABRIC, {}),
    ("sideboard", "wall", (1.2, 0.4, 0.75), (1.8, 0.5, 0.9), WOOD, dict(rooms={_DINING: 0.7, _LIVING: 0.2}, receptacle=True)),
    ("candle", "on_top", (0.05, 0.05, 0.1), (0.08, 0.08, 0.25), WHITE + BRIGHT, dict(rooms={_DINING: 0.4, _LIVING: 0.2, _BED: 0.2}, parents=("dining_table", "sideboard", "nightstand", "coffee_table"), round=True)),
    ("bed", "group", (0.9, 1.9, 0.8), (1.8, 2.1, 1.1), WOOD + FABRIC, dict(receptacle=True)),
    ("nightstand", "group", (0.4, 0.35, 0.45), (0.55, 0.45, 0.6), WOOD + WHITE, dict(receptacle=True)),
    ("table_lamp", "group", (0.2, 0.2, 0.35), (0.35, 0.35, 0.55), WHITE + METAL, dict(round=True)),
    ("wardrobe", "wall", (0.9, 0.55, 1.8), (1.8, 0.65, 2.2), WOOD + WHITE, dict(rooms={_BED: 0.8, _HALL: 0.1})),
    ("dresser", "wall", (0.8, 0.45, 0.75), (1.4, 0.55, 1.0), WOOD + WHITE, dict(rooms={_BED: 0.6}, receptacle=True)),
    ("mirror", "on_wall", (0.5, 0.03, 0.6), (0.8, 0.05, 1.0), METAL, dict(rooms={_HALL: 0.4, _BED: 0.3}, wall_z=(1.0, 1.2))),
    ("pillow", "group", (0.5, 0.3, 0.1), (0.7, 0.4, 0.16), WHITE + FABRIC, {}),
    ("alarm_clock", "on_top", (0.1, 0.06, 0.08), (0.15, 0.09, 0.12), DARK + BRIGHT, dict(rooms={_BED: 0.5}, parents=("nightstand",))),
    ("laptop", "on_top", (0.3, 0.22, 0.2), (0.38, 0.28, 0.25), METAL + DARK, dict(rooms={_OFFICE: 0.4, _BED: 0.2, _LIVING: 0.2}, parents=("desk", "coffee_table", "dining_table"))),
    ("toilet", "group", (0.36, 0.62, 0.72), (0.42, 0.72, 0.82), WHITE, {}),
    ("sink", "group", (0.5, 0.42, 0.8), (0.9, 0.55, 0.9), WHITE + WOOD, dict(receptacle=True)),
    ("bathtub", "group", (1.5, 0.7, 0.5), (1.8, 0.8, 0.6), WHITE, {}),
    ("towel", "group", (0.4, 0.05, 0.5), (0.6, 0.08, 0.8), BRIGHT + WHITE, {}),
    ("toilet_paper", "group", (0.12, 0.1, 0.12), (0.16, 0.13, 0.16), WHITE, {}),
    ("soap", "on_top", (0.06, 0.06, 0.1), (0.09, 0.09, 0.18), BRIGHT + WHITE, dict(rooms={_BATH: 0.8, _KITCHEN: 0.2}, parents=("sink", "counter"))),
    ("laundry_basket", "corner", (0.4, 0.35, 0.45), (0.55, 0.45, 0.6), WHITE + WOOD, dict(rooms={_BATH: 0.4, _BED: 0.2})),
    ("desk", "group", (1.0, 0.55, 0.72), (1.6, 0.75, 0.78), WOOD + WHITE, dict(receptacle=True)),
    ("office_chair", "group", (0.55, 0.55, 0.9), (0.65, 0.65, 1.2), DARK + FABRIC, dict(round=True)),
    ("computer", "group", (0.45, 0.18, 0.35), (0.65, 0.24, 0.5), DARK, {}),
    ("keyboard", "group", (0.38, 0.12, 0.02), (0.46, 0.16, 0.04), DARK + WHITE, {}),
    ("filing_cabinet", "wall", (0.4, 0.5, 0.6), (0.5, 0.6, 1.3), METAL, dict(rooms={_OFFICE: 0.7}, receptacle=True)),
    ("printer", "on_top", (0.4, 0.35, 0.15), (0.5, 0.45, 0.25), WHITE + DARK, dict(rooms={_OFFICE: 0.5}, parents=("filing_cabinet", "desk", "sideboard"))),
    ("desk_lamp", "group", (0.15, 0.15, 0.35), (0.25, 0.25, 0.5), METAL + DARK, {}),
    ("whiteboard", "on_wall", (0.9, 0.03, 0.6), (1.5, 0.05, 0.9), WHITE, dict(rooms={_OFFICE: 0.5}, wall_z=(0.95, 1.1))),
    ("shoe_rack", "wall", (0.6, 0.28, 0.4), (1.0, 0.35, 0.9), WOOD + METAL, dict(rooms={_HALL: 0.8, _BED: 0.05}, receptacle=True)),
    ("coat_rack", "corner", (0.4, 0.4, 1.6), (0.55, 0.55, 1.9), WOOD + METAL, dict(rooms={_HALL: 0.7, _BED: 0.1}, round=True)),
    ("bench", "wall", (1.0, 0.35, 0.42), (1.4, 0.45, 0.48), WOOD, dict(rooms={_HALL: 0.5, _DINING: 0.1})),
    ("stool", "corner", (0.3, 0.3, 0.45), (0.4, 0.4, 0.75), WOOD + METAL, dict(rooms={_KITCHEN: 0.4, _BATH: 0.1}, round=True)),
]
# fmt: on

CATEGORIES: tuple[Category, ...] = tuple(
    Category(
        id=FIRST_OBJECT_ID + i, name=name, placement=placement, size_min=smin, size_max=smax, colors=colors, **extra
    )
    for i, (name, placement, smin, smax, colors, extra) in enumerate(_TABLE)
)
BY_NAME: dict[str, Category] = {c.name: c for c in CATEGORIES}

#: id <-> name for every class a segmentation mask can hold (structure and objects).
CATEGORY_IDS: dict[str, int] = {**STRUCTURE, **{c.name: c.id for c in CATEGORIES}}
CATEGORY_NAMES: dict[int, str] = {i: n for n, i in CATEGORY_IDS.items()}


def category(name: str) -> Category:
    """The object category called ``name``; KeyError names the known ones."""
    try:
        return BY_NAME[name]
    except KeyError:
        raise KeyError(f"unknown object category {name!r}; known: {', '.join(sorted(BY_NAME))}") from None


def category_table() -> dict:
    """The table as JSON-ready data (written by ``objsearch generate`` beside the houses)."""
    return {"version": CATEGORY_TABLE_VERSION, "ids": dict(sorted(CATEGORY_IDS.items(), key=lambda kv: kv[1]))}
