import numpy as np
import pytest

from objsearch.sim.goals import GoalRule, goal_poses


def frames(areas, category=9, size=8):
    semantic = np.zeros((len(areas), size, size), np.uint8)
    for i, a in enumerate(areas):
        semantic[i].flat[:a] = category
    return semantic, np.full(semantic.shape, 2.0, np.float32)


def test_top_area_takes_the_five_largest_with_ties():
    semantic, depth = frames([0, 3, 9, 9, 4, 1, 7, 4, 2])
    # sorted areas 9, 9, 7, 4, 4, 3, ...: the 5th largest is 4, ties included
    assert goal_poses(semantic, depth, 9).tolist() == [2, 3, 4, 6, 7]


def test_top_area_never_picks_poses_that_do_not_see_the_target():
    semantic, depth = frames([0, 0, 5, 0])
    assert goal_poses(semantic, depth, 9).tolist() == [2]
    assert goal_poses(semantic, depth, 10).tolist() == []


def test_near_visible_counts_close_pixels_only():
    semantic, depth = frames([30, 30, 10])
    depth[1] = 1.5  # pose 1 sees the target, but too far away
    rule = GoalRule(kind="near_visible", min_pixels=20, max_distance=1.0)
    depth[0] = 0.8
    depth[2] = 0.8
    assert goal_poses(semantic, depth, 9, rule).tolist() == [0]


def test_unknown_rule_is_rejected():
    with pytest.raises(ValueError, match="goal rule"):
        GoalRule(kind="closest")
