"""The large-house tier's suite files (version 1's three, version 2's six) and the size sweep's
eight: the same houses, starts and targets under each tier's placements, and starts that are far
from the target in every one (checked against the houses regenerated from their seeds, not
against the file's own numbers); goal poses found without a cache are the cache's."""

import tempfile
from dataclasses import replace

import numpy as np
import pytest

from objsearch.house.gen3.build import MAX_TARGET_INSTANCES, SMALL_TARGETS
from objsearch.house.gen4.floorplan import FAMILIES
from objsearch.house.generate import generate_house
from objsearch.sim.large_suite import (
    LARGE_TARGETS,
    LARGE_V2,
    PLACEMENTS,
    RULE,
    SWEEP,
    SWEEP_TARGETS,
    TIERS,
    house_ref,
    room_hops,
)
from objsearch.sim.suite_record import _goal_ids, _near_goal_ids
from objsearch.sim.suites import load_suite_file
from objsearch.sim.world import HouseRef, World

SUITES = {name: load_suite_file(name) for name in TIERS}


def test_the_three_suites_play_the_same_episodes_in_the_same_houses():
    base = SUITES["house-large"]
    assert base["protocol"] == "objectnav" and base["max_steps"] == 500
    assert base["goal_rule"]["kind"] == "near_visible" and base["goal_rule"]["min_pixels"] == 5
    assert set(base["categories"]["targets"]) <= set(SMALL_TARGETS)
    assert len(base["training_houses"]) == 60 and len(base["houses"]) == 15
    assert {k: len(v) for k, v in base["splits"].items()} == {"val": 100, "test": 200} and base["seeds"] == [1]
    for name, placement in PLACEMENTS.items():
        suite = SUITES[name]
        assert suite["houses"].keys() == base["houses"].keys()
        for house, info in suite["houses"].items():
            assert info["seed"] == base["houses"][house]["seed"] and info["generator"] == "house-gen-3"
            assert info.get("placement", "functional") == placement
        for split, episodes in suite["splits"].items():
            same = [(e["house"], e["start"], e["target"]) for e in episodes]
            assert same == [(e["house"], e["start"], e["target"]) for e in base["splits"][split]]
    # the objects moved: the goal poses of a target differ between placements
    house = next(iter(base["goals"]))
    target = next(iter(base["goals"][house]))
    assert SUITES["house-large-shuffled"]["goals"][house].get(target) != base["goals"][house][target]


@pytest.mark.parametrize("rooms", list(SWEEP))
def test_the_sweep_plays_one_house_size_the_same_targets_and_episodes_functional_and_shuffled(rooms):
    functional, shuffled = (SUITES[name] for name in SWEEP[rooms].names)
    assert functional["protocol"] == "objectnav" and functional["max_steps"] == 500 and functional["seeds"] == [1]
    assert set(functional["categories"]["targets"]) == set(SWEEP_TARGETS)  # every size: the same targets
    assert functional["training_houses"] == {} and list(functional["splits"]) == ["test"]
    assert functional["houses"].keys() == shuffled["houses"].keys() and len(functional["houses"]) == 8
    for house, info in functional["houses"].items():
        assert info["size_class"] == f"rooms-{rooms}" and "placement" not in info
        assert shuffled["houses"][house]["placement"] == "shuffled"
        assert shuffled["houses"][house]["seed"] == info["seed"]
    house = next(iter(functional["houses"]))
    assert len(World.load(HouseRef(**functional["houses"][house])).spec.rooms) == rooms
    same = [
        [(e["house"], e["start"], e["target"]) for e in suite["splits"]["test"]] for suite in (functional, shuffled)
    ]
    assert same[0] == same[1] and len(same[0]) == 150


def test_version_2_has_enough_houses_and_the_same_episodes_in_its_six_placements():
    base = SUITES["house-large-v2"]
    assert base["protocol"] == "objectnav" and base["max_steps"] == 500 and base["seeds"] == [1]
    assert base["goal_rule"] == SUITES["house-large"]["goal_rule"]  # the tier's rule for small targets
    assert set(base["categories"]["targets"]) <= set(LARGE_TARGETS)
    assert len(base["training_houses"]) == 100 and len(base["houses"]) == 60
    assert {k: len(v) for k, v in base["splits"].items()} == {"val": 200, "test": 500}
    plans = (
        generate_house(i["seed"], i["size_class"], i["split"], False, i["generator"]) for i in base["houses"].values()
    )
    assert {house.spec.extra["floorplan"] for house in plans} == set(FAMILIES)  # every family is evaluated
    for name, placement in LARGE_V2.placements.items():
        suite = SUITES[name]
        assert suite["houses"].keys() == base["houses"].keys()
        assert suite["training_houses"].keys() == base["training_houses"].keys()
        for house, info in suite["houses"].items():
            assert info["seed"] == base["houses"][house]["seed"] and info["generator"] == "house-gen-4"
            assert info.get("placement", "functional") == placement
        for split, episodes in suite["splits"].items():
            same = [(e["house"], e["start"], e["target"]) for e in episodes]
            assert same == [(e["house"], e["start"], e["target"]) for e in base["splits"][split]]


def test_every_house_of_version_2_plays_episodes():
    # min_targets: a house joins only if the start rule leaves it starts for 2+ targets in every placement
    base = SUITES["house-large-v2"]
    for split, count in (("val", 10), ("test", 50)):
        assert len({e["house"] for e in base["splits"][split]}) == count


@pytest.mark.parametrize("placement", ["functional", "anywhere-50"])
def test_goal_poses_found_without_a_cache_are_the_caches(placement):
    world = World.load(house_ref(replace(LARGE_V2, size_class="rooms-6"), 5, "test", placement))  # small: fast
    with tempfile.TemporaryDirectory() as tmp:
        cached = _goal_ids(world, SMALL_TARGETS, tmp, RULE)
    near = _near_goal_ids(world, SMALL_TARGETS, RULE)
    assert near.keys() == cached.keys() and len(cached) >= 4
    assert all(np.array_equal(near[t], cached[t]) for t in cached)


@pytest.mark.parametrize(
    "name", [*PLACEMENTS, SWEEP[4].names[1], SWEEP[14].names[0], "house-large-v2", "house-large-v2-p50"]
)
def test_starts_are_far_from_the_target_in_walking_and_in_rooms(name):
    suite, tier = SUITES[name], TIERS[name]
    houses = sorted(suite["houses"])[:2]
    for house in houses:
        world = World.load(HouseRef(**suite["houses"][house]))
        graph, spec = world.graph, world.spec
        hops = room_hops(spec)
        for episode in (e for e in suite["splits"]["test"] if e["house"] == house):
            target = episode["target"]
            holders = [o.room for o in spec.objects if o.category == target]
            assert 1 <= len(holders) <= MAX_TARGET_INSTANCES
            goals = [graph.pose_id(*g) for g in suite["goals"][house][target]]
            start = graph.pose_id(*episode["start"])
            assert episode["min_steps"] == int(graph.shortest_steps(goals)[start]) + 1  # the STOP
            metres = graph.geodesic_distance(start, goals)
            assert metres >= tier.min_geodesic and np.isclose(metres, episode["geodesic"])
            room = int(world.cell_rooms[start // 4])
            assert room >= 0 and all(hops[room, h] >= tier.min_room_hops for h in holders)


def test_version_2_renders_live_unless_told_and_the_others_from_caches():
    from objsearch.eval.suites.house import HouseSuite

    assert HouseSuite("house-large-v2-p50").config()["mode"] == "live"  # its caches would take tens of GB
    assert HouseSuite("house-large-v2", mode="cached").mode == "cached"
    assert HouseSuite("house-large").mode == "cached"
