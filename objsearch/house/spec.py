"""``HouseSpec``: a house as pure data (rooms, doors, walls, objects, materials).

Generator stages build it, ``objsearch.house.mjcf`` turns it into MJCF, and it round-trips
through JSON (``spec.json``). Coordinates are metres in the world frame: x east, y north, z
up, the footprint spans ``[0, width] x [0, depth]``, the floor is z = 0. Every float is
rounded to ``DECIMALS`` places when a spec is built, so the JSON is byte-stable.

Object pose: ``position`` is the centre of the object's footprint at its *bottom* (z = base
height), ``yaw`` is in degrees and a multiple of 90, and the object's front (+y in its own
frame) points along ``(-sin yaw, cos yaw)``. ``size`` is (width, depth, height) in its own
frame, so its world footprint swaps width and depth when yaw is 90 or 270.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from objsearch.configs import JsonConfig
from objsearch.errors import UserError

SCHEMA_VERSION = 1
DECIMALS = 4
#: The room id a door's ``rooms`` holds for the outside of the house (an entrance door).
OUTSIDE = -1
#: The families of the placement-fidelity dial (``objsearch.house.dial``): moved objects go
#: anywhere in the house, or into rooms of their room's type.
DIAL_FAMILIES = ("anywhere", "roomwise")
#: The dial's settings: the share of a house's objects moved out of their functional places, in
#: percent (0 is ``functional`` itself).
DIAL_SHARES = (25, 50, 75, 100)
#: How a house's objects are placed (``HouseSpec.placement``): in functional groups by room
#: priors, shuffled anywhere in the house, or roomwise (shuffled within room types;
#: ``objsearch.house.shuffle``), or a setting ``<family>-<share>`` of the fidelity dial
#: (``anywhere-25`` ... ``roomwise-100``: that share of the objects moved, ``objsearch.house.dial``).
#: The first is the default.
HOUSE_PLACEMENTS = ("functional", "shuffled", "roomwise") + tuple(
    f"{family}-{share}" for family in DIAL_FAMILIES for share in DIAL_SHARES
)
#: The generator version (``HouseSpec.generator_version``; the registry:
#: ``objsearch.house.generators.GENERATORS``) that ``generate_house`` and ``objsearch generate``
#: use unless told otherwise.
DEFAULT_GENERATOR = "house-gen-2"


def r4(x: float) -> float:
    """Round to the spec's precision (and turn -0.0 into 0.0)."""
    return round(float(x), DECIMALS) + 0.0


def r4s(xs) -> tuple[float, ...]:
    """``r4`` of every element, as a tuple."""
    return tuple(r4(x) for x in xs)


@dataclass(frozen=True)
class Material:
    """A surface look. ``texture`` is ``flat`` or ``checker`` (tiles: ``rgba`` and ``rgba2``)."""

    name: str
    rgba: tuple[float, float, float, float]
    texture: str = "flat"
    rgba2: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)
    repeat: float = 1.0


@dataclass(frozen=True)
class Room:
    """A room: id, type (``categories.ROOM_TYPES``), counter-clockwise polygon, materials."""

    id: int
    type: str
    polygon: tuple[tuple[float, float], ...]
    floor_material: str
    wall_material: str

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """Bounding box (x0, y0, x1, y1) of the room's polygon, metres."""
        xs = [p[0] for p in self.polygon]
        ys = [p[1] for p in self.polygon]
        return min(xs), min(ys), max(xs), max(ys)

    @property
    def area(self) -> float:
        """Area of the room's polygon, square metres."""
        pts = self.polygon
        return 0.5 * abs(sum(pts[i][0] * pts[i - 1][1] - pts[i - 1][0] * pts[i][1] for i in range(len(pts))))

    def contains(self, x: float, y: float) -> bool:
        """Whether the point (x, y) lies strictly inside the room's polygon (even-odd rule)."""
        inside = False
        pts = self.polygon
        for i in range(len(pts)):
            (xa, ya), (xb, yb) = pts[i - 1], pts[i]
            if (ya > y) != (yb > y) and x < xa + (y - ya) * (xb - xa) / (yb - ya):
                inside = not inside
        return inside

    def rects(self) -> list[tuple[float, float, float, float]]:
        """The room as axis-aligned rectangles (x0, y0, x1, y1) that tile its (rectilinear) polygon.

        A rectangle is itself (``[bounds]``); an L-shape is cut on the grid of its vertex coordinates.
        """
        if len(self.polygon) == 4:
            return [self.bounds]
        xs = sorted({p[0] for p in self.polygon})
        ys = sorted({p[1] for p in self.polygon})
        out = []
        for y0, y1 in zip(ys, ys[1:]):
            for x0, x1 in zip(xs, xs[1:]):
                if self.contains((x0 + x1) / 2, (y0 + y1) / 2):
                    out.append((x0, y0, x1, y1))
        return out


@dataclass(frozen=True)
class Door:
    """An opening between two rooms in the wall line through ``center``.

    An entrance door joins a room to the outside: its ``rooms`` are ``(room, OUTSIDE)``.
    ``axis`` is the direction the wall runs (``x``: a wall at y = center[1]); the opening is
    ``width`` wide and ``height`` high, with a lintel above it up to the wall height.
    """

    id: int
    rooms: tuple[int, int]
    axis: str
    center: tuple[float, float]
    width: float
    height: float

    @property
    def span(self) -> tuple[float, float, float, float]:
        """Footprint of the opening (x0, y0, x1, y1) as a zero-thickness segment."""
        cx, cy = self.center
        h = self.width / 2
        return (cx - h, cy, cx + h, cy) if self.axis == "x" else (cx, cy - h, cx, cy + h)


@dataclass(frozen=True)
class Wall:
    """An axis-aligned wall box: footprint (x0, y0, x1, y1), from the floor to ``height``.

    ``room`` is the room whose side this is (-1: the outer skin of the house).
    """

    id: int
    room: int
    box: tuple[float, float, float, float]
    height: float
    material: str


@dataclass(frozen=True)
class ObjectInstance:
    """One object. Its MJCF body and geom are both named ``name`` = ``<category>_<instance>``."""

    category: str
    instance: int
    variant: str
    room: int
    position: tuple[float, float, float]
    yaw: int
    size: tuple[float, float, float]
    rgba: tuple[float, float, float, float]
    placement: str
    parent: str | None = None
    group: str | None = None

    @property
    def name(self) -> str:
        """``<category>_<instance>``: the name of the object's MJCF body and geom."""
        return f"{self.category}_{self.instance}"

    @property
    def front(self) -> tuple[float, float]:
        """Unit world (x, y) direction the object's front faces: ``(-sin yaw, cos yaw)``."""
        a = math.radians(self.yaw)
        return (r4(-math.sin(a)), r4(math.cos(a)))

    @property
    def footprint(self) -> tuple[float, float, float, float]:
        """World-frame axis-aligned footprint (x0, y0, x1, y1)."""
        w, d, _ = self.size
        if self.yaw % 180:
            w, d = d, w
        x, y, _ = self.position
        return (x - w / 2, y - d / 2, x + w / 2, y + d / 2)

    @property
    def box(self) -> tuple[float, float, float, float, float, float]:
        """World axis-aligned box (x0, y0, z0, x1, y1, z1)."""
        x0, y0, x1, y1 = self.footprint
        z = self.position[2]
        return (x0, y0, z, x1, y1, z + self.size[2])


@dataclass(frozen=True)
class HouseSpec(JsonConfig):
    """A whole house. ``to_json()`` is its data; ``to_json_text()`` the canonical text
    (sorted keys, one-space indent, trailing newline) that ``spec.json`` holds and spec
    hashes are taken of, so its bytes must not change (``objsearch.configs.JsonConfig``)."""

    DESCRIPTION = "a house spec"
    JSON_SORT_KEYS = True

    house_id: str
    seed: int
    split: str
    size_class: str
    attempt: int
    generator_version: str
    category_table_version: str
    footprint: tuple[float, float]
    wall_height: float
    wall_thickness: float
    rooms: tuple[Room, ...]
    doors: tuple[Door, ...]
    walls: tuple[Wall, ...]
    objects: tuple[ObjectInstance, ...]
    materials: tuple[Material, ...]
    schema_version: int = SCHEMA_VERSION
    extra: dict = field(default_factory=dict)

    def room(self, room_id: int) -> Room:
        """The room with id ``room_id`` (StopIteration if there is none)."""
        return next(r for r in self.rooms if r.id == room_id)

    def object(self, name: str) -> ObjectInstance:
        """The object named ``name`` (StopIteration if there is none)."""
        return next(o for o in self.objects if o.name == name)

    @property
    def entrance(self) -> Door | None:
        """The entrance door (the door whose ``rooms`` holds ``OUTSIDE``), None if the house has none."""
        return next((d for d in self.doors if OUTSIDE in d.rooms), None)

    def entrance_point(self, depth: float = 1.0) -> tuple[float, float] | None:
        """The point ``depth`` metres inside the house straight in from the entrance's centre (None without one).

        Where episode starts "near the entrance" can be drawn around.
        """
        d = self.entrance
        if d is None:
            return None
        room = self.room(max(d.rooms))
        cx, cy = d.center
        if d.axis == "x":
            sign = 1.0 if room.contains(cx, cy + 0.05) else -1.0
            return (r4(cx), r4(cy + sign * depth))
        sign = 1.0 if room.contains(cx + 0.05, cy) else -1.0
        return (r4(cx + sign * depth), r4(cy))

    @property
    def placement(self) -> str:
        """How the objects were placed: ``functional`` (groups and room priors), ``shuffled`` or
        ``roomwise`` (``objsearch.house.shuffle``), or a dial setting such as ``anywhere-50``
        (``objsearch.house.dial``), recorded in ``extra`` (absent: functional, so the functional
        houses' bytes never changed)."""
        return self.extra.get("placement", HOUSE_PLACEMENTS[0])

    @property
    def single_room(self) -> str | None:
        """The room type of a single room (``objsearch.house.rooms``: a house of one room, no
        doors), recorded in ``extra``; None for a house."""
        return self.extra.get("room")

    def material(self, name: str) -> Material:
        """The material named ``name`` (StopIteration if there is none)."""
        return next(m for m in self.materials if m.name == name)

    @classmethod
    def upgrade(cls, data: dict) -> dict:
        """The legacy hook: only the current schema is read (older specs are regenerated)."""
        if data.get("schema_version") != SCHEMA_VERSION:
            raise UserError(
                f"schema_version {data.get('schema_version')!r} is not {SCHEMA_VERSION}; "
                "regenerate the house with objsearch generate"
            )
        return super().upgrade(data)
