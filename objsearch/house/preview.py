"""Top-down preview of a house (``preview.png``), readable without the spec at hand.

A title (house id, size, rooms, objects) above the plan; in the plan, rooms filled by type
with their name and area, walls dark, door openings as light gaps with an orange bar, the
entrance (a door to room id < 0, outside) in green with an arrow from outside, and objects
as rectangles with a red tick on their front side and a numbered marker. Beside the plan a
legend numbers the object categories present (in category-table order); under it a scale
bar, the symbols and a north arrow (+y is north). Drawn with OpenCV and Hershey fonts at
``PX`` pixels a metre: the same spec gives the same bytes.

The canvas (pixels a metre, colours, text, ``PlanLayout``) is ``objsearch.house.plan_canvas``;
legends, symbols, the scale bar and the north arrow are ``objsearch.house.plan_legend``.
``objsearch.sim.video`` draws episode maps on the same plan with ``plan_layout``,
``draw_plan`` and ``draw_legend``.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from objsearch.fileio import atomic_write
from objsearch.house.plan_canvas import (
    DOOR,
    ENTRANCE,
    FRONT,
    GAP,
    HIGHLIGHT,
    INK,
    MARGIN,
    PX,
    ROOM_COLORS,
    ROW_H,
    TITLE_H,
    WALL,
    PlanLayout,
    plan_layout,
    put_text,
    text_width,
)
from objsearch.house.plan_legend import draw_footer, footer_height, footer_top, plan_footer
from objsearch.house.spec import Door, HouseSpec, Room

TITLE_SCALE = 0.55


def category_numbers(spec: HouseSpec) -> dict[str, int]:
    """Number (1, 2, ...) of every object category in ``spec``, in category-table order."""
    from objsearch.house.categories import CATEGORY_IDS

    names = sorted({o.category for o in spec.objects}, key=lambda n: (CATEGORY_IDS.get(n, 10**6), n))
    return {name: i + 1 for i, name in enumerate(names)}


def room_label(room: Room) -> tuple[str, str]:
    """The two lines written in a room: its type and its area (``m2`` is drawn as m²)."""
    return room.type.replace("_", " "), f"{room.area:.1f} m2"


def _rect(img, layout: PlanLayout, box, color, thickness=-1) -> None:
    x0, y0, x1, y1 = box
    cv2.rectangle(img, layout.pixel(x0, y1), layout.pixel(x1, y0), color, thickness, lineType=cv2.LINE_AA)


def _polygon(layout: PlanLayout, room: Room) -> np.ndarray:
    return np.array([layout.pixel(x, y) for x, y in room.polygon], np.int32)


def _integral(mask: np.ndarray) -> np.ndarray:
    return cv2.integral(mask.astype(np.uint8))


def _box_sums(integral: np.ndarray, x: np.ndarray, y: np.ndarray, w: int, h: int) -> np.ndarray:
    """Sum of the mask over the w x h box at each (x, y) top-left corner."""
    return integral[y + h, x + w] - integral[y, x + w] - integral[y + h, x] + integral[y, x]


def _room_label_boxes(spec: HouseSpec, layout: PlanLayout) -> list[tuple[int, int, int, int, float]]:
    """(x, y, w, h, scale) of each room's label box: inside the room, over as little
    furniture as possible, else as near the room's centre as possible."""
    shape = (layout.height, layout.width)
    blocked = np.zeros(shape, np.uint8)
    for o in spec.objects:
        x0, y0, x1, y1 = o.footprint
        (c0, r0), (c1, r1) = layout.pixel(x0, y1), layout.pixel(x1, y0)
        blocked[max(r0, 0) : r1 + 1, max(c0, 0) : c1 + 1] = 1
    walls = np.zeros(shape, np.uint8)
    for w in spec.walls:
        x0, y0, x1, y1 = w.box
        (c0, r0), (c1, r1) = layout.pixel(x0, y1), layout.pixel(x1, y0)
        walls[max(r0 - 3, 0) : r1 + 4, max(c0 - 3, 0) : c1 + 4] = 1
    objects = _integral(blocked)
    boxes = []
    for room in spec.rooms:
        inside = np.zeros(shape, np.uint8)
        cv2.fillPoly(inside, [_polygon(layout, room)], 1)
        outside = _integral((inside == 0) | (walls == 1))
        cx, cy = layout.pixel(*np.mean(np.array(room.polygon), axis=0))
        x0, y0, x1, y1 = room.bounds
        (c0, r0), (c1, r1) = layout.pixel(x0, y1), layout.pixel(x1, y0)
        best = None
        for scale in (0.5, 0.42, 0.36):
            w, h = _label_size(room, scale)
            ys = np.arange(max(r0, 0), min(r1, layout.height - 1) - h, 2)
            xs = np.arange(max(c0, 0), min(c1, layout.width - 1) - w, 2)
            if not len(ys) or not len(xs):
                continue
            yy, xx = np.meshgrid(ys, xs, indexing="ij")
            ok = _box_sums(outside, xx, yy, w, h) == 0
            if not ok.any():
                continue
            dist = np.abs(xx + w / 2 - cx) + np.abs(yy + h / 2 - cy)
            cost = np.where(ok, 20.0 * _box_sums(objects, xx, yy, w, h) + dist, np.inf)
            i = np.unravel_index(int(np.argmin(cost)), cost.shape)  # first minimum: deterministic
            best = (0, int(xx[i]), int(yy[i]), w, h, scale)
            break
        if best is None:  # a room too small for its label: centred on it
            w, h = _label_size(room, 0.36)
            best = (0, cx - w // 2, cy - h // 2, w, h, 0.36)
        boxes.append(best[1:])
    return boxes


def _label_size(room: Room, scale: float) -> tuple[int, int]:
    name, area = room_label(room)
    w = max(text_width(name, scale), text_width(area, scale * 0.85) + 6)
    return w + 8, int(round(44 * scale)) + 12


def _draw_room_label(img, room: Room, box) -> None:
    x, y, w, h, scale = box
    cv2.rectangle(img, (x, y), (x + w - 1, y + h - 1), (255, 255, 255), -1)
    cv2.rectangle(img, (x, y), (x + w - 1, y + h - 1), (150, 150, 150), 1)
    name, area = room_label(room)
    line = int(round(22 * scale))
    put_text(img, name, (x + (w - text_width(name, scale)) // 2, y + 4 + line), scale)
    small = scale * 0.85
    aw = text_width(area, small) + 6
    ax, ay = x + (w - aw) // 2, y + h - 5
    put_text(img, area[:-1], (ax, ay), small)  # "12.3 m", then a raised small "2"
    put_text(img, "2", (ax + text_width(area[:-1], small) + 1, ay - int(9 * small)), small * 0.65)


def _draw_doors(img, spec: HouseSpec, layout: PlanLayout) -> None:
    t = spec.wall_thickness / 2 + 0.01
    for d in spec.doors:
        x0, y0, x1, y1 = d.span
        box = (x0, y0 - t, x1, y1 + t) if d.axis == "x" else (x0 - t, y0, x1 + t, y1)
        _rect(img, layout, box, GAP)
        entrance = min(d.rooms) < 0
        cv2.line(img, layout.pixel(x0, y0), layout.pixel(x1, y1), ENTRANCE if entrance else DOOR, 4, cv2.LINE_AA)
        if entrance:
            _draw_entrance_arrow(img, spec, layout, d)


def _outward(spec: HouseSpec, door: Door) -> tuple[int, int]:
    """Unit (dx, dy) from the door away from the room it leads into (outside)."""
    inside = [r for r in spec.rooms if r.id in door.rooms]
    cx, cy = door.center
    probe = (cx, cy + 0.3) if door.axis == "x" else (cx + 0.3, cy)
    polygon = np.array(inside[0].polygon if inside else [(0, 0)], np.float32)
    into_positive = cv2.pointPolygonTest(polygon, probe, False) > 0
    sign = -1 if into_positive else 1
    return (0, sign) if door.axis == "x" else (sign, 0)


def _draw_entrance_arrow(img, spec: HouseSpec, layout: PlanLayout, door: Door) -> None:
    dx, dy = _outward(spec, door)
    tip = np.array(layout.pixel(*door.center)) + np.array([dx, -dy]) * int(PX * spec.wall_thickness / 2 + 3)
    tail = tip + np.array([dx, -dy]) * 24
    cv2.arrowedLine(img, tuple(map(int, tail)), tuple(map(int, tip)), ENTRANCE, 3, cv2.LINE_AA, tipLength=0.45)
    label = "entrance"
    w = text_width(label, 0.4)
    patch = np.full((14, w + 4, 3), 255, np.uint8)
    put_text(patch, label, (2, 10), 0.4, ENTRANCE)
    if dx:  # an east or west wall: the label runs along it, beside the arrow
        patch = np.ascontiguousarray(np.rot90(patch, 1 if dx > 0 else -1))
        x, y = int(tail[0]) - patch.shape[1] // 2 - 12 * dx, int(tail[1]) - patch.shape[0] // 2
    else:
        x, y = int(tail[0]) + 8, (int(tip[1]) + int(tail[1])) // 2 - 7
    _paste(img, patch, x, y)


def _paste(img: np.ndarray, patch: np.ndarray, x: int, y: int) -> None:
    h, w = patch.shape[:2]
    x, y = min(max(x, 0), img.shape[1] - w), min(max(y, 0), img.shape[0] - h)
    region = img[y : y + h, x : x + w]
    np.minimum(region, patch, out=region)  # dark text over whatever is there


def _draw_objects(img, spec: HouseSpec, layout: PlanLayout, highlight: str | None) -> None:
    for o in sorted(spec.objects, key=lambda o: o.position[2]):
        fp = o.footprint
        _rect(img, layout, fp, tuple(int(255 * c) for c in reversed(o.rgba[:3])))
        _rect(img, layout, fp, (30, 30, 30) if o.placement in ("on_top", "on_wall") else (0, 0, 0), 1)
        if o.placement not in ("on_top", "on_wall"):
            cx, cy = (fp[0] + fp[2]) / 2, (fp[1] + fp[3]) / 2
            (fx, fy), half = o.front, o.size[1] / 2
            a, b = (
                layout.pixel(cx + fx * half * 0.5, cy + fy * half * 0.5),
                layout.pixel(cx + fx * half, cy + fy * half),
            )
            cv2.line(img, a, b, FRONT, 2, cv2.LINE_AA)
    for o in spec.objects:
        if o.category == highlight:
            x0, y0, x1, y1 = o.footprint
            _rect(img, layout, (x0 - 0.05, y0 - 0.05, x1 + 0.05, y1 + 0.05), HIGHLIGHT, 3)


def _marker_size(number: int) -> tuple[int, int]:
    return text_width(str(number), 0.33) + 5, 13


def draw_marker(img: np.ndarray, number: int, x: int, y: int) -> None:
    """The numbered marker of an object category, its top-left corner at (x, y)."""
    w, h = _marker_size(number)
    cv2.rectangle(img, (x, y), (x + w - 1, y + h - 1), (255, 255, 255), -1)
    cv2.rectangle(img, (x, y), (x + w - 1, y + h - 1), INK, 1)
    put_text(img, str(number), (x + 3, y + h - 3), 0.33)


def _draw_markers(img, spec: HouseSpec, layout: PlanLayout, numbers: dict[str, int], taken: list) -> None:
    """A marker on each object, small objects first (at their centre); one that would
    cover another marker or a room label moves within its object, else is left out."""
    free = np.ones((layout.height, layout.width), np.uint8)
    for x, y, w, h, *_ in taken:
        free[max(y, 0) : y + h, max(x, 0) : x + w] = 0

    def area(o):
        x0, y0, x1, y1 = o.footprint
        return (x1 - x0) * (y1 - y0)

    for o in sorted(spec.objects, key=lambda o: (area(o), o.name)):
        w, h = _marker_size(numbers[o.category])
        x0, y0, x1, y1 = o.footprint
        (c0, r0), (c1, r1) = layout.pixel(x0, y1), layout.pixel(x1, y0)
        cx, cy = (c0 + c1) // 2 - w // 2, (r0 + r1) // 2 - h // 2
        spots = [(cx, cy)] + sorted(
            ((x, y) for y in range(r0, max(r1 - h, r0) + 1, 3) for x in range(c0, max(c1 - w, c0) + 1, 3)),
            key=lambda p: (abs(p[0] - cx) + abs(p[1] - cy), p),
        )
        for x, y in spots:
            if (
                0 <= x
                and 0 <= y
                and x + w <= layout.width
                and y + h <= layout.height
                and free[y : y + h, x : x + w].all()
            ):
                draw_marker(img, numbers[o.category], x, y)
                free[max(y - 1, 0) : y + h + 1, max(x - 1, 0) : x + w + 1] = 0
                break


def draw_plan(
    img: np.ndarray,
    spec: HouseSpec,
    layout: PlanLayout,
    *,
    room_labels: bool = True,
    numbers: dict[str, int] | None = None,
    highlight: str | None = None,
) -> None:
    """Draw the plan of ``spec`` into ``img`` at ``layout``: rooms, walls, doors and the
    entrance, objects (outlined in magenta where their category is ``highlight``), room
    labels if ``room_labels`` and, with ``numbers`` (category -> number), object markers."""
    for r in spec.rooms:
        cv2.fillPoly(img, [_polygon(layout, r)], ROOM_COLORS.get(r.type, (220, 220, 220)), cv2.LINE_AA)
    for wall in spec.walls:
        _rect(img, layout, wall.box, WALL)
    _draw_doors(img, spec, layout)
    _draw_objects(img, spec, layout, highlight)
    boxes = _room_label_boxes(spec, layout)  # laid out with or without labels: markers stay put
    if room_labels:
        for room, box in zip(spec.rooms, boxes):
            _draw_room_label(img, room, box)
    if numbers is not None:
        _draw_markers(img, spec, layout, numbers, boxes)


def _category_legend(spec: HouseSpec, numbers: dict[str, int], rows: int) -> tuple[int, list]:
    """The width of the category legend in columns of ``rows`` entries, and each entry's (x, y)."""
    names = list(numbers)
    col_w = max(text_width(n.replace("_", " "), 0.4) for n in names) + _marker_size(99)[0] + 20 if names else 0
    spots = [((i // rows) * col_w, (i % rows) * ROW_H) for i in range(len(names))]
    return (len(names) + rows - 1) // rows * col_w if names else 0, spots


def _preview_parts(spec: HouseSpec, object_labels: bool = True):
    numbers = category_numbers(spec) if object_labels else {}
    entries = plan_footer(spec)
    rows = max((int(round(spec.footprint[1] * PX)) + 2 * MARGIN - 24) // ROW_H, 1)
    legend_w, spots = _category_legend(spec, numbers, rows)
    right = legend_w + 10 if numbers else 0
    title_w = text_width(_title(spec), TITLE_SCALE) + 2 * MARGIN  # a small room's plan is narrower than its title
    layout = plan_layout(spec, top=TITLE_H, bottom=footer_height(spec, entries), right=right, min_width=title_w)
    return layout, numbers, entries, spots


def _title(spec: HouseSpec) -> str:
    width, depth = spec.footprint
    rooms = f"{len(spec.rooms)} rooms" if spec.single_room is None else "1 room"
    return f"{spec.house_id}   {width:g} x {depth:g} m   {rooms}   {len(spec.objects)} objects"


def preview_layout(spec: HouseSpec, object_labels: bool = True) -> PlanLayout:
    """Where ``render_preview`` puts the plan of ``spec`` (with or without the category legend)."""
    return _preview_parts(spec, object_labels)[0]


def render_preview(spec: HouseSpec, *, room_labels: bool = True, object_labels: bool = True) -> np.ndarray:
    """The preview of ``spec`` as a BGR (H, W, 3) uint8 image (cv2 order): title, plan,
    legend of the numbered object categories (``object_labels``), scale bar and symbols."""
    layout, numbers, entries, spots = _preview_parts(spec, object_labels)
    img = layout.canvas()
    draw_plan(img, spec, layout, room_labels=room_labels, numbers=numbers if object_labels else None)
    put_text(img, _title(spec), (MARGIN, 21), TITLE_SCALE)
    if numbers:
        x0 = layout.left + layout.plan_w + MARGIN
        put_text(img, "objects", (x0, layout.top - MARGIN + 12), 0.45)
        for (name, number), (dx, dy) in zip(numbers.items(), spots):
            x, y = x0 + dx, layout.top - MARGIN + 22 + dy
            draw_marker(img, number, x, y + 2)
            put_text(img, name.replace("_", " "), (x + _marker_size(99)[0] + 5, y + 13), 0.4)
    draw_footer(img, spec, layout, entries, footer_top(layout))
    return img


def write_preview(spec: HouseSpec, path: str | Path) -> None:
    """Write the preview plan of ``spec`` as a PNG at ``path``."""
    ok, data = cv2.imencode(".png", render_preview(spec))
    if not ok:
        raise RuntimeError(f"could not encode the preview of {spec.house_id}")
    with atomic_write(path, "wb") as f:
        f.write(data.tobytes())
