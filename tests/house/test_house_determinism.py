"""Same seed and version: byte-identical house.xml and spec.json; houses compile anywhere."""

import json
import shutil

import mujoco

from objsearch.house.generate import generate_house, write_house
from objsearch.house.spec import HouseSpec


def test_same_seed_same_bytes(tmp_path):
    a = write_house(generate_house(5), tmp_path / "a")
    b = write_house(generate_house(5), tmp_path / "b")
    for name in ("house.xml", "spec.json"):
        assert (a / name).read_bytes() == (b / name).read_bytes()
    assert generate_house(6).spec.to_json_text() != (a / "spec.json").read_text()


def test_spec_json_round_trip_and_schema(tmp_path):
    house = generate_house(7)
    text = house.spec.to_json_text()
    again = HouseSpec.from_json(json.loads(text))
    assert again == house.spec and again.to_json_text() == text
    data = json.loads(text)
    assert data["schema_version"] == 1
    assert {"type", "polygon"} <= set(data["rooms"][0])
    assert {"category", "instance", "room", "position", "yaw", "size"} <= set(data["objects"][0])


def test_house_dir_compiles_after_moving(tmp_path):
    house = generate_house(8, "small")
    d = write_house(house, tmp_path / "out")
    moved = shutil.move(str(d), str(tmp_path / "elsewhere"))
    model = mujoco.MjModel.from_xml_path(f"{moved}/house.xml")
    assert model.nbody == house.model.nbody and model.ngeom == house.model.ngeom
    assert (tmp_path / "elsewhere" / "preview.png").stat().st_size > 1000


def test_test_split_uses_reserved_variants():
    from objsearch.house.assets import TEST_VARIANTS

    train, test = generate_house(9, split="train"), generate_house(9, split="test")
    assert all(o.variant not in TEST_VARIANTS for o in train.spec.objects)
    assert all(o.variant in TEST_VARIANTS for o in test.spec.objects)
    assert test.spec.house_id != train.spec.house_id
