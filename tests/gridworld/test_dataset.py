import json

import numpy as np

from objsearch.gridworld import dataset
from objsearch.gridworld.tasks import SEEN_GOALS, UNSEEN_GOALS


def test_generator_reproduces_the_shipped_benchmark(tmp_path, capsys):
    """The shipped files are the benchmark; if this fails the generator changed: bump
    DATA_VERSION and rebuild the data deliberately (objsearch data rebuild gridworld; see
    DEVELOPERS.md). The rebuild gives back every shipped file byte for byte."""
    from objsearch.cli import main

    assert main(["data", "rebuild", "gridworld", "--out", str(tmp_path)]) == 0
    assert f"under {tmp_path}" in capsys.readouterr().err
    files = lambda root: sorted(p.relative_to(root) for p in root.rglob("*") if p.is_file())
    assert files(tmp_path) == files(dataset.DATA_DIR)
    for rel in files(dataset.DATA_DIR):
        assert (tmp_path / rel).read_bytes() == (dataset.DATA_DIR / rel).read_bytes(), rel
    for split in ("train", "test"):
        assert len(list((tmp_path / split).glob("*.npz"))) == (
            dataset.NUM_TRAIN_MAPS if split == "train" else dataset.NUM_TEST_MAPS
        )
    assert {p.stem for p in (tmp_path / "tasks").glob("*.jsonl")} == set(dataset.SPLIT_GOALS)
    meta = json.loads((dataset.DATA_DIR / "VERSION.json").read_text())
    assert meta["version"] == dataset.DATA_VERSION


def test_split_task_lists():
    for split, goals in (("seen-goals", SEEN_GOALS), ("unseen-goals", UNSEEN_GOALS), ("all-goals", range(16))):
        tasks = dataset.split_tasks(split)
        assert len(tasks) == 100
        assert {t.goal for t in tasks} <= set(goals)
        assert {t.map for t in tasks} <= set(dataset.test_maps())
        assert min(t.min_steps for t in tasks) >= 1
        # the published lists average 10.4-11.8 minimal steps
        assert 8 <= np.mean([t.min_steps for t in tasks]) <= 14
    all_goals = {t.goal for t in dataset.split_tasks("all-goals")}
    assert all_goals & set(UNSEEN_GOALS) and all_goals & set(SEEN_GOALS)


def test_train_and_test_maps_are_disjoint():
    assert not set(dataset.train_maps()) & set(dataset.test_maps())
    train = {m.obstacles.tobytes() for m in dataset.train_maps().values()}
    assert not train & {m.obstacles.tobytes() for m in dataset.test_maps().values()}
