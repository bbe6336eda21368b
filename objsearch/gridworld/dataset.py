"""The fixed grid-world benchmark data shipped in the package (``gridworld/data/``).

100 training maps (``map_0000``..``map_0099``), 20 test maps (``map_0100``..``map_0119``)
and three test task lists of 100 tasks each (``seen-goals``, ``unseen-goals``,
``all-goals``). The files are the benchmark: code reads them, never regenerates them, so a
change to the generator cannot silently change results. ``objsearch data rebuild gridworld
[--out DIR]`` rebuilds them from the fixed seeds below (a test checks that it still
reproduces the shipped files); bump ``DATA_VERSION`` if they ever change.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import numpy as np

from objsearch.fileio import atomic_write
from objsearch.gridworld.maps import GridMap, generate_map, load_map_dir, save_map
from objsearch.gridworld.tasks import (
    ALL_GOALS,
    SEEN_GOALS,
    UNSEEN_GOALS,
    GridTask,
    load_tasks,
    sample_tasks,
    save_tasks,
)

DATA_VERSION = "gridworld-v1"
DATA_DIR = Path(__file__).parent / "data"
MAP_SEED = 20210601  # map i is generated from default_rng([MAP_SEED, i])
TASK_SEED = 20210602  # split k's tasks come from default_rng([TASK_SEED, k])
NUM_TRAIN_MAPS, NUM_TEST_MAPS = 100, 20
TASKS_PER_SPLIT = 100
SPLIT_GOALS = {"seen-goals": SEEN_GOALS, "unseen-goals": UNSEEN_GOALS, "all-goals": ALL_GOALS}


def map_name(index: int) -> str:
    """The file stem of map ``index``: ``map_0007``."""
    return f"map_{index:04d}"


def generate_maps(first: int, count: int) -> dict[str, GridMap]:
    """Maps ``first``..``first+count-1`` from their fixed seeds."""
    return {
        map_name(i): generate_map(np.random.default_rng([MAP_SEED, i]), name=map_name(i))
        for i in range(first, first + count)
    }


def generate_split_tasks(test_maps: dict[str, GridMap]) -> dict[str, list[GridTask]]:
    """The three test splits' task lists over ``test_maps``, each from its fixed seed."""
    return {
        split: sample_tasks(test_maps, goals, TASKS_PER_SPLIT, np.random.default_rng([TASK_SEED, k]))
        for k, (split, goals) in enumerate(SPLIT_GOALS.items())
    }


def build(out_dir: str | Path) -> None:
    """Write the whole benchmark data set to ``out_dir`` (train/, test/, tasks/, VERSION.json)."""
    out_dir = Path(out_dir)
    train = generate_maps(0, NUM_TRAIN_MAPS)
    test = generate_maps(NUM_TRAIN_MAPS, NUM_TEST_MAPS)
    for split_dir, maps in (("train", train), ("test", test)):
        for grid_map in maps.values():
            save_map(grid_map, out_dir / split_dir)
    for split, tasks in generate_split_tasks(test).items():
        save_tasks(tasks, out_dir / "tasks" / f"{split}.jsonl")
    meta = {"version": DATA_VERSION, "map_seed": MAP_SEED, "task_seed": TASK_SEED}
    with atomic_write(out_dir / "VERSION.json") as f:
        f.write(json.dumps(meta, indent=2) + "\n")


@lru_cache(maxsize=None)
def train_maps() -> dict[str, GridMap]:
    """The 100 packaged training maps by name (loaded once)."""
    return load_map_dir(DATA_DIR / "train")


@lru_cache(maxsize=None)
def test_maps() -> dict[str, GridMap]:
    """The 20 packaged test maps by name (loaded once)."""
    return load_map_dir(DATA_DIR / "test")


def split_tasks(split: str) -> list[GridTask]:
    """The fixed test tasks of ``split`` (one of ``SPLIT_GOALS``)."""
    return load_tasks(DATA_DIR / "tasks" / f"{split}.jsonl", test_maps())


if __name__ == "__main__":  # `python -m` of this module, a command until 2026-12-02: name its replacement
    raise SystemExit("python -m objsearch.gridworld.dataset is now: objsearch data rebuild gridworld [--out DIR]")
