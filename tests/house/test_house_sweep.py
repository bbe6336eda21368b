"""Generator sweep: 200 seeds compile and validate; functional rules hold statistically."""

import math
from collections import Counter

import mujoco
import pytest

from objsearch.house.categories import CATEGORY_IDS, ROOM_TYPES
from objsearch.house.generate import generate_house
from objsearch.house.mjcf import geom_labels

SEEDS = range(200)


@pytest.fixture(scope="module")
def houses():
    # generate_house raises unless the house compiled and passed validate_house
    return [generate_house(seed, generator="house-gen-1") for seed in SEEDS]


def test_every_seed_compiles_and_validates(houses):
    assert len(houses) == len(SEEDS)
    for h in houses:
        assert h.report.ok, (h.spec.house_id, h.report.problems)
        assert isinstance(h.model, mujoco.MjModel)
        # one body and one mesh geom per object, named <category>_<instance>
        assert h.model.nbody == 1 + len(h.spec.objects)
        assert h.model.nmesh == len(h.spec.objects)
        names = {mujoco.mj_id2name(h.model, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(1, h.model.nbody)}
        assert names == {o.name for o in h.spec.objects}


def test_house_shapes_cover_the_issue(houses):
    sizes = Counter(h.spec.size_class for h in houses)
    assert set(sizes) == {"small", "medium", "large"}
    types = Counter(r.type for h in houses for r in h.spec.rooms)
    assert set(types) == set(ROOM_TYPES)
    for h in houses:
        w, d = h.spec.footprint
        assert 6.0 <= w <= 16.0 and 6.0 <= d <= 16.0
        assert 3 <= len(h.spec.rooms) <= 9
        assert all(door.width >= 0.9 for door in h.spec.doors)
    cats = {o.category for h in houses for o in h.spec.objects}
    assert len(cats) >= 50
    # no two houses alike
    assert len({tuple((o.category, o.position) for o in h.spec.objects) for h in houses}) == len(houses)


def test_segmentation_labels_from_geom_names(houses):
    h = houses[0]
    cats, inst = geom_labels(h.model)
    for o in h.spec.objects:
        g = mujoco.mj_name2id(h.model, mujoco.mjtObj.mjOBJ_GEOM, o.name)
        assert cats[g] == CATEGORY_IDS[o.category] and inst[g] == o.instance
    assert set(cats[h.model.geom_bodyid == 0]) <= {CATEGORY_IDS[n] for n in ("wall", "floor", "door")} | {0}
    assert (cats > 0).all()


def _room_of(h, name):
    return h.spec.room(h.spec.object(name).room).type


def test_toilets_sinks_bathtubs_in_bathrooms(houses):
    for cat in ("toilet", "bathtub", "towel"):
        rooms = [h.spec.room(o.room).type for h in houses for o in h.spec.objects if o.category == cat]
        assert rooms and sum(r == "bathroom" for r in rooms) / len(rooms) >= 0.95, cat
    beds = [h.spec.room(o.room).type for h in houses for o in h.spec.objects if o.category == "bed"]
    assert sum(r == "bedroom" for r in beds) / len(beds) >= 0.95
    fridges = [h.spec.room(o.room).type for h in houses for o in h.spec.objects if o.category == "fridge"]
    assert all(r == "kitchen" for r in fridges)


def _facing(a, b, max_deg=30.0):
    """True when a's front points at b (within max_deg)."""
    ax, ay = a.position[:2]
    bx, by = b.position[:2]
    dx, dy = bx - ax, by - ay
    n = math.hypot(dx, dy)
    fx, fy = a.front
    return n > 0 and (fx * dx + fy * dy) / n >= math.cos(math.radians(max_deg))


def test_every_tv_faces_a_sofa_in_its_room(houses):
    tvs = 0
    for h in houses:
        for tv in (o for o in h.spec.objects if o.category == "tv"):
            tvs += 1
            sofas = [o for o in h.spec.objects if o.category == "sofa" and o.room == tv.room]
            assert any(_facing(s, tv) and _facing(tv, s) for s in sofas), (h.spec.house_id, tv.name)
            assert h.spec.object(tv.parent).category == "tv_stand"
    assert tvs >= 100


def _points_at(a, b, reach=0.3):
    """True when the point just in front of a (within reach) lies inside b's footprint."""
    fx, fy = a.front
    x = a.position[0] + fx * (a.size[1] / 2 + reach)
    y = a.position[1] + fy * (a.size[1] / 2 + reach)
    x0, y0, x1, y1 = b.footprint
    return x0 <= x <= x1 and y0 <= y <= y1


def test_functional_groups(houses):
    for h in houses:
        objs = h.spec.objects
        by_group = {}
        for o in objs:
            by_group.setdefault(o.group, []).append(o)
        for o in objs:
            if o.category == "chair":  # dining chairs face their table
                table = next(t for t in by_group[o.group] if t.category == "dining_table")
                assert _points_at(o, table), (h.spec.house_id, o.name)
            if o.category == "mirror" and o.group:  # mirror above the bathroom sink
                sink = next(s for s in by_group[o.group] if s.category == "sink")
                assert (
                    abs(o.position[0] - sink.position[0]) + abs(o.position[1] - sink.position[1])
                    < sink.size[1] / 2 + 0.1
                )
                assert o.position[2] >= sink.position[2] + sink.size[2]
            if o.category == "office_chair":
                desk = next(t for t in by_group[o.group] if t.category == "desk")
                assert _points_at(o, desk)
            if o.category in ("table_lamp", "computer", "keyboard", "pillow", "tv", "kitchen_sink"):
                assert o.parent is not None and o.placement == "on_top"
        for room in h.spec.rooms:
            cats = Counter(o.category for o in objs if o.room == room.id)
            if room.type == "bathroom":
                assert cats["toilet"] >= 1 and cats["sink"] >= 1
            if room.type == "bedroom":
                assert cats["bed"] >= 1 and cats["nightstand"] >= 1
            if room.type == "kitchen":
                assert cats["fridge"] == 1 and cats["stove"] == 1 and cats["kitchen_sink"] == 1
            if room.type == "office":
                assert cats["desk"] >= 1 and cats["office_chair"] >= 1 and cats["computer"] >= 1
            if room.type == "living_room":
                assert cats["sofa"] == 1 and cats["tv"] == 1
    nightstands = [o for h in houses for o in h.spec.objects if o.category == "nightstand"]
    lamps = [o for h in houses for o in h.spec.objects if o.category == "table_lamp"]
    assert len(lamps) >= 0.6 * len(nightstands)
