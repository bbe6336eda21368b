"""``--video`` maps explain themselves: the target, the step count and the outcome in the
title, a legend of the marks, the target's objects outlined; the MP4 has a frame a step."""

import json
import os
from pathlib import Path

import cv2
import numpy as np
import pytest

from objsearch.house.plan_canvas import HIGHLIGHT, TITLE_H, plan_layout
from objsearch.house.spec import HouseSpec
from objsearch.sim.env import HouseTask
from objsearch.sim.video import episode_map, map_legend, map_title, write_episode
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


def test_write_episode_writes_the_map_and_a_frame_a_step(world, tmp_path):
    trajectory = _walk(world, 6)
    task = HouseTask(house=world.spec.house_id, start=trajectory[0], target="bed", goals=(trajectory[-1],), min_steps=4)
    views = [np.full((64, 64, 3), 10 * i, np.uint8) for i in range(len(trajectory))]
    write_episode(tmp_path / "ep", world, task, trajectory, views, success=True)
    png = cv2.imread(str(tmp_path / "ep.png"))
    assert png is not None and png.shape[0] > TITLE_H
    video = cv2.VideoCapture(str(tmp_path / "ep.mp4"))
    assert int(video.get(cv2.CAP_PROP_FRAME_COUNT)) == len(trajectory)
    mask = os.umask(0)
    os.umask(mask)
    assert (tmp_path / "ep.mp4").stat().st_mode & 0o777 == 0o666 & ~mask  # as any other file, not mkstemp's 0600
