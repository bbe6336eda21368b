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
    with pytest.raises(UserError, match="the test split has 10 houses, not 11"):
        split_houses("test", 11)


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


def test_a_misspelt_split_is_refused_before_anything_is_rendered(tmp_path):
    from objsearch.perception.dataset import build_dataset

    with pytest.raises(UserError, match="unknown dataset split.*tests; known: train, val, test, test-seen-shapes"):
        build_dataset(tmp_path, houses={"train": 1, "tests": 1}, progress=False)
    assert not any(tmp_path.iterdir())
