import json

import numpy as np

from objsearch.gridworld import dataset
from objsearch.gridworld.tasks import SEEN_GOALS, UNSEEN_GOALS


def test_generator_reproduces_the_shipped_benchmark(tmp_path):
    """The shipped files are the benchmark; if this fails the generator changed: bump
    DATA_VERSION and rebuild the data deliberately (see DEVELOPERS.md)."""
    dataset.build(tmp_path)
    for split in ("train", "test"):
        fresh = {p.name for p in (tmp_path / split).glob("*.npz")}
        shipped = {p.name for p in (dataset.DATA_DIR / split).glob("*.npz")}
        assert fresh == shipped
        for name in sorted(fresh):
            with np.load(tmp_path / split / name) as a, np.load(dataset.DATA_DIR / split / name) as b:
                assert np.array_equal(a["obstacles"], b["obstacles"]) and np.array_equal(a["goals"], b["goals"]), name
    for split in dataset.SPLIT_GOALS:
        fresh = (tmp_path / "tasks" / f"{split}.jsonl").read_text()
        assert fresh == (dataset.DATA_DIR / "tasks" / f"{split}.jsonl").read_text(), split
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
