"""The large-house tier's prior agents: priors counted from training houses say what a home
says (soap by the sink, an alarm clock by the bed), the close look faces the right cells, and
the privileged calibration agent marks the rooms that hold the target."""

import numpy as np
import pytest

from objsearch.eval.agent import AgentTask
from objsearch.eval.suites.house import HousePath
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.env import HouseTask, relative_pose_of
from objsearch.sim.world import HouseRef, World
from objsearch_agents.baselines.frontier import CELL, RADIUS, STEPS
from objsearch_agents.baselines.prior_frontier import ahead_of, count_priors
from objsearch_agents.baselines.room_frontier import target_room_mask


@pytest.fixture(scope="module")
def houses():
    return [World.load(HouseRef(seed=s, generator="house-gen-3", size_class="rooms-9")) for s in range(4)]


def test_counted_priors_say_where_things_are_in_a_home(houses):
    priors = count_priors(w.spec for w in houses)
    ids = CATEGORY_IDS
    room, near = priors["room"], priors["object"]
    assert room.shape == near.shape == (max(ids.values()) + 1,) * 2
    assert np.all(np.diag(room) == 0) and np.all(np.diag(near) == 0)  # the target itself counts nothing
    assert np.all((room >= 0) & (room <= 1)) and np.all((near >= 0) & (near <= 1))
    # soap: the same room as a toilet, not as a bed; beside a sink more than beside a sofa
    assert room[ids["soap"], ids["toilet"]] > max(0.3, 3 * room[ids["soap"], ids["bed"]])
    assert near[ids["soap"], ids["sink"]] > near[ids["soap"], ids["sofa"]]
    # every small object a house has stands near something it was counted with
    for w in houses:
        for o in w.spec.objects:
            if o.parent is not None and o.category != w.spec.object(o.parent).category:
                assert near[ids[o.category], ids[w.spec.object(o.parent).category]] > 0


def test_ahead_of_reads_the_cells_in_front():
    grid = np.zeros((7, 7))
    grid[3, 5] = 1.0  # two cells along +j (heading 1) from (3, 3)
    assert tuple(STEPS[1]) == (0, 1)
    assert ahead_of(grid, 1, 2)[3, 3] == 1.0 and ahead_of(grid, 1, 1)[3, 4] == 1.0
    assert ahead_of(grid, 3, 2)[3, 3] == 0.0  # behind, not ahead
    assert ahead_of(grid, 1, 2).sum() == 1.0  # nothing wraps round


def test_the_calibration_agent_marks_the_targets_rooms(houses):
    world = houses[0]
    target = next(o for o in world.spec.objects if o.category == "soap" or o.category == "cup")
    start = tuple(int(v) for v in world.graph.pose_of(0))
    task = AgentTask(
        suite="house-large",
        split="test",
        episode_id=0,
        goal=CATEGORY_IDS[target.category],
        goal_name=target.category,
        observation_space=None,
        action_space=None,
        rng=np.random.default_rng(0),
        privileged=HousePath(HouseTask(world.house_id, start, target.category, (), 0), True, world),
    )
    mask = target_room_mask(task, margin=0.0)
    rooms = {o.room for o in world.spec.objects if o.category == target.category}
    in_rooms = np.isin(world.cell_rooms, sorted(rooms))
    assert mask.sum() == in_rooms.sum()  # one map cell per free cell of those rooms
    row, col = (int(v) for v in world.graph.cells[np.flatnonzero(in_rooms)[0]])
    x, y, _ = relative_pose_of(start, (row, col, start[2]))
    assert mask[RADIUS + round(x / CELL), RADIUS + round(y / CELL)]
    elsewhere = world.graph.cells[np.flatnonzero(~in_rooms & (world.cell_rooms >= 0))[0]]
    x, y, _ = relative_pose_of(start, (int(elsewhere[0]), int(elsewhere[1]), start[2]))
    assert not mask[RADIUS + round(x / CELL), RADIUS + round(y / CELL)]
    no_truth = AgentTask(**{**task.__dict__, "privileged": None})
    with pytest.raises(ValueError, match="no house ground truth"):
        target_room_mask(no_truth, 0.5)
