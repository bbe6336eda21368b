"""``--video`` maps explain themselves: the target, the step count and the outcome in the
title, a legend of the marks, the target's objects outlined; the MP4 has a frame a step."""

import json
import os
from pathlib import Path

import cv2
import numpy as np
import pytest

from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.house.plan_canvas import HIGHLIGHT, ROW_H, TITLE_H, plan_layout
from objsearch.house.plan_legend import legend_size
from objsearch.house.spec import HouseSpec
from objsearch.sim.env import HouseTask
from objsearch.sim.video import (
    PANEL_H,
    VIEW,
    episode_map,
    in_view_legend,
    label_colors,
    map_legend,
    map_title,
    write_episode,
)
from objsearch.sim.world import World

GOLDEN = Path(__file__).parents[1] / "house" / "golden" / "spec_000000.json"


@pytest.fixture(scope="module")
def world() -> World:
    return World(HouseSpec.from_json(json.loads(GOLDEN.read_text())))


def _walk(world: World, steps: int) -> list[tuple[int, int, int]]:
    """A deterministic walk of ``steps`` moves ahead / turns on the house's pose graph."""
    graph = world.graph
    pose = graph.num_poses // 2
    poses = [graph.pose_of(pose)]
    for i in range(steps):
        pose = int(graph.next_pose[pose, 0 if i % 5 else 1])
        poses.append(graph.pose_of(pose))
    return poses


def test_title_names_the_target_the_steps_and_the_outcome():
    assert map_title("coffee_table", 1000, False, 41) == "target: coffee table - not found in 1000 steps (shortest 41)"
    assert map_title("plant", 159, True, 33) == "target: plant - found in 159 steps (shortest 33)"
    assert map_title("bed", 12) == "target: bed - 12 steps"
    assert map_title("bed", 1, True) == "target: bed - found in 1 step"


def test_legend_lists_every_mark_of_the_map():
    labels = [label for label, _ in map_legend("toilet_paper")]
    assert labels[:5] == ["path taken", "a shortest path", "goal poses", "start", "end (heading)"]
    assert "toilet paper (target)" in labels


def test_map_titles_differ_by_target_and_outline_the_targets_objects(world):
    spec = world.spec
    trajectory = _walk(world, 12)
    goals = [trajectory[-1]]
    target = next(o.category for o in spec.objects if o.placement not in ("on_top", "on_wall"))
    a = episode_map(world, trajectory[0], goals, trajectory, trajectory, target, True, 12)
    b = episode_map(world, trajectory[0], goals, trajectory, trajectory, "__none__", True, 12)
    c = episode_map(world, trajectory[0], goals, trajectory, trajectory, target, False, 12)
    assert a.shape == b.shape == c.shape
    assert np.any(a[:TITLE_H] != c[:TITLE_H]), "the outcome is not in the title"
    assert np.any(a[:TITLE_H] != b[:TITLE_H]), "the target is not in the title"
    magenta = np.all(a == HIGHLIGHT, axis=2)
    layout = plan_layout(spec, top=TITLE_H)
    for o in spec.objects:
        if o.category == target:
            x0, y0, x1, y1 = o.footprint
            (c0, r0), (c1, r1) = layout.pixel(x0 - 0.1, y1 + 0.1), layout.pixel(x1 + 0.1, y0 - 0.1)
            assert magenta[r0:r1, c0:c1].sum() > 10, f"{o.name} is not outlined"
    assert np.array_equal(a, episode_map(world, trajectory[0], goals, trajectory, trajectory, target, True, 12))


def _observations(n: int, target: str) -> list[dict]:
    """``n`` observations of 64 x 64: an RGB grey ramp over time, depth rising left to right
    (0-6 m), labels of a wall, the floor, a bed and the target in a block in the middle."""
    depth = np.tile(np.linspace(0.0, 6.0, 64, dtype=np.float32), (64, 1))
    semantic = np.full((64, 64), CATEGORY_IDS["wall"], np.uint8)
    semantic[40:] = CATEGORY_IDS["floor"]
    semantic[44:60, 2:20] = CATEGORY_IDS["bed"]
    semantic[24:40, 24:40] = CATEGORY_IDS[target]
    return [{"rgb": np.full((64, 64, 3), 10 * i, np.uint8), "depth": depth, "semantic": semantic} for i in range(n)]


def test_write_episode_films_rgb_depth_and_labels_at_10_fps(world, tmp_path):
    trajectory = _walk(world, 6)
    task = HouseTask(house=world.spec.house_id, start=trajectory[0], target="cup", goals=(trajectory[-1],), min_steps=4)
    write_episode(tmp_path / "ep", world, task, trajectory, _observations(len(trajectory), "cup"), success=True)
    png = cv2.imread(str(tmp_path / "ep.png"))
    assert png is not None and png.shape[0] > TITLE_H
    video = cv2.VideoCapture(str(tmp_path / "ep.mp4"))
    assert int(video.get(cv2.CAP_PROP_FRAME_COUNT)) == len(trajectory)
    assert video.get(cv2.CAP_PROP_FPS) >= 10
    ok, frame = video.read()
    assert ok and frame.shape[0] == VIEW + PANEL_H and frame.shape[1] > 3 * VIEW  # three views, then the map
    depth_view, labels_view = frame[:VIEW, VIEW : 2 * VIEW].astype(int), frame[:VIEW, 2 * VIEW : 3 * VIEW].astype(int)
    near, far = depth_view[VIEW // 2, 20], depth_view[VIEW // 2, VIEW - 20]
    assert np.abs(near - far).sum() > 100, "the depth view does not show depth"
    centre = labels_view[VIEW // 2 - 10 : VIEW // 2 + 10, VIEW // 2 - 10 : VIEW // 2 + 10].reshape(-1, 3).mean(axis=0)
    assert np.abs(centre - np.array(HIGHLIGHT)).max() < 40, "the target is not magenta in the labels view"
    mask = os.umask(0)
    os.umask(mask)
    assert (tmp_path / "ep.mp4").stat().st_mode & 0o777 == 0o666 & ~mask  # as any other file, not mkstemp's 0600


def test_the_legends_fit_the_panel_with_the_target_first():
    width = 3 * VIEW - 8
    assert legend_size(map_legend("toilet_paper"), width)[0] <= width  # no label cut off
    lut = label_colors("cup")
    semantic = np.repeat(np.arange(FIRST_OBJECT_ID, FIRST_OBJECT_ID + 40, dtype=np.uint8), 10)  # 40 categories in view
    semantic[:3] = CATEGORY_IDS["cup"]  # the target, though it has the fewest pixels
    entries = in_view_legend(semantic, lut, "cup", width, rows=2)
    assert entries[0][0] == "cup" and 2 < len(entries) < 40
    assert legend_size(entries, width)[1] <= 2 * ROW_H
    assert tuple(lut[CATEGORY_IDS["cup"]]) == HIGHLIGHT and tuple(lut[CATEGORY_IDS["wall"]]) != HIGHLIGHT
