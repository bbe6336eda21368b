"""frontier's STOP on the ObjectNav protocol: one frame is enough where depth is rendered (the
goal rule's own test), and on predicted perception the target must be confirmed first (from
several cells, at the same place, read as the target by the frames that saw it there)."""

import dataclasses

import numpy as np

from objsearch.eval.agent import AgentTask
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.camera import RenderSettings
from objsearch_agents.baselines.frontier import FrontierAgent, FrontierConfig

STOP, TV, TV_STAND, FLOOR, WALL = (
    6,
    CATEGORY_IDS["tv"],
    CATEGORY_IDS["tv_stand"],
    CATEGORY_IDS["floor"],
    CATEGORY_IDS["wall"],
)
CAMERA = RenderSettings(width=64, height=64).intrinsics()
RULE = {"kind": "near_visible", "min_pixels": 20, "max_distance": 1.0}


def agent_for(**config) -> FrontierAgent:
    agent = FrontierAgent()
    agent.config = dataclasses.replace(FrontierConfig(), **config)
    task = AgentTask(
        suite="t", split="t", episode_id=0, goal=TV, goal_name="tv", observation_space=None, action_space=None,
        rng=np.random.default_rng(0), camera=CAMERA, stop_action=STOP, goal_rule=RULE,
    )  # fmt: skip
    agent.reset(task)
    return agent


def frame(x: float, target_depth: float, label: int = TV, floor_error: float = 0.0) -> dict:
    """The agent at ``x`` metres ahead of its start, facing a wall 3 m off with a 10 x 8 pixel
    patch labelled ``label`` at ``target_depth`` in the middle of the view; the floor's depth is
    rendered exactly, or off by ``floor_error`` (a share: predicted depth)."""
    h, w = CAMERA["height"], CAMERA["width"]
    rows = np.arange(h)[:, None] + 0.5
    down = (rows - CAMERA["cy"]) / CAMERA["fy"]  # metres down per metre of depth
    floor = np.where(down > 0, CAMERA["camera_height"] / np.maximum(down, 1e-9), np.inf) * (1 + floor_error)
    depth = np.broadcast_to(np.minimum(floor, 3.0), (h, w)).astype(np.float32).copy()
    semantic = np.where(np.broadcast_to(floor < 3.0, (h, w)), FLOOR, WALL).astype(np.uint8)
    patch = (slice(28, 36), slice(27, 37))  # about the horizon: the same height seen from any distance
    depth[patch], semantic[patch] = target_depth, label
    return {
        "pose": np.array([x, 0.0, 0.0], np.float32),
        "depth": depth,
        "semantic": semantic,
        "target": TV,
        "collided": 0,
    }


def test_rendered_depth_stops_on_the_first_frame_that_passes_the_goal_rule():
    agent = agent_for()
    assert agent.act(frame(0.0, 0.8)) == STOP


def test_rendered_depth_does_not_stop_beyond_the_goal_rules_distance():
    agent = agent_for()
    assert agent.act(frame(0.0, 1.2)) != STOP


def test_predicted_depth_stops_only_once_a_second_cell_sees_the_same_target():
    agent = agent_for(stop_views=2, stop_margin=0.0, stop_share=0.0)
    assert agent.act(frame(0.0, 0.85, floor_error=0.05)) != STOP, "one view of a predicted target is not enough"
    assert agent.act(frame(0.0, 0.85, floor_error=0.05)) != STOP, "the same cell again is not a second view"
    assert agent.act(frame(0.25, 0.6, floor_error=0.05)) == STOP, "a cell nearer sees it at the same place"


def test_predicted_sightings_at_different_places_do_not_confirm_each_other():
    agent = agent_for(stop_views=2, stop_margin=0.0, stop_share=0.0)
    assert agent.act(frame(0.0, 0.85, floor_error=0.05)) != STOP
    assert agent.act(frame(1.0, 0.8, floor_error=0.05)) != STOP, "1 m further on: another thing, not a second view"


def test_the_margin_asks_predicted_depth_to_be_nearer_than_the_goal_rule():
    agent = agent_for(stop_views=1, stop_margin=0.15, stop_share=0.0)
    assert agent.act(frame(0.0, 0.9, floor_error=0.05)) != STOP
    assert agent.act(frame(0.0, 0.8, floor_error=0.05)) == STOP


def test_a_place_other_frames_read_as_another_object_is_not_confirmed():
    config = dict(stop_views=2, stop_margin=0.0, stop_share=0.6)
    agent = agent_for(**config)
    for _ in range(5):  # seen as a tv stand from 1.35 m
        assert agent.act(frame(-0.5, 1.35, label=TV_STAND, floor_error=0.05)) != STOP
    agent.act(frame(0.0, 0.85, floor_error=0.05))
    assert agent.act(frame(0.25, 0.6, floor_error=0.05)) != STOP, "most of its labels were tv_stand"
    agent = agent_for(**config)
    agent.act(frame(0.0, 0.85, floor_error=0.05))
    assert agent.act(frame(0.25, 0.6, floor_error=0.05)) == STOP, "the same views without the tv_stand labels"


def test_the_shipped_agent_earns_its_stop_on_predicted_depth_and_not_on_rendered_depth():
    agent = agent_for()  # the defaults, as the leaderboard runs them
    assert agent.act(frame(0.0, 0.8, floor_error=0.05)) != STOP, "one predicted view is not enough"
    assert agent.act(frame(0.25, 0.55, floor_error=0.05)) == STOP, "a second cell confirms it"
    assert agent_for().act(frame(0.0, 0.95)) == STOP, "rendered depth: the goal rule's own test, no margin"
