"""Single functional rooms (``objsearch.house.rooms``, ``objsearch generate --room TYPE``)."""

import json
import math
import os
import subprocess
import sys
from dataclasses import replace

import pytest

from objsearch.errors import UserError
from objsearch.house.gen2.floorplan import AREA_LIMITS
from objsearch.house.gen2.furnish import FILL_DENSITY
from objsearch.house.generate import generate_house
from objsearch.house.rooms import ROOM_SIZE_CLASS, ROOM_TYPES, check_rules
from objsearch.house.spec import Door, HouseSpec
from objsearch.house.validate import validate_house
from objsearch.sim.suites import load_suite_file
from objsearch.sim.world import HouseRef, World

CMD = [sys.executable, "-m", "objsearch.cli", "generate"]
ENV = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}


@pytest.fixture(scope="module")
def rooms():
    return {(t, s): generate_house(s, room=t) for t in ROOM_TYPES for s in (0, 1, 2)}


@pytest.mark.parametrize("room", ROOM_TYPES)
def test_each_type_is_one_valid_dense_room(rooms, room):
    for seed in (0, 1, 2):
        house = rooms[room, seed]
        spec = house.spec
        assert house.report.ok and validate_house(spec, house.model).ok
        assert [r.type for r in spec.rooms] == [room] and spec.doors == () and spec.entrance is None
        assert spec.single_room == room and spec.extra == {"room": room}
        assert spec.size_class == ROOM_SIZE_CLASS and spec.generator_version == "house-gen-2"
        assert spec.house_id == f"train_{room}_{seed:06d}"
        lo, hi = AREA_LIMITS[room]
        area = spec.rooms[0].area
        assert lo <= area <= hi and area == pytest.approx(spec.footprint[0] * spec.footprint[1])
        # denser than house-gen-2's top-up, in small objects above all
        assert len(spec.objects) >= math.ceil(2 * FILL_DENSITY * area)
        assert sum(o.placement in ("on_top", "on_wall") for o in spec.objects) >= 2
        assert all(o.room == 0 for o in spec.objects)
    assert len({rooms[room, s].spec.to_json_text() for s in (0, 1, 2)}) == 3  # seeds differ


def test_a_room_regenerates_byte_identically_from_its_spec(rooms):
    house = rooms["kitchen", 1]
    spec = HouseSpec.from_json(json.loads(house.spec.to_json_text()))
    again = generate_house(
        spec.seed, spec.size_class, spec.split, generator=spec.generator_version, room=spec.single_room
    )
    assert again.spec.to_json_text() == house.spec.to_json_text() and again.xml == house.xml


def test_types_and_seeds_draw_independent_rooms(rooms):
    sizes = {rooms[t, 0].spec.footprint for t in ROOM_TYPES}
    assert len(sizes) == len(ROOM_TYPES)
    assert generate_house(0, room="bedroom", split="test").spec.house_id == "test_bedroom_000000"


def test_room_rules_catch_doors_and_extra_rooms(rooms):
    spec = rooms["bedroom", 0].spec
    assert check_rules(spec) == []
    door = Door(0, (0, -1), "x", (1.0, 0.0), 0.9, 2.1)
    assert any("no doors" in p for p in check_rules(replace(spec, doors=(door,))))
    assert any("holds rooms" in p for p in check_rules(replace(spec, extra={"room": "kitchen"})))
    bare = replace(spec, objects=())
    assert check_rules(bare) == []  # fill is checked only for rooms with objects
    assert any(p.startswith("fill:") for p in check_rules(replace(spec, objects=spec.objects[:1])))


def test_bad_room_arguments_are_user_errors():
    with pytest.raises(UserError, match="unknown room type 'garage'; use one of kitchen, living_room, bedroom"):
        generate_house(0, room="garage")
    with pytest.raises(UserError, match="house-gen-2"):
        generate_house(0, room="kitchen", generator="house-gen-1")
    with pytest.raises(UserError, match="no size class 'small'"):
        generate_house(0, "small", room="kitchen")


def test_houses_keep_their_bytes():
    """Single rooms share house-gen-2's stages: its shipped houses still hash as recorded."""
    suite = load_suite_file("house-gen-v2")
    for group in ("houses", "training_houses"):
        info = next(iter(suite[group].values()))
        assert World.load(HouseRef(**info)).spec_sha256 == info["spec_sha256"]


def test_cli_writes_rooms(tmp_path):
    r = subprocess.run(
        CMD + ["--room", "bathroom", "--seed", "4", "--out", str(tmp_path), "--no-preview", "--quiet"],
        capture_output=True,
        text=True,
        env=ENV,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    spec = json.loads((tmp_path / "train_bathroom_000004" / "spec.json").read_text())
    assert spec["extra"] == {"room": "bathroom"} and spec["size_class"] == "room"
    assert spec["house_id"] == "train_bathroom_000004"


@pytest.mark.parametrize(
    "args, says",
    [
        (["--room", "garage"], "unknown room type 'garage'; use one of kitchen, living_room, bedroom, bathroom"),
        (["--room", "kitchen", "--rooms", "small"], "exclude each other"),
        (["--room", "kitchen", "--generator", "house-gen-1"], "--generator house-gen-2"),
    ],
)
def test_cli_bad_room_exits_2_before_writing(tmp_path, args, says):
    out = tmp_path / "out"
    r = subprocess.run(CMD + ["--out", str(out)] + args, capture_output=True, text=True, env=ENV, timeout=60)
    assert r.returncode == 2 and says in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert not out.exists()


def test_house_ref_loads_a_room(rooms):
    house = rooms["living_room", 2]
    world = World.load(HouseRef(seed=2, room="living_room"))
    assert world.spec.to_json_text() == house.spec.to_json_text()
    assert HouseRef(seed=2, room="living_room").to_json() == {"seed": 2, "split": "train", "room": "living_room"}
    assert world.graph.num_poses > 0


def test_preview_of_a_small_room_holds_its_title(rooms):
    from objsearch.house.plan_canvas import MARGIN, text_width
    from objsearch.house.preview import TITLE_SCALE, _title, render_preview

    spec = min((h.spec for h in rooms.values()), key=lambda s: s.footprint[0])
    assert "1 room " in _title(spec)
    assert render_preview(spec).shape[1] >= text_width(_title(spec), TITLE_SCALE) + 2 * MARGIN
