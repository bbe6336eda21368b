"""Category table and the mesh library."""

import hashlib

from objsearch.house import assets
from objsearch.house.categories import CATEGORIES, CATEGORY_IDS, CATEGORY_NAMES, FIRST_OBJECT_ID, STRUCTURE


def test_category_table_is_fixed_and_complete():
    assert len(CATEGORIES) >= 50
    assert STRUCTURE == {"background": 0, "wall": 1, "floor": 2, "door": 3, "ceiling": 4}
    ids = [c.id for c in CATEGORIES]
    assert ids == list(range(FIRST_OBJECT_ID, FIRST_OBJECT_ID + len(CATEGORIES)))
    assert len(CATEGORY_IDS) == len(CATEGORY_NAMES)
    # spot-check ids that segmentation data depends on (changing them needs a version bump)
    assert CATEGORY_IDS["sofa"] == 8 and CATEGORY_IDS["toilet"] == 50 and CATEGORY_IDS["stool"] == 68
    for c in CATEGORIES:
        assert all(lo <= hi for lo, hi in zip(c.size_min, c.size_max)), c.name
        assert set(c.rooms) <= {"living_room", "kitchen", "dining_room", "bedroom", "bathroom", "office", "hallway"}
        assert c.placement != "on_top" or c.parents


def test_every_category_has_three_distinct_variants_and_a_test_one():
    manifest = assets.load_manifest()
    for c in CATEGORIES:
        entries = manifest["categories"][c.name]
        assert len(assets.variants(c.name, "train")) >= 3 and assets.variants(c.name, "test"), c.name
        digests = {hashlib.sha256(assets.mesh_bytes(c.name, v)).hexdigest() for v in entries}
        assert len(digests) == len(entries), f"{c.name}: variants are not all different"
        if c.receptacle:
            assert all("surface" in e for e in entries.values())


def test_asset_build_is_deterministic(tmp_path, capsys):
    from objsearch.cli import main

    assert main(["data", "rebuild", "assets", "--out", str(tmp_path)]) == 0
    assert f"under {tmp_path / 'meshes'}" in capsys.readouterr().err
    for path in sorted((tmp_path / "meshes").rglob("*")):
        if path.is_file():
            rel = path.relative_to(tmp_path)
            assert path.read_bytes() == (assets.assets_dir() / rel).read_bytes(), (
                f"{rel} differs: rebuild with objsearch data rebuild assets"
            )
    total = sum(p.stat().st_size for p in (assets.assets_dir() / "meshes").rglob("*") if p.is_file())
    assert total < 5_000_000
