"""``placement="shuffled"``: the functional house of the seed with its objects moved anywhere,
valid, reproducible; the functional houses unchanged."""

import json
import os
import subprocess
import sys
from collections import Counter

import pytest

from objsearch.errors import UserError
from objsearch.house import generate
from objsearch.house.categories import category
from objsearch.house.generate import HouseGenerationError, generate_house
from objsearch.house.mjcf import compile_house
from objsearch.house.stages import StageFailure
from objsearch.house.validate import validate_house

HOUSES = [(0, "house-gen-1"), (1, "house-gen-1"), (0, "house-gen-2"), (1, "house-gen-2")]


def _identity(spec) -> dict:
    """What shuffling keeps: the house without its objects' places."""
    data = spec.to_json()
    objects = data.pop("objects")
    data.pop("extra")
    data["objects"] = [(o["category"], o["instance"], o["variant"], o["size"], o["rgba"]) for o in objects]
    return data


@pytest.mark.parametrize("seed, generator", HOUSES)
def test_shuffled_house_is_the_functional_house_with_its_objects_moved_and_valid(seed, generator):
    functional = generate_house(seed, "small", generator=generator).spec
    house = generate_house(seed, "small", generator=generator, placement="shuffled")
    shuffled = house.spec
    assert functional.placement == "functional" and functional.extra == {}
    assert shuffled.placement == "shuffled" and json.loads(shuffled.to_json_text())["extra"] == {
        "placement": "shuffled"
    }
    # floorplan, rooms, doors, walls, materials, categories, counts, variants, sizes, colours: the same
    assert _identity(shuffled) == _identity(functional)
    moved = [(a.room, a.position) != (b.room, b.position) for a, b in zip(functional.objects, shuffled.objects)]
    assert sum(moved) > 0.8 * len(moved)
    assert all(o.group is None for o in shuffled.objects)
    # the same validation as a functional house: no collisions, every room and object reachable and visible
    assert validate_house(shuffled, compile_house(shuffled)[0]).ok
    # same seed, same house
    again = generate_house(seed, "small", generator=generator, placement="shuffled").spec
    assert again.to_json_text() == shuffled.to_json_text()
    # as suites regenerate their houses (validate=False): the shuffle of that functional house, validated
    unchecked = generate_house(seed, "small", validate=False, generator=generator, placement="shuffled")
    assert _identity(unchecked.spec) == _identity(
        generate_house(seed, "small", validate=False, generator=generator).spec
    )
    assert validate_house(unchecked.spec, unchecked.model).ok


def test_shuffled_houses_break_the_room_priors():
    """Over a few houses, objects stand in rooms their category's prior excludes (none does in the
    functional houses, groups aside)."""
    out_of_place = Counter()
    for seed, generator in HOUSES:
        for placement in ("functional", "shuffled"):
            spec = generate_house(seed, "small", generator=generator, placement=placement).spec
            types = {r.id: r.type for r in spec.rooms}
            for o in spec.objects:
                prior = category(o.category).rooms
                if prior and o.group is None and types[o.room] not in prior:
                    out_of_place[placement] += 1
    assert out_of_place["functional"] == 0 and out_of_place["shuffled"] >= 5, out_of_place


def test_unknown_placement_and_a_house_that_cannot_be_shuffled(monkeypatch):
    with pytest.raises(UserError, match="unknown placement 'random'; use one of functional, shuffled"):
        generate_house(0, placement="random")

    def no_room(spec, rng, placement):
        raise StageFailure("no place for bed_0 in the house")

    monkeypatch.setattr(generate, "shuffle_house", no_room)
    with pytest.raises(
        HouseGenerationError, match=r"placement shuffled\): no valid shuffle in \d+ tries; use another seed"
    ):
        generate_house(0, "small", placement="shuffled")


CMD = [sys.executable, "-m", "objsearch.cli", "generate"]
ENV = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}


def test_cli_placement(tmp_path):
    r = subprocess.run(
        CMD + ["--out", str(tmp_path), "--rooms", "small", "--placement", "shuffled", "--no-preview", "--quiet"],
        capture_output=True,
        text=True,
        env=ENV,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "train_000000" / "spec.json").read_text())["extra"] == {"placement": "shuffled"}
    r = subprocess.run(
        CMD + ["--out", str(tmp_path), "--placement", "bogus"], capture_output=True, text=True, env=ENV, timeout=60
    )
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "--placement" in r.stderr and "'functional', 'shuffled'" in r.stderr, r.stderr
