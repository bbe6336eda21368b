"""Episode pictures for ``objsearch-eval --video DIR``: a top-down map (PNG) and an MP4.

The map is the house's plan (``objsearch.house.preview``) with the target's objects
outlined, its goal poses, a shortest path and the agent's trajectory, under a title naming
the target, the step count and the outcome, above a legend of those marks. The MP4 shows,
one step a frame (``FPS`` a second), what the agent observed side by side (RGB, depth on a
colour scale, the semantic labels with the target in the map's magenta), under them the
target, the step count, the map's legend and a legend of the categories in view, and beside
all that the map of the trajectory so far. With predicted observations the depth and labels
are the network's, as the agent saw them.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Sequence

import cv2
import numpy as np

from objsearch.fileio import atomic_write
from objsearch.house.categories import CATEGORY_IDS, CATEGORY_NAMES, FIRST_OBJECT_ID, STRUCTURE
from objsearch.house.plan_canvas import (
    HIGHLIGHT,
    PX,
    ROW_H,
    SYMBOL_W,
    TITLE_H,
    PlanLayout,
    plan_layout,
    put_text,
    text_width,
)
from objsearch.house.plan_legend import (
    LegendEntry,
    draw_footer,
    draw_legend,
    footer_height,
    footer_top,
    front_symbol,
    legend_size,
    plan_footer,
)
from objsearch.house.preview import draw_plan
from objsearch.sim.navgraph import GRID, HEADING_VECTORS
from objsearch.sim.world import World

FPS = 10
VIEW = 256  # each egocentric view in the video, pixels a side (RGB, depth and labels side by side)
PANEL_H = 150  # the text panel under the views
DEPTH_RANGE = 5.0  # metres: the depth view's colour scale runs from 0 to this (farther: its far end)
# the semantic view's colours of the structure (BGR); objects get well-spread hues, the target magenta
STRUCTURE_COLORS = {
    "background": (0, 0, 0),
    "wall": (150, 150, 150),
    "floor": (110, 160, 200),
    "door": (40, 120, 200),
    "ceiling": (215, 215, 215),
}
TRAJECTORY = (40, 40, 220)  # BGR red
SHORTEST = (200, 120, 40)  # BGR blue
GOAL = (60, 170, 60)  # BGR green
DASH = (10, 7)  # shortest path: pixels drawn, pixels skipped


def map_title(target: str | None, steps: int | None = None, success: bool | None = None, min_steps=None) -> str:
    """The map's title, e.g. ``target: coffee table - not found in 1000 steps (shortest 41)``:
    the target category, then the steps taken and the outcome where known."""
    title = f"target: {target.replace('_', ' ')}" if target else "episode"
    if steps is not None:
        outcome = {None: "", True: "found in ", False: "not found in "}[success]
        title += f" - {outcome}{steps} step{'s' if steps != 1 else ''}"
    if min_steps is not None:
        title += f" (shortest {min_steps})"
    return title


def _line_symbol(color, dashed=False):
    def draw(img, x, y):
        if dashed:
            _dashed(img, [(x, y + 9), (x + SYMBOL_W - 1, y + 9)], color, 2)
        else:
            cv2.line(img, (x, y + 9), (x + SYMBOL_W - 1, y + 9), color, 3, cv2.LINE_AA)

    return draw


def _goal_symbol(img, x, y):
    cv2.circle(img, (x + SYMBOL_W // 2, y + 9), 5, GOAL, -1, cv2.LINE_AA)


def _start_symbol(img, x, y):
    cv2.circle(img, (x + SYMBOL_W // 2, y + 9), 6, TRAJECTORY, 2, cv2.LINE_AA)


def _end_symbol(img, x, y):
    cv2.arrowedLine(img, (x + 4, y + 9), (x + SYMBOL_W - 3, y + 9), TRAJECTORY, 3, cv2.LINE_AA, tipLength=0.4)


def _target_symbol(img, x, y):
    cv2.rectangle(img, (x + 5, y + 3), (x + SYMBOL_W - 6, y + 15), HIGHLIGHT, 2, cv2.LINE_AA)


def map_legend(target: str | None = None) -> list[LegendEntry]:
    """The legend of an episode map: path taken, a shortest path, goal poses, start, end,
    and the target's objects."""
    name = target.replace("_", " ") if target else "target"
    return [
        ("path taken", _line_symbol(TRAJECTORY)),
        ("a shortest path", _line_symbol(SHORTEST, dashed=True)),
        ("goal poses", _goal_symbol),
        ("start", _start_symbol),
        ("end (heading)", _end_symbol),
        (f"{name} (target)", _target_symbol),
    ]


def _pixel(layout: PlanLayout, row: float, col: float) -> tuple[int, int]:
    return layout.pixel((col + 0.5) * GRID, (row + 0.5) * GRID)


def _dashed(img: np.ndarray, points: Sequence[tuple[int, int]], color, thickness: int) -> None:
    """A dashed polyline whose dashes run on across its corners."""
    on, off = DASH
    phase = 0.0
    for a, b in zip(points[:-1], points[1:]):
        a, b = np.array(a, float), np.array(b, float)
        length = float(np.hypot(*(b - a)))
        t = 0.0
        while t < length:
            in_dash = phase < on
            step = min((on - phase) if in_dash else (on + off - phase), length - t)
            if in_dash:
                p, q = a + (b - a) * t / length, a + (b - a) * (t + step) / length
                cv2.line(img, tuple(map(int, np.round(p))), tuple(map(int, np.round(q))), color, thickness, cv2.LINE_AA)
            t += step
            phase = (phase + step) % (on + off)


def episode_map(
    world: World,
    start,
    goals,
    path_poses,
    trajectory,
    target: str | None = None,
    success: bool | None = None,
    min_steps: int | None = None,
) -> np.ndarray:
    """The episode's map (BGR): a title (``map_title``: ``target``, the steps of
    ``trajectory``, ``success`` and ``min_steps`` where given), the plan with the target's
    objects outlined (magenta), the goal poses (green), a shortest path ``path_poses``
    (blue, dashed) and the agent's trajectory (red) from its start (ring) to its last pose
    (arrow: heading), and a legend of those marks and the doors with the scale bar."""
    spec = world.spec
    entries = map_legend(target) + [e for e in plan_footer(spec) if e[1] is not front_symbol]
    layout = plan_layout(spec, top=TITLE_H, bottom=footer_height(spec, entries), min_width=420)
    img = _base_map(world, layout, goals, path_poses, target)
    for a, b in zip(trajectory[:-1], trajectory[1:]):
        _draw_move(img, layout, a, b)
    _draw_agent(img, layout, start, trajectory[-1])
    put_text(img, map_title(target, len(trajectory) - 1, success, min_steps), (layout.left, 21), 0.55)
    draw_footer(img, spec, layout, entries, footer_top(layout))
    return img


def _base_map(world: World, layout: PlanLayout, goals, path_poses, target: str | None) -> np.ndarray:
    img = layout.canvas()
    draw_plan(img, world.spec, layout, highlight=target)
    for row, col, heading in goals:
        cv2.circle(img, _pixel(layout, row, col), 6, GOAL, -1, cv2.LINE_AA)
    points = [_pixel(layout, p[0], p[1]) for p in path_poses]
    points = [p for i, p in enumerate(points) if i == 0 or p != points[i - 1]]  # turns stay in place
    _dashed(img, points, SHORTEST, 2)
    return img


def _point(layout: PlanLayout, row: float, col: float, scale: float) -> tuple[int, int]:
    """Pixel of the cell centre (row, col) on the map ``layout`` shrunk by ``scale``, in
    quarter pixels (cv2's ``shift=2``), so that lines drawn on a small map stay smooth."""
    x, y = layout.left + (col + 0.5) * GRID * PX, layout.top + layout.plan_h - (row + 0.5) * GRID * PX
    return int(round(x * scale * 4)), int(round(y * scale * 4))


def _draw_move(img: np.ndarray, layout: PlanLayout, a, b, scale: float = 1.0) -> None:
    width = max(int(round(3 * scale)), 1)
    p, q = _point(layout, a[0], a[1], scale), _point(layout, b[0], b[1], scale)
    cv2.line(img, p, q, TRAJECTORY, width, cv2.LINE_AA, shift=2)


def _draw_agent(img: np.ndarray, layout: PlanLayout, start, pose, scale: float = 1.0) -> None:
    width = max(int(round(3 * scale)), 1)
    ring = max(int(round(8 * scale * 4)), 4)
    cv2.circle(img, _point(layout, start[0], start[1], scale), ring, TRAJECTORY, max(width - 1, 1), cv2.LINE_AA, 2)
    row, col, heading = pose
    dx, dy = HEADING_VECTORS[heading]
    tip = _point(layout, row + 1.5 * dy, col + 1.5 * dx, scale)
    cv2.arrowedLine(img, _point(layout, row, col, scale), tip, TRAJECTORY, width, cv2.LINE_AA, 2, tipLength=0.4)


def _encode_png(img: np.ndarray) -> bytes:
    ok, data = cv2.imencode(".png", img)
    if not ok:
        raise RuntimeError("PNG encoding failed")
    return data.tobytes()


def label_colors(target: str | None = None) -> np.ndarray:
    """The semantic view's colour of every label id (256 x 3, BGR): ``STRUCTURE_COLORS``, each
    object category a hue of its own (golden-ratio steps round the wheel), ``target`` magenta."""
    ids = np.arange(256)
    hsv = np.stack([(ids * 0.618034 % 1.0) * 180, np.full(256, 150), np.full(256, 215)], axis=1)
    lut = cv2.cvtColor(hsv.astype(np.uint8)[None], cv2.COLOR_HSV2BGR)[0]
    for name, color in STRUCTURE_COLORS.items():
        lut[STRUCTURE[name]] = color
    lut[len(STRUCTURE) : FIRST_OBJECT_ID] = (0, 0, 0)  # unused ids
    if target in CATEGORY_IDS:
        lut[CATEGORY_IDS[target]] = HIGHLIGHT
    return lut


def observation_views(obs: dict, lut: np.ndarray) -> np.ndarray:
    """RGB | depth | labels of one observation, each ``VIEW`` pixels high (its aspect kept) and
    captioned (BGR)."""
    depth = np.clip(np.nan_to_num(np.asarray(obs["depth"], np.float32)) / DEPTH_RANGE, 0.0, 1.0)
    views = (
        ("RGB", np.ascontiguousarray(np.asarray(obs["rgb"])[:, :, ::-1])),
        (f"depth 0-{DEPTH_RANGE:g} m", cv2.applyColorMap(np.round(depth * 255).astype(np.uint8), cv2.COLORMAP_VIRIDIS)),
        ("labels", lut[np.asarray(obs["semantic"])]),
    )
    out, (h, w) = [], np.asarray(obs["rgb"]).shape[:2]
    for caption, img in views:
        img = cv2.resize(img, (int(round(w * VIEW / h)), VIEW), interpolation=cv2.INTER_NEAREST)
        cv2.rectangle(img, (0, 0), (text_width(caption, 0.4) + 8, 17), (0, 0, 0), -1)
        put_text(img, caption, (4, 13), 0.4, color=(255, 255, 255))
        out.append(img)
    return np.concatenate(out, axis=1)


def _swatch(color):
    def draw(img, x, y):
        cv2.rectangle(img, (x + 4, y + 3), (x + SYMBOL_W - 5, y + 15), tuple(int(c) for c in color), -1)
        cv2.rectangle(img, (x + 4, y + 3), (x + SYMBOL_W - 5, y + 15), (0, 0, 0), 1)

    return draw


def in_view_legend(
    semantic: np.ndarray, lut: np.ndarray, target: str | None, width: int, rows: int
) -> list[LegendEntry]:
    """The object categories in a labels view, the target first, then by pixels, as many as
    ``rows`` legend rows of ``width`` pixels hold."""
    counts = np.bincount(np.asarray(semantic).ravel(), minlength=256)
    ids = [int(i) for i in np.argsort(-counts, kind="stable") if counts[i] and i >= FIRST_OBJECT_ID]
    if target in CATEGORY_IDS and CATEGORY_IDS[target] in ids:
        ids.remove(CATEGORY_IDS[target])
        ids.insert(0, CATEGORY_IDS[target])
    entries = [(CATEGORY_NAMES.get(i, str(i)).replace("_", " "), _swatch(lut[i])) for i in ids]
    while entries and legend_size(entries, width)[1] > rows * ROW_H:
        entries.pop()
    return entries


def _panel(target: str | None, width: int) -> np.ndarray:
    """The video's text panel without its step line and categories in view: the target and the
    map's legend, ``width`` pixels wide."""
    panel = np.full((PANEL_H, width, 3), 255, np.uint8)
    put_text(panel, f"target: {target.replace('_', ' ')}" if target else "episode", (6, 18), 0.5)
    draw_legend(panel, map_legend(target), 4, 44, width - 8)
    return panel


def write_episode(
    out_stem: str | Path, world: World, task, trajectory, observations, success: bool | None = None
) -> None:
    """Write ``<out_stem>.png`` (the map) and ``<out_stem>.mp4`` (views and text | map, per step).

    Args:
        task: the episode's ``HouseTask`` (start, target, goals, min_steps).
        trajectory: (row, col, heading) of every pose visited, the start first.
        observations: the observation at each of those poses: ``rgb`` (uint8 H x W x 3),
            ``depth`` (metres, H x W) and ``semantic`` (label ids, H x W), as the agent got them.
        success: whether the target was found (None: not known, not shown).
    """
    out_stem = Path(out_stem)
    graph = world.graph
    goal_ids = [graph.pose_id(*g) for g in task.goals]
    start = graph.pose_id(*task.start)
    path, pose = [task.start], start
    for action in graph.shortest_path(start, goal_ids):
        pose = int(graph.next_pose[pose, action])
        path.append(graph.pose_of(pose))
    target, min_steps = getattr(task, "target", None), getattr(task, "min_steps", None)
    final = episode_map(world, task.start, task.goals, path, trajectory, target, success, min_steps)
    with atomic_write(out_stem.with_suffix(".png"), "wb") as f:
        f.write(_encode_png(final))

    layout = plan_layout(world.spec)  # the video's map: the plan alone, the text is in the panel
    height = VIEW + PANEL_H
    map_w = int(round(layout.width * height / layout.height)) // 2 * 2
    lut = label_colors(target)
    views_w = observation_views(observations[0], lut).shape[1]
    size = (views_w + map_w, height)
    panel = _panel(target, views_w)
    legend_top = 44 + legend_size(map_legend(target), views_w - 8)[1] + 6  # the categories in view below
    rows = (PANEL_H - legend_top - 14) // ROW_H
    last = len(trajectory) - 1
    fd, tmp = tempfile.mkstemp(dir=out_stem.parent, suffix=".mp4")
    os.close(fd)
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(tmp, 0o666 & ~mask)  # mkstemp makes 0600; give the video the usual mode
    try:
        writer = cv2.VideoWriter(tmp, cv2.VideoWriter_fourcc(*"mp4v"), FPS, size)
        scale = map_w / layout.width  # the map is shrunk once; each step draws its move on it
        drawn = cv2.resize(
            _base_map(world, layout, task.goals, path, target), (map_w, height), interpolation=cv2.INTER_AREA
        )
        blank = np.full((height, size[0], 3), 255, np.uint8)
        for step in range(len(trajectory)):
            frame = blank.copy()
            frame[:VIEW, :views_w] = observation_views(observations[step], lut)
            text = frame[VIEW:, :views_w]
            text[:] = panel
            line = f"step {step}" + (f" (shortest {min_steps})" if min_steps is not None else "")
            if step == last and success is not None:
                line += " - found" if success else " - not found"
            put_text(text, line, (6, 36), 0.45)
            seen = in_view_legend(observations[step]["semantic"], lut, target, views_w - 8 - 70, rows)
            put_text(text, "in view:", (6, legend_top + 13), 0.4)
            draw_legend(text, seen, 70, legend_top, views_w - 8 - 70)
            if step:
                _draw_move(drawn, layout, trajectory[step - 1], trajectory[step], scale)
            step_map = frame[:, size[0] - map_w :]
            step_map[:] = drawn
            _draw_agent(step_map, layout, task.start, trajectory[step], scale)
            writer.write(frame)
        writer.release()
        os.replace(tmp, out_stem.with_suffix(".mp4"))
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
