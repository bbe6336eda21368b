"""Episode pictures for ``objsearch-eval --video DIR``: a top-down map (PNG) with the
trajectory, the goal poses and a shortest path, and an MP4 of the egocentric view beside
the map, one step a frame."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import cv2
import numpy as np

from objsearch.fileio import atomic_write
from objsearch.house.preview import MARGIN, PX, render_preview
from objsearch.sim.navgraph import GRID, HEADING_VECTORS
from objsearch.sim.world import World

FPS = 4
VIEW = 256  # egocentric view height in the video, pixels


def _pixel(img_height: int, row: int, col: int) -> tuple[int, int]:
    x, y = (col + 0.5) * GRID, (row + 0.5) * GRID
    return int(round(MARGIN + x * PX)), int(round(img_height - MARGIN - y * PX))


def episode_map(world: World, start, goals, path_poses, trajectory) -> np.ndarray:
    """Top-down map: goal poses (green), a shortest path (blue, dashed), the agent's
    trajectory (red) from its start (ring) with its heading at the end (arrow)."""
    img = _base_map(world, goals, path_poses)
    for a, b in zip(trajectory[:-1], trajectory[1:]):
        _draw_move(img, a, b)
    _draw_agent(img, start, trajectory[-1])
    return img


def _base_map(world: World, goals, path_poses) -> np.ndarray:
    img = render_preview(world.spec)
    h = img.shape[0]
    for row, col, heading in goals:
        cv2.circle(img, _pixel(h, row, col), 6, (60, 170, 60), -1, cv2.LINE_AA)
    for a, b in zip(path_poses[:-1], path_poses[1:]):
        if (a[0], a[1]) != (b[0], b[1]):
            cv2.line(img, _pixel(h, a[0], a[1]), _pixel(h, b[0], b[1]), (200, 120, 40), 2, cv2.LINE_4)
    return img


def _draw_move(img: np.ndarray, a, b) -> None:
    h = img.shape[0]
    cv2.line(img, _pixel(h, a[0], a[1]), _pixel(h, b[0], b[1]), (40, 40, 220), 3, cv2.LINE_AA)


def _draw_agent(img: np.ndarray, start, pose) -> None:
    h = img.shape[0]
    cv2.circle(img, _pixel(h, start[0], start[1]), 8, (40, 40, 220), 2, cv2.LINE_AA)
    row, col, heading = pose
    dx, dy = HEADING_VECTORS[heading]
    tip = _pixel(h, row + 1.5 * dy, col + 1.5 * dx)
    cv2.arrowedLine(img, _pixel(h, row, col), tip, (40, 40, 220), 3, cv2.LINE_AA, tipLength=0.4)


def _encode_png(img: np.ndarray) -> bytes:
    ok, data = cv2.imencode(".png", img)
    if not ok:
        raise RuntimeError("PNG encoding failed")
    return data.tobytes()


def write_episode(out_stem: str | Path, world: World, task, trajectory, views) -> None:
    """Write ``<out_stem>.png`` (the map) and ``<out_stem>.mp4`` (view | map, per step).

    Args:
        trajectory: (row, col, heading) of every pose visited, the start first.
        views: the RGB observation at each of those poses (uint8 H x W x 3).
    """
    out_stem = Path(out_stem)
    graph = world.graph
    goal_ids = [graph.pose_id(*g) for g in task.goals]
    start = graph.pose_id(*task.start)
    path, pose = [task.start], start
    for action in graph.shortest_path(start, goal_ids):
        pose = int(graph.next_pose[pose, action])
        path.append(graph.pose_of(pose))
    final = episode_map(world, task.start, task.goals, path, trajectory)
    with atomic_write(out_stem.with_suffix(".png"), "wb") as f:
        f.write(_encode_png(final))

    scale = VIEW / final.shape[0]
    map_w = int(round(final.shape[1] * scale))
    view_w = int(round(views[0].shape[1] * VIEW / views[0].shape[0]))
    size = (view_w + map_w, VIEW)
    fd, tmp = tempfile.mkstemp(dir=out_stem.parent, suffix=".mp4")
    os.close(fd)
    try:
        writer = cv2.VideoWriter(tmp, cv2.VideoWriter_fourcc(*"mp4v"), FPS, size)
        drawn = _base_map(
            world, task.goals, path
        )  # the map of each step is this one's trajectory so far, and the agent
        for step in range(len(trajectory)):
            frame = np.zeros((VIEW, size[0], 3), np.uint8)
            frame[:, :view_w] = cv2.resize(
                np.ascontiguousarray(views[step][:, :, ::-1]), (view_w, VIEW), interpolation=cv2.INTER_NEAREST
            )
            if step:
                _draw_move(drawn, trajectory[step - 1], trajectory[step])
            step_map = drawn.copy()
            _draw_agent(step_map, task.start, trajectory[step])
            frame[:, view_w:] = cv2.resize(step_map, (map_w, VIEW), interpolation=cv2.INTER_AREA)
            writer.write(frame)
        writer.release()
        os.replace(tmp, out_stem.with_suffix(".mp4"))
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
