"""Top-down preview of a house (``preview.png``): rooms coloured and labelled, doors, objects.

Rooms are filled by type, walls drawn dark, door openings as light gaps with a door-width
arc, floor objects as filled rectangles with a tick on their front side, wall-mounted and
small objects as outlined rectangles. Drawn with OpenCV; 60 pixels per metre.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from objsearch.fileio import atomic_write
from objsearch.house.spec import HouseSpec

PX = 60
MARGIN = 20
ROOM_COLORS = {  # BGR
    "living_room": (170, 210, 240),
    "kitchen": (170, 235, 200),
    "dining_room": (150, 200, 235),
    "bedroom": (235, 200, 190),
    "bathroom": (235, 225, 160),
    "office": (210, 180, 220),
    "hallway": (205, 205, 205),
}


def render_preview(spec: HouseSpec) -> np.ndarray:
    """A top-down BGR (H, W, 3) uint8 plan of the house (cv2 order): rooms, walls, doors, objects, a title."""
    width, depth = spec.footprint
    h, w = int(depth * PX) + 2 * MARGIN, int(width * PX) + 2 * MARGIN
    img = np.full((h, w, 3), 255, np.uint8)

    def pt(x, y):  # world -> pixel (y up)
        return int(round(MARGIN + x * PX)), int(round(h - MARGIN - y * PX))

    def rect(box, color, thickness=-1):
        x0, y0, x1, y1 = box
        cv2.rectangle(img, pt(x0, y1), pt(x1, y0), color, thickness, lineType=cv2.LINE_AA)

    for r in spec.rooms:
        rect(r.bounds, ROOM_COLORS.get(r.type, (220, 220, 220)))
    for wall in spec.walls:
        rect(wall.box, (60, 60, 60))
    for d in spec.doors:
        x0, y0, x1, y1 = d.span
        t = spec.wall_thickness / 2 + 0.01
        box = (x0, y0 - t, x1, y1 + t) if d.axis == "x" else (x0 - t, y0, x1 + t, y1)
        rect(box, (250, 250, 250))
        cv2.line(img, pt(x0, y0), pt(x1, y1), (40, 120, 200), 2, cv2.LINE_AA)
    for o in sorted(spec.objects, key=lambda o: o.position[2]):
        fp = o.footprint
        color = tuple(int(255 * c) for c in reversed(o.rgba[:3]))
        if o.placement in ("on_top", "on_wall"):
            rect(fp, color)
            rect(fp, (30, 30, 30), 1)
        else:
            rect(fp, color)
            rect(fp, (0, 0, 0), 1)
            cx, cy = (fp[0] + fp[2]) / 2, (fp[1] + fp[3]) / 2
            fx, fy = o.front
            half = o.size[1] / 2
            cv2.line(
                img,
                pt(cx + fx * half * 0.5, cy + fy * half * 0.5),
                pt(cx + fx * half, cy + fy * half),
                (0, 0, 200),
                2,
                cv2.LINE_AA,
            )
    for r in spec.rooms:
        x0, y0, x1, y1 = r.bounds
        label = r.type.replace("_", " ")
        (tw, th), _ = cv2.getTextSize(label, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1)
        px, py = pt((x0 + x1) / 2, (y0 + y1) / 2)
        cv2.rectangle(img, (px - tw // 2 - 3, py - th - 3), (px + tw // 2 + 3, py + 4), (255, 255, 255), -1)
        cv2.putText(img, label, (px - tw // 2, py), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (20, 20, 20), 1, cv2.LINE_AA)
    cv2.putText(
        img,
        f"{spec.house_id}  {width:g} x {depth:g} m  {len(spec.objects)} objects",
        (MARGIN, 14),
        cv2.FONT_HERSHEY_SIMPLEX,
        0.45,
        (0, 0, 0),
        1,
        cv2.LINE_AA,
    )
    return img


def write_preview(spec: HouseSpec, path: str | Path) -> None:
    """Write the preview plan of ``spec`` as a PNG at ``path``."""
    ok, data = cv2.imencode(".png", render_preview(spec))
    if not ok:
        raise RuntimeError(f"could not encode the preview of {spec.house_id}")
    with atomic_write(path, "wb") as f:
        f.write(data.tobytes())
