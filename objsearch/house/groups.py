"""Furniture in functional groups, then free objects and small objects: the furnishing of one room
that every generator's furnishing stage uses (``house-gen-1``: ``gen1.furnish``; ``house-gen-2``,
in rooms of any shape and topped up by area: ``gen2.furnish``).

Groups (placed first, as units, so their relations always hold):

* living room: sofa against a wall, a TV stand on the opposite wall facing it with a TV on
  it, a coffee table in between (when there is room), sometimes a side table and a remote;
* bedroom: bed with its head to a wall, one or two nightstands beside it with lamps,
  pillows at the head; sometimes a desk group;
* dining room (or a large kitchen without a dining room): dining table with chairs round
  it facing it;
* bathroom: toilet (+ toilet paper beside it), sink with a mirror above it, bathtub in a
  corner with a towel above it (when the room is large enough; else the towel hangs free);
* office: desk with an office chair in front, a computer and keyboard on it, maybe a lamp;
* kitchen: a run of counters along one wall with fridge at one end, stove and (maybe) a
  dishwasher in the run, a sink, microwave and toaster on the counters.

Then every category whose ``rooms`` affinity names the room type is added with that
probability (``count`` instances), floor objects first, wall-mounted next, small objects on
receptacles last. Mandatory groups that cannot be placed raise ``StageFailure`` (the house
is resampled); optional objects that do not fit are dropped.
"""

from __future__ import annotations

import math

from objsearch.house.categories import CATEGORIES, category
from objsearch.house.layout import GAP, SIDES, SURFACE_GAP, RoomLayout, box_of, surface_rect
from objsearch.house.spec import ObjectInstance, r4
from objsearch.house.stages import StageFailure

OPPOSITE = {"S": "N", "N": "S", "W": "E", "E": "W"}
YAW_SIDE = {yaw: side for side, (yaw, _) in SIDES.items()}
FILL_ORDER = ("wall", "corner", "middle", "on_wall", "on_top")


def local_to_world(obj: ObjectInstance, lx: float, ly: float) -> tuple[float, float]:
    """World (x, y) of the point (lx, ly) in ``obj``'s own frame (yaw a multiple of 90)."""
    a = math.radians(obj.yaw)
    c, s = round(math.cos(a)), round(math.sin(a))
    return obj.position[0] + c * lx - s * ly, obj.position[1] + s * lx + c * ly


def _u_of(L: RoomLayout, obj: ObjectInstance) -> tuple[str, float]:
    side = YAW_SIDE[obj.yaw]
    return side, L.along(side, obj.position[0], obj.position[1])


def _all_fit(L: RoomLayout, boxes) -> bool:
    return all(L.fits(b) for b in boxes) and not any(
        a[0] < b[3] and b[0] < a[3] and a[1] < b[4] and b[1] < a[4] for i, a in enumerate(boxes) for b in boxes[i + 1 :]
    )


def _on_top_at(L: RoomLayout, name: str, parent: ObjectInstance, lx: float, ly: float, size, group=None):
    """Put ``name`` on ``parent`` at local offset (lx, ly) in the parent's frame, same yaw."""
    x, y = local_to_world(parent, lx, ly)
    z = surface_rect(parent)[0] + SURFACE_GAP
    sz, sx0, sy0, sx1, sy1 = surface_rect(parent)
    b = box_of(r4(x), r4(y), z, size, parent.yaw)
    if b[0] < sx0 - 1e-4 or b[1] < sy0 - 1e-4 or b[3] > sx1 + 1e-4 or b[4] > sy1 + 1e-4:
        return None
    return L.place(category(name), size, x, y, z, parent.yaw, "on_top", parent=parent, group=group)


def sofa_group(L: RoomLayout, gid: str) -> bool:
    """Living-room group: sofa, TV stand with a TV facing it, maybe a coffee table, side table and remote.

    Returns False if it does not fit.
    """
    rng = L.rng
    x0, y0, x1, y1 = L.interior
    for _ in range(30):
        side = "SNWE"[int(rng.integers(4))]
        opp = OPPOSITE[side]
        sofa, stand = L.sample_size(category("sofa")), L.sample_size(category("tv_stand"))
        across = (y1 - y0) if side in "SN" else (x1 - x0)
        free = across - sofa[1] - stand[1] - 2 * GAP
        length = L.side_length(side)
        if free < 1.6 or length < sofa[0] + 0.2:
            continue
        u = L.span(sofa[0] / 2 + GAP, length - sofa[0] / 2 - GAP)
        us = min(max(u, stand[0] / 2 + GAP), length - stand[0] / 2 - GAP)
        sp = L.wall_position(side, u, sofa[1])
        boxes = [box_of(*sp, 0.0, sofa, SIDES[side][0])]
        if free <= 4.5:  # TV stand against the opposite wall
            tp = L.wall_position(opp, us, stand[1])
            behind = None
        else:  # large room: a free-standing TV stand facing the sofa, passage kept behind it
            view = rng.uniform(2.2, 3.2)
            free = view
            tp = L.wall_position(side, us, stand[1], gap=GAP + sofa[1] + view)
            behind = box_of(
                *L.wall_position(side, us, 0.6, gap=GAP + sofa[1] + view + stand[1]),
                0.0,
                (stand[0] + 0.4, 0.6, 1.0),
                SIDES[side][0],
            )
            boxes.append(behind)
        boxes.append(box_of(*tp, 0.0, stand, SIDES[opp][0]))
        if not _all_fit(L, boxes):
            continue
        s = L.place(category("sofa"), sofa, *sp, 0.0, SIDES[side][0], "wall", group=gid)
        t = L.place(
            category("tv_stand"), stand, *tp, 0.0, SIDES[opp][0], "wall" if behind is None else "middle", group=gid
        )
        if behind is not None:
            L.block(behind)
        tv = L.sample_size(category("tv"), max_width=stand[0] - 0.04)
        tv = (tv[0], min(tv[1], stand[1] - 0.04), tv[2])
        _on_top_at(L, "tv", t, 0.0, 0.0, tv, gid)
        ct = L.sample_size(category("coffee_table"))
        if free >= ct[1] + 0.4 + 1.0:
            cp = L.wall_position(side, u, ct[1], gap=GAP + sofa[1] + 0.4)
            c = L.place(category("coffee_table"), ct, *cp, 0.0, SIDES[side][0], "group", group=gid)
            if c and rng.random() < 0.7:
                L.try_on_top(category("remote_control"), parents=[c], face_parent=False, group=gid)
        if rng.random() < 0.5:
            st = L.sample_size(category("side_table"))
            for sign in (1, -1) if rng.random() < 0.5 else (-1, 1):
                p = L.wall_position(side, u + sign * (sofa[0] / 2 + 2 * GAP + st[0] / 2), st[1])
                if L.place(category("side_table"), st, *p, 0.0, SIDES[side][0], "group", group=gid):
                    break
        L.keep_front(s, 0.4)
        L.keep_front(t, 0.4)
        return True
    return False


def dining_group(L: RoomLayout, gid: str) -> bool:
    """Dining group: a table with chairs round it (and at its ends when long), plates; False if it does not fit."""
    rng = L.rng
    x0, y0, x1, y1 = L.interior
    for _ in range(20):
        tw, td, th = L.sample_size(category("dining_table"))
        cw, cd, ch = L.sample_size(category("chair"))
        per_side = max(1, min(3, int((tw - 0.1) // 0.6)))
        ends = tw >= 1.5
        off_y = td / 2 + 0.08 + cd / 2
        off_x = tw / 2 + 0.08 + cd / 2
        half = ((off_x + cd / 2) if ends else tw / 2, off_y + cd / 2)
        yaw = 90 * int(rng.integers(2))
        hx, hy = (half[1], half[0]) if yaw else half
        clear = 0.5
        if x1 - x0 < 2 * (hx + clear) or y1 - y0 < 2 * (hy + clear):
            continue
        x = L.span(x0 + hx + clear, x1 - hx - clear)
        y = L.span(y0 + hy + clear, y1 - hy - clear)
        if not L.fits((x - hx - clear, y - hy - clear, 0.0, x + hx + clear, y + hy + clear, th)):
            continue
        table = L.place(category("dining_table"), (tw, td, th), x, y, 0.0, yaw, "middle", group=gid)
        seats = [
            ((i + 0.5) * tw / per_side - tw / 2, sy * off_y, 0 if sy < 0 else 180)
            for i in range(per_side)
            for sy in (-1, 1)
        ]
        if ends:
            seats += [(-off_x, 0.0, 270), (off_x, 0.0, 90)]
        for lx, ly, cyaw in seats:
            px, py = local_to_world(table, lx, ly)
            L.place(category("chair"), (cw, cd, ch), px, py, 0.0, (cyaw + yaw) % 360, "group", group=gid)
        L.block((x - hx - 0.4, y - hy - 0.4, 0.0, x + hx + 0.4, y + hy + 0.4, 0.6))
        for _ in range(int(rng.integers(0, min(4, 2 * per_side) + 1))):
            L.try_on_top(category("plate"), parents=[table], face_parent=False, group=gid)
        return True
    return False


BED_CORRIDOR = 0.7  # free width kept beside the bed on each nightstand side


def bed_group(L: RoomLayout, gid: str) -> bool:
    """Bedroom group: bed against a wall, one or two nightstands with lamps, pillows; False if it does not fit."""
    rng = L.rng
    for k in range(40):
        side = "SNWE"[int(rng.integers(4))]
        compact = k >= 20  # small bedroom: a narrower bed with one nightstand
        bed = L.sample_size(category("bed"), max_width=1.2 if compact else None)
        ns = L.sample_size(category("nightstand"))
        both = rng.random() < 0.7 and not compact
        slot = max(ns[0] + 2 * GAP, BED_CORRIDOR)
        left = slot
        right = slot if both else 0.0
        length = L.side_length(side)
        if length < bed[0] + left + right + 2 * GAP:
            continue
        u = L.span(left + bed[0] / 2 + GAP, length - right - bed[0] / 2 - GAP)
        yaw = SIDES[side][0]
        bp = L.wall_position(side, u, bed[1])
        signs = (-1, 1) if both else (-1,)
        nps = [L.wall_position(side, u + sg * (bed[0] / 2 + 2 * GAP + ns[0] / 2), ns[1]) for sg in signs]
        boxes = [box_of(*bp, 0.0, bed, yaw)] + [box_of(*p, 0.0, ns, yaw) for p in nps]
        # corridor beside the bed, from the nightstand to the foot of the bed
        corridors = []
        for sg, p in zip(signs, nps):
            cx, cy = L.wall_position(
                side, u + sg * (bed[0] / 2 + 2 * GAP + slot / 2), bed[1] - ns[1] - GAP, gap=2 * GAP + ns[1]
            )
            corridors.append(box_of(cx, cy, 0.0, (slot - GAP, bed[1] - ns[1] - GAP, 1.0), yaw))
        if not _all_fit(L, boxes + corridors):
            continue
        b = L.place(category("bed"), bed, *bp, 0.0, yaw, "wall", group=gid)
        L.keep_front(b, 0.6)
        for c in corridors:
            L.block(c)
        for p in nps:
            n = L.place(category("nightstand"), ns, *p, 0.0, yaw, "group", group=gid)
            if n and rng.random() < 0.8:
                L.try_on_top(category("table_lamp"), parents=[n], group=gid)
        surf = L.sample_size(category("pillow"))
        ly = -0.44 * bed[1] + 0.03 + surf[1] / 2
        if bed[0] >= 1.3:
            pillow, xs = (r4(min(surf[0], bed[0] / 2 - 0.06)), surf[1], surf[2]), (-bed[0] / 4, bed[0] / 4)
        else:
            pillow, xs = (r4(min(surf[0], bed[0] - 0.1)), surf[1], surf[2]), (0.0,)
        for lx in xs:
            _on_top_at(L, "pillow", b, lx, ly, pillow, gid)
        return True
    return False


def tub_with_towel(L: RoomLayout, gid: str, min_area: float) -> None:
    """A bathtub in a corner (from ``min_area`` m^2 of interior, 80% of the time) with a towel on
    the wall above it, else a towel on a free wall."""
    rng = L.rng
    x0, y0, x1, y1 = L.interior
    tub = None
    if (x1 - x0) * (y1 - y0) >= min_area and rng.random() < 0.8:
        tub = L.try_wall(category("bathtub"), corner=True, access=0.5, group=gid)
    towel = L.sample_size(category("towel"))
    if tub:
        side, u = _u_of(L, tub)
        half = (tub.size[0] - towel[0]) / 2 - 0.02
        L.try_on_wall(
            category("towel"),
            towel,
            side=side,
            u_range=(u - half, u + half),
            z=tub.size[2] + rng.uniform(0.4, 0.6),
            group=gid,
        )
    else:
        L.try_on_wall(category("towel"), towel, z=rng.uniform(0.9, 1.2), group=gid)


def toilet_and_sink(L: RoomLayout, gid: str) -> bool:
    """A toilet (with toilet paper beside it, 80% of the time), then a sink with a mirror above
    it; False if the toilet or the sink does not fit."""
    rng = L.rng
    toilet = L.try_wall(category("toilet"), access=0.5, group=gid)
    if toilet is None:
        return False
    if rng.random() < 0.8:
        side, u = _u_of(L, toilet)
        tp = L.sample_size(category("toilet_paper"))
        for sign in (1, -1):
            uu = u + sign * (toilet.size[0] / 2 + 0.12 + tp[0] / 2)
            if L.try_on_wall(
                category("toilet_paper"), tp, tries=1, side=side, u_range=(uu, uu), z=rng.uniform(0.6, 0.72), group=gid
            ):
                break
    sink = L.try_wall(category("sink"), access=0.5, group=gid)
    if sink is None:
        return False
    side, u = _u_of(L, sink)
    mirror = L.sample_size(category("mirror"), max_width=sink.size[0] + 0.1)
    L.try_on_wall(
        category("mirror"),
        mirror,
        tries=3,
        side=side,
        u_range=(u, u),
        z=sink.size[2] + rng.uniform(0.25, 0.4),
        group=gid,
    )
    return True


def bathroom_group(L: RoomLayout, gid: str) -> bool:
    """Bathroom group: bathtub with a towel, toilet with paper, sink with a mirror; False without toilet or sink."""
    tub_with_towel(L, gid, min_area=4.0)
    return toilet_and_sink(L, gid)


def desk_group(L: RoomLayout, gid: str, computer: bool = True) -> bool:
    """Office group: desk against a wall with an office chair, a computer and keyboard (or a laptop), maybe a lamp.

    Returns False if it does not fit; raises ``StageFailure`` when the computer finds no place on the desk.
    """
    rng = L.rng
    for _ in range(25):
        side = "SNWE"[int(rng.integers(4))]
        desk, chair = L.sample_size(category("desk")), L.sample_size(category("office_chair"))
        length = L.side_length(side)
        if length < desk[0] + 2 * GAP:
            continue
        u = L.span(desk[0] / 2 + GAP, length - desk[0] / 2 - GAP)
        yaw = SIDES[side][0]
        dp = L.wall_position(side, u, desk[1])
        cp = L.wall_position(side, u, chair[1], gap=GAP + desk[1] + 0.05)
        if not _all_fit(L, [box_of(*dp, 0.0, desk, yaw), box_of(*cp, 0.0, chair, (yaw + 180) % 360)]):
            continue
        d = L.place(category("desk"), desk, *dp, 0.0, yaw, "wall", group=gid)
        c = L.place(category("office_chair"), chair, *cp, 0.0, (yaw + 180) % 360, "group", group=gid)
        L.keep_front(c, 0.4, back=True)
        back = -desk[1] / 2
        if computer:
            mon = L.sample_size(category("computer"), max_width=desk[0] * 0.6)
            m = _on_top_at(L, "computer", d, 0.0, back + 0.03 + mon[1] / 2, mon, gid)
            if m is None:
                raise StageFailure(f"room {L.room_id}: no place for the computer on {d.name}")
            kb = L.sample_size(category("keyboard"))
            if m:
                _on_top_at(L, "keyboard", d, 0.0, back + 0.03 + mon[1] + 0.05 + kb[1] / 2, kb, gid)
        else:
            L.try_on_top(category("laptop"), parents=[d], group=gid)
        if rng.random() < 0.5:
            lamp = L.sample_size(category("desk_lamp"))
            sign = 1 if rng.random() < 0.5 else -1
            _on_top_at(
                L, "desk_lamp", d, sign * (desk[0] / 2 - 0.03 - lamp[0] / 2), back + 0.03 + lamp[1] / 2, lamp, gid
            )
        return True
    return False


def kitchen_group(L: RoomLayout, gid: str) -> bool:
    """Kitchen group: fridge, stove, sink counter, maybe a dishwasher and counters in a run along one wall.

    Returns False if it does not fit.
    """
    rng = L.rng
    height = r4(round(rng.uniform(0.88, 0.92), 2))
    depth = r4(round(rng.uniform(0.6, 0.62), 2))
    for _ in range(30):
        side = "SNWE"[int(rng.integers(4))]
        length = L.side_length(side)
        if length < 2.5:
            continue
        fridge = L.sample_size(category("fridge"))
        modules = [
            ("stove", r4(round(rng.uniform(0.6, 0.76), 2))),
            ("sink_counter", r4(round(rng.uniform(0.8, 1.2), 2))),
        ]
        if rng.random() < 0.6:
            modules.append(("dishwasher", 0.6))
        target = min(length - 2 * GAP, rng.uniform(2.5, 4.5))
        while fridge[0] + sum(w for _, w in modules) + 0.6 <= target:
            modules.append(
                (
                    "counter",
                    r4(round(rng.uniform(0.6, max(0.6, min(1.2, target - fridge[0] - sum(w for _, w in modules)))), 2)),
                )
            )
        order = [modules[int(i)] for i in rng.permutation(len(modules))]
        run = [("fridge", fridge[0])] + order if rng.random() < 0.5 else order + [("fridge", fridge[0])]
        total = sum(w for _, w in run) + GAP * (len(run) - 1)
        if total > length - 2 * GAP:
            continue
        start = L.span(GAP, length - GAP - total)
        yaw = SIDES[side][0]
        placed, boxes, u = [], [], start
        for name, w in run:
            size = fridge if name == "fridge" else (w, depth, height)
            p = L.wall_position(side, u + w / 2, size[1])
            placed.append((name, size, p))
            boxes.append(box_of(*p, 0.0, size, yaw))
            u += w + GAP
        if not _all_fit(L, boxes):
            continue
        counters = []
        for name, size, p in placed:
            cat = "counter" if name == "sink_counter" else name
            obj = L.place(category(cat), size, *p, 0.0, yaw, "group", group=gid)
            L.keep_front(obj, 0.9)
            if name == "sink_counter":
                sink = L.sample_size(category("kitchen_sink"), max_width=size[0] - 0.1)
                sink = (sink[0], min(sink[1], depth - 0.1), sink[2])
                _on_top_at(L, "kitchen_sink", obj, 0.0, -depth / 2 + 0.03 + sink[1] / 2, sink, gid)
            elif name == "counter":
                counters.append(obj)
        for name, p in (("microwave", 0.8), ("toaster", 0.6)):
            if counters and rng.random() < p:
                L.try_on_top(category(name), parents=counters, group=gid)
        return True
    return False


MANDATORY = {
    "living_room": [("sofa", sofa_group)],
    "bedroom": [("bed", bed_group)],
    "dining_room": [("dining", dining_group)],
    "bathroom": [("bathroom", bathroom_group)],
    "office": [("desk", desk_group)],
    "kitchen": [("kitchen", kitchen_group)],
    "hallway": [],
}


def furnish_room(L: RoomLayout, house_types: list[str], mandatory: dict | None = None) -> None:
    """Furnish one room: its mandatory groups, optional groups, then the fill categories of its type.

    ``house_types``: the room types of the whole house; ``mandatory``: the groups per room type
    (default ``MANDATORY``). Raises ``StageFailure`` when a mandatory group does not fit.
    """
    rng = L.rng
    for gname, fn in (mandatory or MANDATORY)[L.type]:
        if not fn(L, f"{gname}_{L.room_id}"):
            raise StageFailure(f"room {L.room_id} ({L.type}): no place for the {gname} group")
    x0, y0, x1, y1 = L.interior
    area = (x1 - x0) * (y1 - y0)
    if L.type == "kitchen" and "dining_room" not in house_types and area >= 10 and rng.random() < 0.8:
        dining_group(L, f"dining_{L.room_id}")
    if L.type == "living_room" and "dining_room" not in house_types and "kitchen" not in house_types and area >= 20:
        dining_group(L, f"dining_{L.room_id}")
    if L.type == "bedroom" and area >= 10 and rng.random() < 0.3:
        desk_group(L, f"desk_{L.room_id}", computer=rng.random() < 0.5)
    fill = [c for c in CATEGORIES if L.type in c.rooms and c.placement != "group"]
    fill.sort(key=lambda c: FILL_ORDER.index(c.placement))
    for cat in fill:
        if rng.random() < cat.rooms[L.type]:
            for _ in range(int(rng.integers(cat.count[0], cat.count[1] + 1))):
                L.try_category(cat.name)
