"""``house-gen-4``: houses in floorplan families (bar, bar2, L, U, T), whose outline is not
always a rectangle and whose hallways are not always one; walls close along the outline, the
agent never stands outside the rooms, and ``house-gen-3``'s rules and size knob still hold."""

import json
from collections import Counter
from dataclasses import replace

import numpy as np
import pytest

from objsearch.house.floorplan_stats import describe, shares
from objsearch.house.gen3.build import MAX_TARGET_INSTANCES, SMALL_TARGETS
from objsearch.house.gen4.floorplan import FAMILIES
from objsearch.house.gen4.rules import check_rules, footprint_problems
from objsearch.house.generate import generate_house
from objsearch.house.occupancy import occupancy_grid
from objsearch.house.spec import HouseSpec, Room

GEN4 = "house-gen-4"
SEEDS = range(24)


@pytest.fixture(scope="module")
def houses():
    return {seed: generate_house(seed, generator=GEN4) for seed in SEEDS}


def test_houses_are_valid_large_and_reproducible(houses):
    for seed in (0, 1):
        spec = houses[seed].spec
        assert houses[seed].report.ok and spec.generator_version == GEN4 and spec.size_class == "xlarge"
        assert 9 <= len(spec.rooms) <= 14 and check_rules(spec) == []
        small = Counter(o.category for o in spec.objects if o.category in SMALL_TARGETS)
        assert len(small) >= 6 and max(small.values()) <= MAX_TARGET_INSTANCES
        assert generate_house(seed, generator=GEN4).spec.to_json_text() == spec.to_json_text()
        assert HouseSpec.from_json(json.loads(spec.to_json_text())) == spec


def test_layouts_vary_across_seeds(houses):
    got = shares(h.spec for h in houses.values())
    assert set(got["family"]) == set(FAMILIES), got["family"]  # every family comes out
    assert max(got["family"].values()) <= 0.5
    # 24 seeds: loose bounds (100 seeds, the figures of docs/houses.md: benchmarks/floorplan_families.py)
    assert 0.1 <= got["not_rectangular"] <= 0.9 and got["not_one_straight_hallway"] >= 0.2, got
    for h in houses.values():  # the recorded family is the plan's: one hallway a corridor wing at most
        d = describe(h.spec)
        assert d["hallways"] <= len(FAMILIES[d["family"]])
        assert d["footprint"] == "rectangle" or d["family"] != "bar"


def test_walls_close_along_an_outline_that_is_not_a_rectangle(houses):
    spec = next(h.spec for h in houses.values() if describe(h.spec)["footprint"] != "rectangle")
    grid = occupancy_grid(spec)
    ys, xs = (np.argwhere(grid.free) + 0.5).T * grid.resolution
    for x, y in zip(xs[::97], ys[::97]):  # every free cell lies in a room
        assert any(r.contains(float(x), float(y)) for r in spec.rooms), (x, y)
    width, depth = spec.footprint
    outside = sum(r.area for r in spec.rooms) < 0.99 * width * depth
    assert outside
    # the outer skin (room -1) covers the outline: its length is at least the outline's perimeter
    skin = sum(max(w.box[2] - w.box[0], w.box[3] - w.box[1]) for w in spec.walls if w.room == -1)
    doors_out = sum(d.width for d in spec.doors if -1 in d.rooms)
    perimeter = _perimeter(spec)
    assert skin + doors_out >= perimeter - 1e-6, (skin, perimeter)


def _perimeter(spec: HouseSpec) -> float:
    """The outline's length: room edges that no other room shares."""
    from objsearch.house.gen2.doors import edges, shared_segments

    total = sum(hi - lo for r in spec.rooms for _, _, lo, hi, _ in edges(r.polygon))
    shared = sum(
        b - a
        for i, r in enumerate(spec.rooms)
        for q in spec.rooms[i + 1 :]
        for _, _, a, b in shared_segments(r.polygon, q.polygon)
    )
    return total - 2 * shared


def test_the_footprint_rule_catches_overlapping_rooms(houses):
    spec = houses[0].spec
    r = spec.rooms[0]
    moved = Room(len(spec.rooms), "bedroom", r.polygon, r.floor_material, r.wall_material)
    bad = replace(spec, rooms=(*spec.rooms, moved))
    assert any("overlap" in p for p in footprint_problems(bad))


@pytest.mark.parametrize("rooms", [4, 7, 10, 14])
def test_the_size_knob_gives_exactly_that_many_rooms(rooms):
    spec = generate_house(5, f"rooms-{rooms}", generator=GEN4).spec
    assert len(spec.rooms) == rooms and spec.size_class == f"rooms-{rooms}"
    assert check_rules(spec) == []
