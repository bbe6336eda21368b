import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.perception.dataset import (
    EXTRA_TRAIN_SEED,
    load_split,
    read_manifest,
    read_shard,
    sample_pose_ids,
    split_houses,
    write_shard,
)
from objsearch.perception.model import NUM_CLASSES
from objsearch.sim.camera import RenderSettings

LOW_RES = RenderSettings(width=32, height=32)  # conftest's; a function-level conftest import is ambiguous in a full run


def test_splits_are_disjoint_and_keep_test_instances_out_of_training():
    train, val, test = (split_houses(s) for s in ("train", "val", "test"))
    assert (len(train), len(val), len(test)) == (40, 10, 10)
    assert not (set(train) & set(val)) and not (set(train) & set(test)) and not (set(val) & set(test))
    assert {h["split"] for h in train.values()} == {"train"}  # training mesh variants only
    assert {h["split"] for h in val.values()} == {h["split"] for h in test.values()} == {"test"}
    with pytest.raises(UserError, match="unknown dataset split"):
        split_houses("holdout")


def test_more_training_houses_are_generated_past_the_suites_forty():
    train = split_houses("train", 42)
    suite = split_houses("train")
    assert list(train)[:40] == list(suite)  # a smaller build is a prefix of a larger one
    extra = [train[h] for h in list(train)[40:]]
    assert [h["seed"] for h in extra] == [EXTRA_TRAIN_SEED, EXTRA_TRAIN_SEED + 1]
    assert {h["split"] for h in extra} == {"train"} and all(len(h["spec_sha256"]) == 64 for h in extra)
    assert not set(train) & (set(split_houses("val")) | set(split_houses("test")))
    assert list(split_houses("train", 3)) == list(suite)[:3]
    with pytest.raises(UserError, match="the test split of house-gen has 10 houses, not 11"):
        split_houses("test", 11)


def test_house_large_splits_are_its_own_houses_with_small_targets_and_no_seen_shapes():
    from objsearch.perception.dataset import default_houses
    from objsearch.sim.suites import load_suite_file

    train, val, test = (split_houses(s, suite="house-large") for s in ("train", "val", "test"))
    suite = load_suite_file("house-large")
    assert train == suite["training_houses"] and len(train) == 60
    assert {**val, **test} == suite["houses"] and (len(val), len(test)) == (5, 10)
    assert {h["generator"] for h in {**train, **val}.values()} == {"house-gen-3"}
    assert {h["split"] for h in test.values()} == {"test"}  # held-out mesh variants
    assert default_houses("house-large") == {"train": 60, "val": 5, "test": 10}
    assert split_houses("test-seen-shapes", 0, suite="house-large") == {}
    with pytest.raises(UserError, match="house-large has no test-seen-shapes split"):
        split_houses("test-seen-shapes", 2, suite="house-large")
    with pytest.raises(UserError, match="the train split of house-large has 60 houses, not 61"):
        split_houses("train", 61, suite="house-large")  # only house-gen generates more
    with pytest.raises(UserError, match="house-gen or house-large, not 'house-multi'"):
        split_houses("train", suite="house-multi")


def test_pose_sampling_is_seeded_per_house():
    a = sample_pose_ids(1000, 50, seed=0, house_seed=1000)
    assert np.array_equal(a, sample_pose_ids(1000, 50, seed=0, house_seed=1000))
    assert not np.array_equal(a, sample_pose_ids(1000, 50, seed=0, house_seed=1001))
    assert len(np.unique(a)) == 50 and len(sample_pose_ids(10, 50, 0, 1)) == 10


def test_shard_round_trip(tmp_path):
    rng = np.random.default_rng(0)
    rgb = rng.integers(0, 256, (5, 8, 8, 3), dtype=np.uint8)
    depth = rng.uniform(0.05, 30.0, (5, 8, 8)).astype(np.float32)
    semantic = rng.integers(0, NUM_CLASSES, (5, 8, 8), dtype=np.uint8)
    write_shard(tmp_path / "s.npz", rgb, depth, semantic, [3, 1, 4, 1, 5], {"house": "h"})
    back = read_shard(tmp_path / "s.npz")
    assert np.array_equal(back["rgb"], rgb) and np.array_equal(back["semantic"], semantic)
    assert np.abs(back["depth"] - depth).max() <= 0.0005 + 1e-6  # millimetres
    assert back["pose_ids"].tolist() == [3, 1, 4, 1, 5] and back["meta"] == {"house": "h"}
    assert not list(tmp_path.glob(".*.tmp"))


def test_built_dataset_matches_its_manifest(tiny_dataset):
    manifest = read_manifest(tiny_dataset)
    assert list(manifest["splits"]) == ["train"] and manifest["num_classes"] == NUM_CLASSES
    frames = load_split(tiny_dataset, "train")
    assert frames.rgb.shape == (48, 32, 32, 3) and frames.depth.dtype == np.float32
    assert manifest["splits"]["train"]["frames"] == 48
    counts = np.bincount(frames.semantic.ravel(), minlength=NUM_CLASSES)
    assert counts.tolist() == manifest["splits"]["train"]["class_pixels"]
    with pytest.raises(UserError, match="no 'test' split"):
        load_split(tiny_dataset, "test")


def test_the_seen_shapes_split_is_unseen_houses_with_training_mesh_variants():
    from objsearch.perception.dataset import SEEN_SHAPES_SEED, split_houses

    houses = split_houses("test-seen-shapes")
    assert len(houses) == 10 and len(split_houses("test-seen-shapes", 2)) == 2
    # generated as training houses (training mesh variants) from seeds that no training house has
    assert {info["split"] for info in houses.values()} == {"train"}
    assert min(info["seed"] for info in houses.values()) >= SEEN_SHAPES_SEED
    others = {h for split in ("train", "val", "test") for h in split_houses(split)}
    assert not set(houses) & others
    with pytest.raises(UserError, match="10 houses, not 11"):
        split_houses("test-seen-shapes", 11)


def test_a_house_large_build_renders_its_first_training_house_and_records_the_suite(tmp_path):
    from objsearch.perception.dataset import build_dataset

    manifest = build_dataset(
        tmp_path, settings=LOW_RES, poses_per_house=8, houses={"train": 1}, progress=False, suite="house-large"
    )
    assert (manifest["suite"], manifest["suite_version"]) == ("house-large", "house-large-v1")
    assert list(manifest["splits"]) == ["train"] and manifest["splits"]["train"]["frames"] == 8
    (house,) = manifest["splits"]["train"]["houses"]
    assert house == next(iter(split_houses("train", suite="house-large")))
    assert read_manifest(tmp_path) == manifest and len(load_split(tmp_path, "train")) == 8


def test_target_share_chooses_poses_that_show_the_suites_targets(tmp_path):
    from objsearch.perception.dataset import build_dataset, read_shard

    kwargs = dict(settings=LOW_RES, poses_per_house=24, houses={"train": 1, "val": 1}, progress=False)
    uniform = build_dataset(tmp_path / "uniform", **kwargs, suite="house-large")
    chosen = build_dataset(tmp_path / "targets", **kwargs, suite="house-large", target_share=1.0)
    train = chosen["splits"]["train"]
    assert chosen["target_share"] == 1.0 and "target_share" not in uniform
    assert train["frames"] == 24 and train["target_frames"] >= 12  # random poses: a few show a small target
    house = next(iter(train["houses"]))
    shards = {k: read_shard(tmp_path / k / "train" / f"{house}.npz") for k in ("uniform", "targets")}
    assert not np.array_equal(shards["uniform"]["pose_ids"], shards["targets"]["pose_ids"])
    assert len(np.unique(shards["targets"]["pose_ids"])) == 24
    # validation frames stay uniform, and a rebuild draws the same poses
    assert chosen["splits"]["val"] == uniform["splits"]["val"] and "target_frames" not in chosen["splits"]["val"]
    again = build_dataset(tmp_path / "again", **kwargs, suite="house-large", target_share=1.0)
    assert again["splits"]["train"] == train
    with pytest.raises(UserError, match="target_share must be between 0 and 1"):
        build_dataset(tmp_path / "bad", **kwargs, target_share=1.5)


def test_a_misspelt_split_is_refused_before_anything_is_rendered(tmp_path):
    from objsearch.perception.dataset import build_dataset

    with pytest.raises(UserError, match="unknown dataset split.*tests; known: train, val, test, test-seen-shapes"):
        build_dataset(tmp_path, houses={"train": 1, "tests": 1}, progress=False)
    assert not any(tmp_path.iterdir())
