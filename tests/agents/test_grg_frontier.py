"""``grg_frontier``: a frontier beside what relates to the target is preferred, weight 0 plays
exactly as ``frontier``, records do not depend on the batch, a suite without a GRG is refused."""

from dataclasses import replace

import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.eval.agent import AgentTask
from objsearch.eval.episode import run_episode
from objsearch.eval.suites.house import HouseSuite
from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.sim.camera import AGENT_CAMERA
from objsearch_agents.baselines.frontier import RADIUS, FrontierAgent, project
from objsearch_agents.baselines.grg_frontier import GRGFrontierAgent, GRGSlotState, grg_file, relation_table
from objsearch_agents.core.grg import GoalsRelationalGraph
from objsearch_agents.house.world import NUM_NODES

BED, TOILET, PILLOW, NIGHTSTAND = (CATEGORY_IDS[n] for n in ("bed", "toilet", "pillow", "nightstand"))


def _grg() -> GoalsRelationalGraph:
    """Chasing a bed shows a pillow at once, chasing a pillow a nightstand; chasing a toilet
    shows nothing: bed -> nightstand has no edge of its own, only a plan through the pillow."""
    grg = GoalsRelationalGraph(NUM_NODES, max_option_steps=10, observable=NUM_NODES - 1)
    for source, seen in ((BED, PILLOW), (PILLOW, NIGHTSTAND)):
        grg.add_counts(source - FIRST_OBJECT_ID, seen - FIRST_OBJECT_ID, 0, count=50)
    grg.add_counts(TOILET - FIRST_OBJECT_ID, NIGHTSTAND - FIRST_OBJECT_ID, 10, count=50)  # never seen
    return grg


def _task(goal: int) -> AgentTask:
    return AgentTask(
        suite="t", split="t", episode_id=0, goal=goal, goal_name="t", observation_space=None, action_space=None,
        rng=np.random.default_rng(0), camera=AGENT_CAMERA.intrinsics(),
    )  # fmt: skip


def test_a_frontier_beside_a_related_category_costs_less_than_an_equally_near_unrelated_one():
    table = relation_table(_grg(), "plan")
    # C(bed -> nightstand): the plan through the pillow
    assert table[NIGHTSTAND, BED] == pytest.approx(table[NIGHTSTAND, PILLOW] * table[PILLOW, BED])
    assert table[NIGHTSTAND, BED] > 0.5 and table[NIGHTSTAND, TOILET] == 0.0
    assert relation_table(_grg(), "edge")[NIGHTSTAND, BED] == 0.0  # no direct edge
    # one frame, looking along x from the map's centre: a bed 2 m ahead on the left, a toilet on the right
    camera = _task(0).camera
    depth = np.full((1, camera["height"], camera["width"]), 2.0, np.float32)
    semantic = np.full((camera["height"], camera["width"]), CATEGORY_IDS["wall"])
    semantic[20:40, :24], semantic[20:40, 40:] = BED, TOILET
    points = {k: v[0] for k, v in project(depth, np.zeros((1, 3)), camera).items()}
    here = np.array([RADIUS, RADIUS])
    left, right = here + [6, 6], here + [6, -6]  # each 0.5 m from the nearest cell of one object
    costs = {}
    for weight in (0.0, 10.0):
        config = replace(GRGFrontierAgent.config, relation_weight=weight, relation_radius=1.0)
        state = GRGSlotState(_task(NIGHTSTAND), config, table[NIGHTSTAND])
        state.update_map(here, 0, points, semantic)
        costs[weight] = state.frontier_cost(np.stack([left, right]), np.array([10.0, 10.0]))
    assert list(costs[0.0]) == [10.0, 10.0]
    assert costs[10.0][0] == pytest.approx(10.0 - 10.0 * table[NIGHTSTAND, BED]) and costs[10.0][1] == 10.0


def test_with_no_relation_weight_it_plays_exactly_as_frontier(cache_dir):
    class NoRelation(GRGFrontierAgent):
        config = replace(GRGFrontierAgent.config, relation_weight=0.0)

    suite = HouseSuite("house-single", cache_dir=cache_dir, max_steps=120)
    env = suite.make_env()
    for episode in suite.episodes("unseen-goals")[:6]:
        agents = FrontierAgent(), NoRelation.for_suite("house-single")
        records = [run_episode(agent, env, suite.name, "unseen-goals", episode, 1) for agent in agents]
        assert records[0] == records[1] and "error" not in records[0]


def test_a_suite_without_a_grg_is_refused_naming_the_fix(monkeypatch, tmp_path):
    import objsearch_agents.house.agent as house_agent

    assert grg_file("house-gen-v2-shuffled").parent.parts[-2:] == ("house-gen-v2", "hrl_grg_explorer")
    monkeypatch.setattr(house_agent, "generalisation_checkpoint", lambda suite, name: (None, "house-gen-9"))
    with pytest.raises(UserError, match="no GRG is shipped for suite mine.json .*--checkpoint"):
        grg_file("mine.json")
    with pytest.raises(UserError, match="--checkpoint"):
        grg_file("mine.json", tmp_path / "missing.npz")
