"""The placement-fidelity dial (``anywhere-P``, ``roomwise-P``): a share P of the functional house's
objects moved, nested across P, the rest and the floorplan untouched, moved objects on top spread
over their receptacle's surface, valid, reproducible; ``shuffled`` and ``roomwise`` unchanged."""

import json
import os
import subprocess
import sys
from functools import cache

import numpy as np
import pytest

from objsearch.house import generate
from objsearch.house.dial import DIAL_PLACEMENTS, dial_setting, move_order, moved_count, narrow_arms
from objsearch.house.generate import DIAL_ORDER_STREAM, DIAL_STREAMS, PLACEMENT_STREAMS, generate_house
from objsearch.house.layout import surface_rect
from objsearch.house.mjcf import compile_house
from objsearch.house.shuffle import narrow_cells
from objsearch.house.spec import DIAL_FAMILIES, DIAL_SHARES, HOUSE_PLACEMENTS, Room
from objsearch.house.validate import validate_house
from objsearch.sim.suite_schema import SCHEMA
from objsearch.sim.world import spec_hash

SEEDS = (0, 1, 2)
SIZE = "rooms-7"


@cache
def house(seed: int, placement: str = "functional"):
    return generate_house(seed, SIZE, generator="house-gen-3", placement=placement).spec


def _pose(o) -> tuple:
    return (o.room, o.position, o.yaw, o.parent)


def _moved(functional, spec) -> set[str]:
    """The names of the objects whose pose (room, position, yaw, parent) differs from the functional house's."""
    return {a.name for a, b in zip(functional.objects, spec.objects) if _pose(a) != _pose(b)}


def _floorplan(spec) -> dict:
    data = spec.to_json()
    data.pop("objects"), data.pop("extra")
    return data


def test_the_dial_names_are_placements_and_their_streams_are_new():
    assert list(DIAL_PLACEMENTS) == [f"{f}-{p}" for f in DIAL_FAMILIES for p in DIAL_SHARES]
    assert HOUSE_PLACEMENTS[:3] == ("functional", "shuffled", "roomwise")
    assert set(HOUSE_PLACEMENTS[3:]) == set(DIAL_PLACEMENTS)
    assert dial_setting("roomwise-75") == ("roomwise", 75)
    with pytest.raises(ValueError, match="not 'anywhere-30'"):
        dial_setting("anywhere-30")
    # suite files may record them (the schema's enum derives from HOUSE_PLACEMENTS)
    assert "anywhere-50" in json.dumps(SCHEMA)
    streams = [DIAL_ORDER_STREAM, *DIAL_STREAMS.values()]
    assert len(set(streams)) == 3 and not set(streams) & set(PLACEMENT_STREAMS.values())
    assert [moved_count(71, p) for p in (0, 25, 50, 75, 100)] == [0, 18, 36, 53, 71]  # 17.75, 35.5, 53.25


@pytest.mark.parametrize("seed", SEEDS)
def test_the_dial_moves_its_share_nested_and_keeps_the_rest_and_the_floorplan(seed):
    functional = house(seed)
    n = len(functional.objects)
    for family in DIAL_FAMILIES:
        before: set[str] = set()
        for share in DIAL_SHARES:
            placement = f"{family}-{share}"
            spec = house(seed, placement)
            assert json.loads(spec.to_json_text())["extra"] == {"placement": placement} and spec.placement == placement
            assert _floorplan(spec) == _floorplan(functional)  # rooms, doors, walls, materials: the same at every P
            assert [o.name for o in spec.objects] == [o.name for o in functional.objects]
            moved = _moved(functional, spec)
            assert abs(len(moved) - moved_count(n, share)) <= 1, (placement, len(moved), n)
            assert before <= moved  # nested: what moved at a smaller share moves here too
            before = moved
            for a, b in zip(functional.objects, spec.objects):
                if a.name not in moved:  # what stays is the functional object, byte for byte
                    assert a == b
                else:  # what moves keeps its identity
                    assert (a.category, a.variant, a.size, a.rgba) == (b.category, b.variant, b.size, b.rgba)
            # nothing stands on an object that moved away from under it
            names = {o.name: o for o in spec.objects}
            assert all(o.parent is None or o.parent in names for o in spec.objects)
            assert all(o.name in moved for o in spec.objects if o.parent is not None and o.parent in moved)
    # both families move the same objects at a share
    for share in DIAL_SHARES:
        anywhere, roomwise = (_moved(functional, house(seed, f"{f}-{share}")) for f in DIAL_FAMILIES)
        assert len(anywhere ^ roomwise) <= 2


@pytest.mark.parametrize("seed", SEEDS)
def test_roomwise_keeps_room_types_and_anywhere_does_not(seed):
    functional = house(seed)
    types = {r.id: r.type for r in functional.rooms}
    other = 0
    for share in DIAL_SHARES:
        roomwise, anywhere = house(seed, f"roomwise-{share}"), house(seed, f"anywhere-{share}")
        for a, b, c in zip(functional.objects, roomwise.objects, anywhere.objects):
            assert types[b.room] == types[a.room]
            other += types[c.room] != types[a.room]
    assert other > 20


def _front_distances(seed: int, placement: str) -> list[tuple[float, float]]:
    """(distance from the receptacle's front edge, the surface's depth) of every moved object on top
    in ``placement``'s house of ``seed``, checking that it stands within the receptacle's top rectangle."""
    functional, spec = house(seed), house(seed, placement)
    out = []
    for o in spec.objects:
        if o.parent is None or o.name not in _moved(functional, spec):
            continue
        parent = spec.object(o.parent)
        z, x0, y0, x1, y1 = surface_rect(parent)
        fx0, fy0, fx1, fy1 = o.footprint
        assert x0 - 1e-3 <= fx0 and fx1 <= x1 + 1e-3 and y0 - 1e-3 <= fy0 and fy1 <= y1 + 1e-3, o.name
        assert o.position[2] >= z
        x, y, _ = o.position
        out.append(
            {
                (1, 0): (x1 - x, x1 - x0),
                (-1, 0): (x - x0, x1 - x0),
                (0, 1): (y1 - y, y1 - y0),
                (0, -1): (y - y0, y1 - y0),
            }[tuple(round(v) for v in parent.front)]
        )
    return out


def test_moved_objects_on_top_stand_on_a_receptacle_spread_over_its_surface():
    """Within the receptacle's top rectangle, and not near its front edge (``shuffle.FRONT_BAND``):
    over many objects their mean distance from the front edge is about half the surface's depth,
    on deep receptacles (beds, tables) too, where ``shuffled`` keeps them near the front."""
    dial = [d for s in SEEDS for p in ("anywhere-100", "roomwise-100", "anywhere-50") for d in _front_distances(s, p)]
    shuffled = [d for s in SEEDS for d in _front_distances(s, "shuffled")]
    assert len(dial) > 100
    assert 0.43 < np.mean([d / depth for d, depth in dial]) < 0.57
    deep = [d / depth for d, depth in dial if depth >= 1.0]
    assert len(deep) >= 20 and np.mean(deep) > 0.4, (len(deep), np.mean(deep))
    assert np.mean([d / depth for d, depth in shuffled if depth >= 1.0]) < 0.3  # what the dial corrects
    for seed in SEEDS:  # a moved object leaves its functional parent (anywhere; roomwise may lack another)
        functional, spec = house(seed), house(seed, "anywhere-100")
        assert all(o.parent != functional.object(o.name).parent for o in spec.objects if o.parent is not None)


def test_dial_houses_are_valid_and_reproducible():
    for placement in ("anywhere-25", "roomwise-100"):
        first = house(0, placement)
        assert validate_house(first, compile_house(first)[0]).ok
        again = generate_house(0, SIZE, generator="house-gen-3", placement=placement).spec
        assert again.to_json_text() == first.to_json_text()
    # as suites regenerate houses (validate=False): the dial of that functional house, validated
    unchecked = generate_house(1, SIZE, validate=False, generator="house-gen-3", placement="anywhere-75")
    assert validate_house(unchecked.spec, unchecked.model).ok


def test_moved_furniture_may_use_the_main_part_of_an_l_shaped_room():
    """Only an L's arm narrower than ``NARROW`` is kept free (``shuffle.narrow_cells`` also keeps the
    strip of its main part that the room's grid cuts off, where this bedroom's bed stands)."""
    bedroom = Room(4, "bedroom", ((6.8, 3.8), (9.6, 3.8), (9.6, 7.4), (4.7, 7.4), (4.7, 5.9), (6.8, 5.9)), "f", "w")
    assert narrow_cells(bedroom) == [(4.7, 5.9, 6.8, 7.4), (6.8, 5.9, 9.6, 7.4)]
    assert narrow_arms(bedroom) == [(4.7, 5.9, 6.8, 7.4)]
    assert narrow_arms(Room(0, "bedroom", ((0, 0), (3, 0), (3, 1), (0, 1)), "f", "w")) == []
    # that house-gen-2 house has no valid roomwise shuffle, but a roomwise-100 one
    spec = generate_house(0, "medium", generator="house-gen-2", placement="roomwise-100").spec
    assert spec.object("bed_0").room == 4


def test_move_order_puts_what_stands_on_an_object_before_it():
    spec = house(1)
    for draw in range(5):
        order = move_order(spec, np.random.default_rng(draw))
        assert sorted(order) == sorted(o.name for o in spec.objects)
        at = {name: i for i, name in enumerate(order)}
        assert all(at[o.name] < at[o.parent] for o in spec.objects if o.parent is not None)


def test_a_dial_house_that_cannot_be_moved_says_so(monkeypatch):
    from objsearch.house.stages import StageFailure

    def no_room(spec, moving, rng, placement):
        raise StageFailure("no place for bed_0 in the house")

    monkeypatch.setattr(generate, "dial_house", no_room)
    with pytest.raises(generate.HouseGenerationError, match=r"placement anywhere-50\): no valid shuffle in \d+ tries"):
        generate_house(0, SIZE, generator="house-gen-3", placement="anywhere-50")


@pytest.mark.parametrize(
    "suite, house_id",
    [("house-large-shuffled", "test_002000"), ("house-large-roomwise", "test_002000"), ("house-size-7-shuffled", None)],
)
def test_the_shipped_shuffled_and_roomwise_houses_are_unchanged(suite, house_id):
    from objsearch.sim.suites import load_suite_file

    houses = load_suite_file(suite)["houses"]
    info = houses[house_id or next(iter(houses))]
    spec = generate_house(
        info["seed"],
        info["size_class"],
        info["split"],
        validate=False,
        generator=info["generator"],
        placement=info["placement"],
    ).spec
    assert spec_hash(spec) == info["spec_sha256"]


def test_cli_generates_a_dial_house(tmp_path):
    cmd = [sys.executable, "-m", "objsearch.cli", "generate", "--out", str(tmp_path), "--generator", "house-gen-3"]
    r = subprocess.run(
        cmd + ["--rooms", "4", "--placement", "roomwise-25", "--no-preview", "--quiet"],
        capture_output=True,
        text=True,
        env={**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")},
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "train_000000" / "spec.json").read_text())["extra"] == {"placement": "roomwise-25"}
