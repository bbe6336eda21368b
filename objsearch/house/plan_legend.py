"""Legends, symbols, the scale bar and the north arrow under and beside a house plan
(the preview and the episode maps)."""

from __future__ import annotations

from typing import Callable, Sequence

import cv2
import numpy as np

from objsearch.house.plan_canvas import (
    DOOR,
    ENTRANCE,
    FRONT,
    GAP,
    INK,
    MARGIN,
    PX,
    ROW_H,
    SYMBOL_W,
    WALL,
    PlanLayout,
    entrances,
    put_text,
    scale_bar_metres,
    text_width,
)
from objsearch.house.spec import HouseSpec

#: A legend entry: its label and a function drawing its symbol in the box at (x, y).
LegendEntry = tuple[str, Callable[[np.ndarray, int, int], None]]


def legend_size(entries: Sequence[LegendEntry], max_width: int) -> tuple[int, int]:
    """(width, height) that ``draw_legend`` fills with ``entries`` wrapped at ``max_width``."""
    return _legend(None, entries, 0, 0, max_width)


def draw_legend(img: np.ndarray, entries: Sequence[LegendEntry], x: int, y: int, max_width: int) -> tuple[int, int]:
    """Draw ``entries`` (symbol, then label) left to right from (x, y), wrapping at
    ``max_width`` pixels; returns the (width, height) used."""
    return _legend(img, entries, x, y, max_width)


def _legend(img, entries, x, y, max_width) -> tuple[int, int]:
    """Entries in a grid of equal columns, as many as ``max_width`` holds (at least one)."""
    if not entries:
        return 0, 0
    col_w = max(SYMBOL_W + 4 + text_width(label, 0.4) + 14 for label, _ in entries)
    cols = min(max(max_width // col_w, 1), len(entries))
    if img is not None:
        for i, (label, symbol) in enumerate(entries):
            cx, cy = x + (i % cols) * col_w, y + (i // cols) * ROW_H
            symbol(img, cx, cy)
            put_text(img, label, (cx + SYMBOL_W + 4, cy + 13), 0.4)
    return cols * col_w, (len(entries) + cols - 1) // cols * ROW_H


def door_symbol(img: np.ndarray, x: int, y: int) -> None:
    """Legend symbol of a door: the orange bar in a gap of a wall."""
    cv2.rectangle(img, (x, y + 6), (x + SYMBOL_W - 1, y + 12), WALL, -1)
    cv2.rectangle(img, (x + 6, y + 5), (x + SYMBOL_W - 7, y + 13), GAP, -1)
    cv2.line(img, (x + 6, y + 9), (x + SYMBOL_W - 7, y + 9), DOOR, 4, cv2.LINE_AA)


def entrance_symbol(img: np.ndarray, x: int, y: int) -> None:
    """Legend symbol of the entrance: a green arrow into the house."""
    cv2.arrowedLine(img, (x + 2, y + 9), (x + SYMBOL_W - 2, y + 9), ENTRANCE, 3, cv2.LINE_AA, tipLength=0.45)


def front_symbol(img: np.ndarray, x: int, y: int) -> None:
    """Legend symbol of an object with the red tick on its front side."""
    cv2.rectangle(img, (x + 4, y + 3), (x + SYMBOL_W - 5, y + 15), (190, 190, 190), -1)
    cv2.rectangle(img, (x + 4, y + 3), (x + SYMBOL_W - 5, y + 15), (0, 0, 0), 1)
    cv2.line(img, (x + SYMBOL_W // 2, y + 9), (x + SYMBOL_W // 2, y + 15), FRONT, 2, cv2.LINE_AA)


def draw_scale_bar(img: np.ndarray, x: int, y: int, metres: int) -> int:
    """A bar of ``metres`` (``PX`` pixels a metre: it covers columns x .. x + PX * metres - 1,
    rows y .. y + 5) in black and white metres, labelled; returns the column after the label."""
    for m in range(metres):
        color = INK if m % 2 == 0 else (255, 255, 255)
        cv2.rectangle(img, (x + m * PX, y), (x + (m + 1) * PX - 1, y + 5), color, -1)
    cv2.rectangle(img, (x, y), (x + metres * PX - 1, y + 5), INK, 1)
    label = f"{metres} m"
    put_text(img, label, (x + metres * PX + 6, y + 9), 0.4)
    return x + metres * PX + 6 + text_width(label, 0.4)


def draw_north_arrow(img: np.ndarray, x: int, y: int) -> None:
    """An arrow pointing up the picture (north, +y) with an ``N``, its top-left at (x, y)."""
    cv2.arrowedLine(img, (x + 5, y + 22), (x + 5, y + 2), INK, 2, cv2.LINE_AA, tipLength=0.35)
    put_text(img, "N", (x + 12, y + 14), 0.4)


def plan_footer(spec: HouseSpec) -> list[LegendEntry]:
    """The symbols a plan's footer explains: doors, the entrance if the house has one, object fronts."""
    entries = [("door", door_symbol)]
    if entrances(spec):
        entries.append(("entrance", entrance_symbol))
    return entries + [("front of an object", front_symbol)]


def draw_footer(img: np.ndarray, spec: HouseSpec, layout: PlanLayout, entries: Sequence[LegendEntry], y: int) -> None:
    """The scale bar, then ``entries`` (wrapped to the plan's width), then a north arrow, from row ``y``."""
    x = draw_scale_bar(img, layout.left, y + 6, scale_bar_metres(spec)) + 24
    used, _ = draw_legend(img, entries, x, y, layout.left + layout.plan_w - 30 - x)
    # at the plan's right edge, or past the legend where the plan is narrower than it (a small room)
    draw_north_arrow(img, max(layout.left + layout.plan_w - 16, x + used + 14), y - 4)


def footer_height(spec: HouseSpec, entries: Sequence[LegendEntry]) -> int:
    """Rows ``draw_footer`` needs below the plan for ``entries``."""
    width = int(round(spec.footprint[0] * PX))
    bar = scale_bar_metres(spec) * PX + 6 + text_width("2 m", 0.4) + 24
    return legend_size(entries, width - 30 - bar)[1] + 12


def footer_top(layout: PlanLayout) -> int:
    """First row of the footer (scale bar and symbols) under the plan of ``layout``."""
    return layout.top + layout.plan_h + MARGIN - 4
