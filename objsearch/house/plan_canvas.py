"""The canvas of a house plan: pixels a metre, colours, text, and where the plan lies.

Shared by the preview (``objsearch.house.preview``), its legends and symbols
(``objsearch.house.plan_legend``) and the episode maps of ``objsearch.sim.video``.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from objsearch.house.spec import Door, HouseSpec

PX = 60  # pixels a metre
MARGIN = 40  # white border round the plan: room for the entrance's arrow and label
TITLE_H = 30
ROW_H = 18  # one legend row
SYMBOL_W = 26  # a legend symbol's box
FONT = cv2.FONT_HERSHEY_SIMPLEX
INK = (20, 20, 20)
WALL = (60, 60, 60)
GAP = (250, 250, 250)
DOOR = (40, 120, 200)  # BGR orange
ENTRANCE = (40, 150, 40)  # BGR green
FRONT = (0, 0, 200)
HIGHLIGHT = (200, 0, 200)  # BGR magenta: the target's objects on episode maps
ROOM_COLORS = {  # BGR
    "living_room": (170, 210, 240),
    "kitchen": (170, 235, 200),
    "dining_room": (150, 200, 235),
    "bedroom": (235, 200, 190),
    "bathroom": (235, 225, 160),
    "office": (210, 180, 220),
    "hallway": (205, 205, 205),
}


@dataclass(frozen=True)
class PlanLayout:
    """Where a house's plan lies on a canvas of ``width`` x ``height`` pixels.

    ``left``, ``top``: pixel of the plan's north-west corner (x = 0, y = depth);
    ``plan_w``, ``plan_h``: the footprint in pixels (``PX`` a metre).
    """

    width: int
    height: int
    left: int
    top: int
    plan_w: int
    plan_h: int

    def pixel(self, x: float, y: float) -> tuple[int, int]:
        """Pixel (column, row) of world point (x, y) metres (y points up the picture)."""
        return int(round(self.left + x * PX)), int(round(self.top + self.plan_h - y * PX))

    def canvas(self) -> np.ndarray:
        """A white BGR canvas of the layout's size."""
        return np.full((self.height, self.width, 3), 255, np.uint8)


def plan_layout(spec: HouseSpec, top: int = 0, bottom: int = 0, right: int = 0, min_width: int = 0) -> PlanLayout:
    """The layout of ``spec``'s plan with ``MARGIN`` round it, ``top`` / ``bottom`` pixels
    above / below for a title and a footer and ``right`` beside it for a legend."""
    width, depth = spec.footprint
    plan_w, plan_h = int(round(width * PX)), int(round(depth * PX))
    return PlanLayout(
        width=max(plan_w + 2 * MARGIN + right, min_width),
        height=top + plan_h + 2 * MARGIN + bottom,
        left=MARGIN,
        top=top + MARGIN,
        plan_w=plan_w,
        plan_h=plan_h,
    )


def put_text(img: np.ndarray, text: str, org: tuple[int, int], scale: float = 0.45, color=INK, thickness=1) -> None:
    """Draw ``text`` with its baseline's left end at ``org`` (Hershey simplex, anti-aliased)."""
    cv2.putText(img, text, org, FONT, scale, color, thickness, cv2.LINE_AA)


def text_width(text: str, scale: float = 0.45, thickness: int = 1) -> int:
    """Width in pixels of ``text`` drawn by ``put_text``."""
    return cv2.getTextSize(text, FONT, scale, thickness)[0][0]


def entrances(spec: HouseSpec) -> list[Door]:
    """The doors that lead outside (one of their ``rooms`` is a negative id)."""
    return [d for d in spec.doors if min(d.rooms) < 0]


def scale_bar_metres(spec: HouseSpec) -> int:
    """Length of the scale bar: 2 m, or 1 m for a footprint under 6 m wide."""
    return 1 if spec.footprint[0] < 6 else 2
