"""Placement inside one room: the primitives the furnishing stage is written in.

All objects stand axis-aligned (yaw a multiple of 90 degrees), so every object, keep-out
zone and wall is an axis-aligned box and a placement check is a handful of comparisons.
A candidate fits when it lies inside the room's interior (the room minus its walls), below
the ceiling height, and overlaps no placed box by more than ``EPS``; objects keep ``GAP``
from each other. Keep-out boxes (in front of doors, in front of furniture that must be
reached, around free-standing groups) are boxes that block but are not objects.
"""

from __future__ import annotations

import numpy as np

from objsearch.house import assets
from objsearch.house.categories import Category, category
from objsearch.house.materials import object_color
from objsearch.house.spec import ObjectInstance, r4

EPS = 1e-4
GAP = 0.01  # between objects, and between a floor object's back and the wall
WALL_GAP = 0.002  # between a wall-mounted object and the wall
SURFACE_GAP = 0.001  # between an object and the surface it stands on
ACCESS_DEPTH = 0.5  # free strip kept in front of wall furniture
ACCESS_HEIGHT = 1.2
EDGE_BAND_PARENTS = ("dining_table",)
EDGE_BAND = 0.3  # small objects on a dining table stay this close to a long edge

# side -> (yaw, inward normal)
SIDES = {"S": (0, (0.0, 1.0)), "N": (180, (0.0, -1.0)), "W": (270, (1.0, 0.0)), "E": (90, (-1.0, 0.0))}

Box = tuple[float, float, float, float, float, float]


def box_of(x: float, y: float, z: float, size, yaw: int) -> Box:
    """World box (x0, y0, z0, x1, y1, z1) of an object of ``size`` (w, d, h), footprint centre (x, y), base z."""
    w, d, h = size
    if yaw % 180:
        w, d = d, w
    return (x - w / 2, y - d / 2, z, x + w / 2, y + d / 2, z + h)


def overlaps(a: Box, b: Box, eps: float = EPS) -> bool:
    """Whether boxes ``a`` and ``b`` overlap by more than ``eps`` along all three axes."""
    return (
        a[0] < b[3] - eps
        and b[0] < a[3] - eps
        and a[1] < b[4] - eps
        and b[1] < a[4] - eps
        and a[2] < b[5] - eps
        and b[2] < a[5] - eps
    )


def rotate_rect(rect, yaw: int):
    """Rotate a local rect (x0, y0, x1, y1) about the origin by a multiple of 90 degrees."""
    x0, y0, x1, y1 = rect
    corners = [(x0, y0), (x1, y1)]
    rot = {0: lambda x, y: (x, y), 90: lambda x, y: (-y, x), 180: lambda x, y: (-x, -y), 270: lambda x, y: (y, -x)}[
        yaw % 360
    ]
    pts = [rot(x, y) for x, y in corners]
    return (min(p[0] for p in pts), min(p[1] for p in pts), max(p[0] for p in pts), max(p[1] for p in pts))


def surface_rect(parent: ObjectInstance) -> tuple[float, float, float, float, float]:
    """World support surface of a receptacle: (z, x0, y0, x1, y1)."""
    z, ux0, uy0, ux1, uy1 = assets.surface(parent.category, parent.variant)
    w, d, h = parent.size
    x0, y0, x1, y1 = rotate_rect((ux0 * w, uy0 * d, ux1 * w, uy1 * d), parent.yaw)
    px, py, pz = parent.position
    return (pz + z * h, px + x0, py + y0, px + x1, py + y1)


class HouseContext:
    """What all rooms of one house share: the rng, the split, instance counters, objects."""

    def __init__(self, rng: np.random.Generator, split: str):
        self.rng = rng
        self.split = split
        self.counts: dict[str, int] = {}
        self.objects: list[ObjectInstance] = []

    def new_instance(
        self, cat: Category, room: int, pos, yaw: int, size, placement: str, parent=None, group=None
    ) -> ObjectInstance:
        """Create, record and return the next ``cat`` instance (numbered per category) in ``room``.

        Draws its variant (among the split's) and colour from the house rng; ``parent`` and ``group`` are names.
        """
        i = self.counts.get(cat.name, 0)
        self.counts[cat.name] = i + 1
        names = assets.variants(cat.name, self.split)
        variant = names[int(self.rng.integers(len(names)))]
        obj = ObjectInstance(
            cat.name,
            i,
            variant,
            room,
            tuple(r4(v) for v in pos),
            int(yaw) % 360,
            tuple(size),
            object_color(cat, self.rng),
            placement,
            parent,
            group,
        )
        self.objects.append(obj)
        return obj


class RoomLayout:
    """One room being furnished: its interior (x0, y0, x1, y1), the boxes that block it, the objects placed in it."""

    def __init__(self, ctx: HouseContext, room_id: int, room_type: str, interior, wall_height: float):
        self.ctx, self.rng = ctx, ctx.rng
        self.room_id, self.type = room_id, room_type
        self.interior = tuple(interior)
        self.wall_height = wall_height
        self.blocks: list[tuple[Box, str | None]] = []
        self.objects: list[ObjectInstance] = []

    # --- geometry ---------------------------------------------------------------------
    def span(self, lo: float, hi: float) -> float:
        """Uniform in [lo, hi]; lo when rounding made the range (slightly) empty."""
        return float(self.rng.uniform(lo, hi)) if hi > lo else float(lo)

    def side_length(self, side: str) -> float:
        """Interior length (metres) of wall ``side`` (one of S, N, W, E)."""
        x0, y0, x1, y1 = self.interior
        return x1 - x0 if side in "SN" else y1 - y0

    def wall_position(self, side: str, u: float, depth: float, gap: float = GAP) -> tuple[float, float]:
        """Centre of a footprint ``depth`` deep with its back on wall ``side``, ``u`` along it."""
        x0, y0, x1, y1 = self.interior
        off = gap + depth / 2
        return {"S": (x0 + u, y0 + off), "N": (x0 + u, y1 - off), "W": (x0 + off, y0 + u), "E": (x1 - off, y0 + u)}[
            side
        ]

    def along(self, side: str, x: float, y: float) -> float:
        """Inverse of ``wall_position`` for the coordinate along the wall."""
        return x - self.interior[0] if side in "SN" else y - self.interior[1]

    def fits(self, box: Box, ignore: tuple[str, ...] = (), inside: bool = True, gap: float = GAP) -> bool:
        """Whether ``box`` is free: below the ceiling (less 5 cm), clear of every block by ``gap``.

        ``ignore``: owners whose blocks do not count (the parent of an object on top); with ``inside``, the box must
        also lie within the interior.
        """
        x0, y0, x1, y1 = self.interior
        if inside and (box[0] < x0 - EPS or box[1] < y0 - EPS or box[3] > x1 + EPS or box[4] > y1 + EPS):
            return False
        if box[5] > self.wall_height - 0.05:
            return False
        grown = (box[0] - gap, box[1] - gap, box[2], box[3] + gap, box[4] + gap, box[5])
        return not any(overlaps(grown, b) for b, owner in self.blocks if owner not in ignore)

    def block(self, box: Box, owner: str | None = None) -> None:
        """Mark ``box`` as taken; ``owner`` is the object's name, None for a keep-out zone."""
        self.blocks.append((tuple(box), owner))

    def keep_front(self, obj: ObjectInstance, depth: float = ACCESS_DEPTH, back: bool = False) -> None:
        """Keep a strip in front of ``obj`` (behind it if ``back``) free, so it can be reached."""
        x0, y0, x1, y1 = obj.footprint
        fx, fy = obj.front
        if back:
            fx, fy = -fx, -fy
        if fx > 0.5:
            rect = (x1, y0, x1 + depth, y1)
        elif fx < -0.5:
            rect = (x0 - depth, y0, x0, y1)
        elif fy > 0.5:
            rect = (x0, y1, x1, y1 + depth)
        else:
            rect = (x0, y0 - depth, x1, y0)
        box = (rect[0], rect[1], 0.0, rect[2], rect[3], ACCESS_HEIGHT)
        self.block(box, None)

    # --- sampling ---------------------------------------------------------------------
    def sample_size(self, cat: Category, max_width: float | None = None) -> tuple[float, float, float]:
        """Draw a size (w, d, h) in metres within the category's bounds, width at most ``max_width``."""
        lo, hi = np.asarray(cat.size_min), np.asarray(cat.size_max)
        if max_width is not None:
            hi = hi.copy()
            hi[0] = max(lo[0], min(hi[0], max_width))
        s = [round(float(v), 2) for v in self.rng.uniform(lo, hi)]
        if cat.round:
            s[1] = s[0]
        return (r4(s[0]), r4(s[1]), r4(s[2]))

    def place(
        self,
        cat: Category,
        size,
        x: float,
        y: float,
        z: float,
        yaw: int,
        placement: str,
        parent: ObjectInstance | None = None,
        group: str | None = None,
        inside: bool = True,
        check: bool = True,
        access: float = 0.0,
    ) -> ObjectInstance | None:
        """Place ``cat`` with footprint centre (x, y), base z, and block its box; None if it does not fit.

        ``check=False`` places it without the fit check; ``access`` > 0 keeps that deep a strip in front of it free.
        """
        x, y, z = r4(x), r4(y), r4(z)
        box = box_of(x, y, z, size, yaw)
        ignore = (parent.name,) if parent is not None else ()
        gap = 0.0 if placement == "on_wall" else GAP
        if check and not self.fits(box, ignore=ignore, inside=inside, gap=gap):
            return None
        obj = self.ctx.new_instance(
            cat, self.room_id, (x, y, z), yaw, size, placement, parent.name if parent else None, group
        )
        self.objects.append(obj)
        self.block(obj.box, obj.name)
        if access > 0:
            self.keep_front(obj, access)
        return obj

    def try_wall(
        self, cat: Category, size=None, tries: int = 20, access: float = ACCESS_DEPTH, corner: bool = False, group=None
    ):
        """Place ``cat`` with its back against a random wall (``corner``: at one end of it); None after ``tries``.

        ``access``: depth of the strip kept free in front of it.
        """
        size = size or self.sample_size(cat)
        for _ in range(tries):
            side = "SNWE"[int(self.rng.integers(4))]
            length = self.side_length(side)
            if length < size[0] + 2 * GAP:
                continue
            if corner:
                u = GAP + size[0] / 2 if self.rng.random() < 0.5 else length - GAP - size[0] / 2
            else:
                u = self.span(GAP + size[0] / 2, length - GAP - size[0] / 2)
            x, y = self.wall_position(side, u, size[1])
            obj = self.place(
                cat, size, x, y, 0.0, SIDES[side][0], "corner" if corner else "wall", access=access, group=group
            )
            if obj:
                return obj
        return None

    def try_middle(self, cat: Category, size=None, clearance: float = 0.6, tries: int = 20, group=None):
        """Place ``cat`` free-standing with ``clearance`` metres free around it; None if it does not fit."""
        size = size or self.sample_size(cat)
        x0, y0, x1, y1 = self.interior
        for _ in range(tries):
            yaw = 90 * int(self.rng.integers(4))
            w, d = (size[1], size[0]) if yaw % 180 else (size[0], size[1])
            if x1 - x0 < w + 2 * clearance or y1 - y0 < d + 2 * clearance:
                return None
            x = self.span(x0 + clearance + w / 2, x1 - clearance - w / 2)
            y = self.span(y0 + clearance + d / 2, y1 - clearance - d / 2)
            outer = (
                x - w / 2 - clearance,
                y - d / 2 - clearance,
                0.0,
                x + w / 2 + clearance,
                y + d / 2 + clearance,
                size[2],
            )
            if self.fits(outer):
                return self.place(cat, size, x, y, 0.0, yaw, "middle", group=group)
        return None

    def try_on_wall(self, cat: Category, size=None, tries: int = 20, side=None, u_range=None, z=None, group=None):
        """Hang ``cat`` on a wall, base at ``z`` (default: drawn from its ``wall_z``); None if it does not fit.

        ``side`` fixes the wall and ``u_range`` (lo, hi) the range of its centre along it.
        """
        size = size or self.sample_size(cat)
        for _ in range(tries):
            s = side or "SNWE"[int(self.rng.integers(4))]
            length = self.side_length(s)
            lo, hi = u_range or (size[0] / 2 + 0.05, length - size[0] / 2 - 0.05)
            if hi < lo:
                return None
            u = self.rng.uniform(lo, hi)
            x, y = self.wall_position(s, u, size[1], gap=WALL_GAP)
            zz = z if z is not None else self.span(*cat.wall_z)
            obj = self.place(cat, size, x, y, zz, SIDES[s][0], "on_wall", group=group)
            if obj:
                return obj
        return None

    def try_on_top(
        self, cat: Category, parents=None, tries: int = 12, size=None, group=None, face_parent: bool = True, where=None
    ):
        """Stand ``cat`` on a receptacle in the room (or one of ``parents``); None if none has room.

        ``face_parent``: take the parent's yaw (else a random one); ``where(parent, w, d, rect)`` picks (x, y)
        on the surface rect instead of a random spot.
        """
        cands = parents if parents is not None else [o for o in self.objects if o.category in cat.parents]
        if not cands:
            return None
        for _ in range(tries):
            parent = cands[int(self.rng.integers(len(cands)))]
            sz, sx0, sy0, sx1, sy1 = surface_rect(parent)
            s = size or self.sample_size(cat)
            yaw = parent.yaw if face_parent else 90 * int(self.rng.integers(4))
            w, d = (s[1], s[0]) if yaw % 180 else (s[0], s[1])
            if sx1 - sx0 < w + 0.02 or sy1 - sy0 < d + 0.02:
                continue
            if where is not None:
                x, y = where(parent, w, d, (sx0, sy0, sx1, sy1))
            elif parent.category in EDGE_BAND_PARENTS:
                # on tables with chairs round them, stay near a long edge (within reach)
                x = self.span(sx0 + 0.01 + w / 2, sx1 - 0.01 - w / 2)
                y = self.span(sy0 + 0.01 + d / 2, sy1 - 0.01 - d / 2)
                band = EDGE_BAND - 0.01
                if parent.yaw % 180 == 0 and sy1 - sy0 > 2 * band:
                    y = (sy0 + 0.01 + d / 2) if self.rng.random() < 0.5 else (sy1 - 0.01 - d / 2)
                    y += self.span(0, max(band - d, 0)) * (1 if y < (sy0 + sy1) / 2 else -1)
                elif parent.yaw % 180 and sx1 - sx0 > 2 * band:
                    x = (sx0 + 0.01 + w / 2) if self.rng.random() < 0.5 else (sx1 - 0.01 - w / 2)
                    x += self.span(0, max(band - w, 0)) * (1 if x < (sx0 + sx1) / 2 else -1)
            else:
                x = self.span(sx0 + 0.01 + w / 2, sx1 - 0.01 - w / 2)
                y = self.span(sy0 + 0.01 + d / 2, sy1 - 0.01 - d / 2)
            obj = self.place(cat, s, x, y, sz + SURFACE_GAP, yaw, "on_top", parent=parent, group=group)
            if obj:
                return obj
        return None

    def try_category(self, name: str):
        """Place one free (fill) object of category ``name`` by its placement rule."""
        cat = category(name)
        if cat.placement == "wall":
            return self.try_wall(cat)
        if cat.placement == "corner":
            return self.try_wall(cat, corner=True, access=0.3)
        if cat.placement == "middle":
            return self.try_middle(cat)
        if cat.placement == "on_wall":
            return self.try_on_wall(cat)
        if cat.placement == "on_top":
            return self.try_on_top(cat, face_parent=False)
        raise ValueError(f"category {name} is placed by its group only")
