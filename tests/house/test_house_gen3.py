"""``house-gen-3``: large houses (9-14 rooms, a corridor, repeated room types, rare small
targets), a size knob from 4 to 14 rooms, and the placement dial (functional, roomwise,
shuffled) over the same floorplans and objects; ``house-gen-2``'s houses unchanged."""

import hashlib
import json
import subprocess
import sys
from collections import Counter
from dataclasses import replace

import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.house.categories import category
from objsearch.house.gen2.build import build_spec as gen2_build_spec
from objsearch.house.gen3.build import MAX_TARGET_INSTANCES, SMALL_TARGETS
from objsearch.house.gen3.rules import check_rules
from objsearch.house.generate import generate_house
from objsearch.house.rooms import build_room_spec
from objsearch.house.shuffle import shuffle_house
from objsearch.house.spec import HouseSpec

GEN3 = "house-gen-3"


def _sha(spec: HouseSpec) -> str:
    return hashlib.sha256(spec.to_json_text().encode()).hexdigest()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_default_houses_are_large_valid_and_repeat_room_types(seed):
    house = generate_house(seed, generator=GEN3)
    spec = house.spec
    assert house.report.ok and spec.generator_version == GEN3 and spec.size_class == "xlarge"
    types = Counter(r.type for r in spec.rooms)
    assert 9 <= len(spec.rooms) <= 14
    assert types["hallway"] == 1 and types["bedroom"] >= 2 and types["bathroom"] >= 2 and types["office"] >= 1
    width, depth = spec.footprint
    assert 140 <= width * depth <= 300, spec.footprint
    small = Counter(o.category for o in spec.objects if o.category in SMALL_TARGETS)
    assert len(small) >= 6, small  # small targets exist ...
    assert max(small.values()) <= MAX_TARGET_INSTANCES  # ... in one place each
    assert check_rules(spec) == []
    # same seed, same bytes; the spec round-trips through JSON
    assert generate_house(seed, generator=GEN3).spec.to_json_text() == spec.to_json_text()
    assert HouseSpec.from_json(json.loads(spec.to_json_text())) == spec


@pytest.mark.parametrize("rooms", [4, 7, 10, 14])
def test_the_size_knob_gives_exactly_that_many_rooms(rooms):
    spec = generate_house(5, f"rooms-{rooms}", generator=GEN3).spec
    assert len(spec.rooms) == rooms and spec.size_class == f"rooms-{rooms}"
    assert (
        max(Counter(o.category for o in spec.objects if o.category in SMALL_TARGETS).values()) <= MAX_TARGET_INSTANCES
    )


def test_the_rule_counts_small_targets():
    spec = generate_house(0, generator=GEN3).spec
    target = next(o for o in spec.objects if o.category in SMALL_TARGETS)
    have = sum(o.category == target.category for o in spec.objects)
    extra = tuple(replace(target, instance=90 + k) for k in range(MAX_TARGET_INSTANCES))
    problems = check_rules(replace(spec, objects=spec.objects + extra))
    assert (
        f"targets: {have + MAX_TARGET_INSTANCES} {target.category} objects, more than {MAX_TARGET_INSTANCES}"
        in problems
    )


def _identity(spec) -> dict:
    """What the placement dial keeps: the house without its objects' places."""
    data = spec.to_json()
    objects = data.pop("objects")
    data.pop("extra")
    data["objects"] = [(o["category"], o["instance"], o["variant"], o["size"], o["rgba"]) for o in objects]
    return data


@pytest.mark.parametrize("seed", [0, 2])
def test_the_placement_dial_moves_the_same_objects_in_the_same_floorplan(seed):
    functional = generate_house(seed, generator=GEN3).spec
    roomwise = generate_house(seed, generator=GEN3, placement="roomwise").spec
    shuffled = generate_house(seed, generator=GEN3, placement="shuffled").spec
    assert (functional.placement, roomwise.placement, shuffled.placement) == ("functional", "roomwise", "shuffled")
    assert _identity(roomwise) == _identity(functional) == _identity(shuffled)
    room_type = {r.id: r.type for r in functional.rooms}
    pairs = list(zip(functional.objects, roomwise.objects))
    # roomwise: every object stays in a room of its room's type ...
    assert all(room_type[a.room] == room_type[b.room] for a, b in pairs)
    # ... and most move; objects on others stand on a receptacle drawn among those of such rooms
    # (a kitchen has few: the same one is often drawn again), so many leave their functional parent
    assert sum(a.position != b.position for a, b in pairs) > 0.8 * len(pairs)
    on_top = [(a, b) for a, b in pairs if a.parent is not None]
    assert sum(a.parent != b.parent for a, b in on_top) > 0.3 * len(on_top)
    # shuffled: room types change too (room priors broken)
    changed = sum(room_type[a.room] != room_type[b.room] for a, b in zip(functional.objects, shuffled.objects))
    assert changed > 0.3 * len(pairs)
    # a roomwise small target stands on a receptacle of a room of its type, which its category allows
    for b in roomwise.objects:
        if b.parent is not None:
            parent = next(o for o in roomwise.objects if o.name == b.parent)
            assert category(parent.category).receptacle and room_type[parent.room] == room_type[b.room]
    assert generate_house(seed, generator=GEN3, placement="roomwise").spec.to_json_text() == roomwise.to_json_text()


def test_house_gen2_is_unchanged_by_the_arguments_gen3_passes():
    """``house-gen-2``'s stages take ``house-gen-3``'s limits as arguments; with their defaults they
    give the bytes they gave before (hashes taken on main b8ce317)."""
    assert _sha(gen2_build_spec(1, "medium", "train", 0)) == (
        "a6c8ded4d8c08837672bc090ce7a85fdb2aa6cda6ba0cf9b88aba45c2d62cd16"
    )
    large = gen2_build_spec(2, "large", "test", 0)
    assert _sha(large) == "a805270e586fdb9ed34f5ab16341533763bcf18d4198a2665a8baaa484f64b49"
    assert _sha(build_room_spec(0, "room", "train", 0, "kitchen")) == (
        "bc849d93523c0502a8c7793c449bc90bf48238cff2ea2674e85628b9b07668b9"
    )
    shuffled = shuffle_house(gen2_build_spec(3, "large", "train", 0), np.random.default_rng(3))
    assert _sha(shuffled) == "8f52361905eafda2e7ea3c20366d3f1cb415144af371de35446f874ec6a4012d"


def test_size_classes_belong_to_their_generator():
    with pytest.raises(UserError, match="house-gen-2 has no room size 'rooms-12'"):
        generate_house(0, "rooms-12", generator="house-gen-2")
    with pytest.raises(UserError, match="house-gen-3 has no room size 'large'"):
        generate_house(0, "large", generator=GEN3)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--rooms", "20"], "20 rooms: house-gen-3 builds 4 to 14 rooms"),
        (["--rooms", "12", "--generator", "house-gen-2"], "house-gen-2 has no size --rooms 12"),
        (["--rooms", "huge"], "use small, medium, large, xlarge or a number of rooms"),
    ],
)
def test_cli_refuses_sizes_a_generator_does_not_have(tmp_path, args, message):
    out = tmp_path / "houses"
    proc = subprocess.run(
        [sys.executable, "-m", "objsearch.cli", "generate", "--out", str(out), "--generator", GEN3, *args],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2 and message in proc.stderr, proc.stderr
    assert not out.exists()


def test_cli_writes_a_sized_roomwise_house(tmp_path):
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "objsearch.cli",
            "generate",
            "--generator",
            GEN3,
            "--rooms",
            "9",
            "--placement",
            "roomwise",
            "--seed",
            "1",
            "--no-preview",
            "--out",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    spec = HouseSpec.from_json(json.loads((tmp_path / "train_000001" / "spec.json").read_text()))
    assert len(spec.rooms) == 9 and spec.placement == "roomwise" and spec.generator_version == GEN3
