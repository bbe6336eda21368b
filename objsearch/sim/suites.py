"""The house evaluation suites: fixed, versioned episode files, and how they were made.

A suite file (``objsearch/sim/data/<suite>.json``) records its houses by generator seed
with their spec hashes, the goal poses of every target (by the goal rule, so success never
depends on the renderer at evaluation time) and the episodes of every split. Evaluation
regenerates the houses and refuses to run if a hash differs.

* ``house-single`` (the paper's Table 3, left): one house, 12 target categories; splits
  ``seen-goals`` and ``unseen-goals`` (6 categories each; agents train on the seen ones).
* ``house-multi`` (Table 3, right): 4 training houses and 4 unseen houses with the same 6
  target categories; splits ``seen-envs`` and ``unseen-envs``.
* ``house-gen`` (beyond the paper): 40 training houses (listed, no episodes), 10
  validation and 10 test houses generated as test houses (unseen object instances), with
  seen and unseen target categories (targets found in at least half of the evaluation
  houses, a third of them held out as unseen); splits ``val-seen``, ``val-unseen``,
  ``test-seen``, ``test-unseen``.

Episodes: 100 per split, house and target drawn uniformly, the start uniformly among poses
6 to 40 minimal steps from the nearest goal pose (``START_STEPS``); 1000 steps at most.
Rebuild (deliberately; bump the version): ``python -m objsearch.sim.suites NAME``.
"""

from __future__ import annotations

import json
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import write_json
from objsearch.house.categories import CATEGORY_IDS
from objsearch.sim.env import START_STEPS, HouseTask
from objsearch.sim.goals import DEFAULT_RULE, GOAL_CAMERA, goal_poses
from objsearch.sim.navgraph import NAVGRAPH_VERSION
from objsearch.sim.world import HouseRef, World

DATA_DIR = Path(__file__).parent / "data"
SUITE_NAMES = ("house-single", "house-multi", "house-gen")
EPISODES_PER_SPLIT = 100
MAX_STEPS = 1000
SUITE_SEED = 20211201
# Targets: objects large enough to be found from across a room (the kind House3D used).
TARGETS = (
    "armchair", "bathtub", "bed", "bookshelf", "chair", "coffee_table", "counter", "desk", "dining_table",
    "dishwasher", "dresser", "filing_cabinet", "floor_lamp", "fridge", "kitchen_sink", "mirror", "nightstand",
    "office_chair", "painting", "plant", "side_table", "sink", "sofa", "stove", "toilet", "trash_can", "tv",
    "tv_stand", "wardrobe", "whiteboard",
)


@lru_cache(maxsize=None)
def load_suite_file(name: str) -> dict:
    path = DATA_DIR / f"{name}.json"
    if not path.exists():
        raise UserError(f"suite file {path} is missing; rebuild it with python -m objsearch.sim.suites {name}")
    return json.loads(path.read_text())


def house_refs(suite: dict) -> list[HouseRef]:
    return [HouseRef(**info) for info in suite["houses"].values()]


def episode_task(suite: dict, item: dict) -> HouseTask:
    goals = suite["goals"][item["house"]][item["target"]]
    return HouseTask(
        house=item["house"],
        start=tuple(item["start"]),
        target=item["target"],
        goals=tuple(tuple(g) for g in goals),
        min_steps=item["min_steps"],
    )


def training_houses(suite: dict) -> list[HouseRef]:
    """The houses agents train on: ``house-single``'s house, ``house-multi``'s seen
    environments, ``house-gen``'s training houses (never an evaluation-only house)."""
    if suite["training_houses"]:
        return [HouseRef(**info) for info in suite["training_houses"].values()]
    split = "seen-envs" if "seen-envs" in suite["splits"] else next(iter(suite["splits"]))
    ids = sorted({item["house"] for item in suite["splits"][split]})
    return [HouseRef(**suite["houses"][house]) for house in ids]


def training_targets(suite: dict) -> list[str]:
    """The target categories agents train on: the suite's seen ones (``house-multi``: its six)."""
    categories = suite["categories"]
    return list(categories.get("seen", categories.get("targets", [])))


# -- building ---------------------------------------------------------------------------
def _goal_table(world: World, targets, cache_dir) -> dict[str, list]:
    from objsearch.sim.cache import HouseCache

    cache = HouseCache.open(world, GOAL_CAMERA, cache_dir)
    semantic, depth = np.asarray(cache.semantic), np.asarray(cache.depth)
    graph = world.graph
    table = {}
    for target in targets:
        goals = goal_poses(semantic, depth, CATEGORY_IDS[target], DEFAULT_RULE)
        dist = graph.shortest_steps(goals) if len(goals) else None
        if dist is not None and ((dist >= START_STEPS[0]) & (dist <= START_STEPS[1])).any():
            table[target] = [list(graph.pose_of(int(g))) for g in goals]
    return table


def _episodes(worlds: dict[str, World], goals: dict, targets: list[str], count: int, rng) -> list[dict]:
    out = []
    names = sorted(worlds)
    while len(out) < count:
        house = names[rng.integers(len(names))]
        target = targets[rng.integers(len(targets))]
        if target not in goals[house]:
            continue
        graph = worlds[house].graph
        dist = graph.shortest_steps([graph.pose_id(*g) for g in goals[house][target]])
        starts = np.flatnonzero((dist >= START_STEPS[0]) & (dist <= START_STEPS[1]))
        start = int(starts[rng.integers(len(starts))])
        out.append({"house": house, "start": list(graph.pose_of(start)), "target": target, "min_steps": int(dist[start])})
    return out


def house_entry(world: World, ref: HouseRef) -> dict:
    """The fields a suite file stores for a house (``HouseRef`` fields, with the spec hash)."""
    return {"seed": ref.seed, "split": ref.split, "size_class": world.spec.size_class, "spec_sha256": world.spec_sha256}


def build_suite(name: str, cache_dir: str | None = None) -> dict:
    """Build a suite from its fixed seeds (renders every pose of its evaluation houses)."""
    rng = np.random.default_rng([SUITE_SEED, SUITE_NAMES.index(name)])
    if name == "house-single":
        candidates = {s: World.load(HouseRef(seed=s, size_class="medium")) for s in range(10)}
        # the house with the most target categories
        seed = max(candidates, key=lambda s: (len({o.category for o in candidates[s].spec.objects} & set(TARGETS)), -s))
        eval_refs = {"eval": [HouseRef(seed=seed, size_class="medium")]}
        train_refs: list[HouseRef] = []
    elif name == "house-multi":
        eval_refs = {
            "seen-envs": [HouseRef(seed=s, size_class="medium") for s in (100, 101, 102, 103)],
            "unseen-envs": [HouseRef(seed=s, size_class="medium") for s in (200, 201, 202, 203)],
        }
        train_refs = []
    elif name == "house-gen":
        train_refs = [HouseRef(seed=s) for s in range(1000, 1040)]
        eval_refs = {
            "val": [HouseRef(seed=s, split="test") for s in range(2000, 2010)],
            "test": [HouseRef(seed=s, split="test") for s in range(3000, 3010)],
        }
    else:
        raise UserError(f"unknown house suite {name!r}; known: {', '.join(SUITE_NAMES)}")

    worlds = {key: [World.load(r) for r in refs] for key, refs in eval_refs.items()}
    houses, goals = {}, {}
    for key, refs in eval_refs.items():
        for ref, world in zip(refs, worlds[key]):
            houses[world.house_id] = house_entry(world, ref)
            goals[world.house_id] = _goal_table(world, TARGETS, cache_dir)
    training = {}
    for ref in train_refs:
        world = World.load(ref)
        training[world.house_id] = house_entry(world, ref)

    def common(ws):
        sets = [set(goals[w.house_id]) for w in ws]
        return sorted(set.intersection(*sets))

    splits, categories = {}, {}
    if name == "house-single":
        (world,) = worlds["eval"]
        usable = common([world])
        picked = [usable[i] for i in sorted(rng.choice(len(usable), size=12, replace=False))]
        order = rng.permutation(12)
        categories = {"seen": sorted(picked[i] for i in order[:6]), "unseen": sorted(picked[i] for i in order[6:])}
        by_id = {world.house_id: world}
        splits["seen-goals"] = _episodes(by_id, goals, categories["seen"], EPISODES_PER_SPLIT, rng)
        splits["unseen-goals"] = _episodes(by_id, goals, categories["unseen"], EPISODES_PER_SPLIT, rng)
    elif name == "house-multi":
        usable = common(worlds["seen-envs"] + worlds["unseen-envs"])
        if len(usable) < 6:
            raise RuntimeError(f"only {len(usable)} targets common to all house-multi houses: {usable}")
        categories = {"targets": [usable[i] for i in sorted(rng.choice(len(usable), size=6, replace=False))]}
        for split in ("seen-envs", "unseen-envs"):
            by_id = {w.house_id: w for w in worlds[split]}
            splits[split] = _episodes(by_id, goals, categories["targets"], EPISODES_PER_SPLIT, rng)
    else:
        # targets found in at least half of the evaluation houses (an episode's house always has its target)
        evaluated = worlds["val"] + worlds["test"]
        usable = sorted(t for t in TARGETS if sum(t in goals[w.house_id] for w in evaluated) >= len(evaluated) / 2)
        order = rng.permutation(len(usable))
        unseen_count = max(3, len(usable) // 3)
        categories = {
            "seen": sorted(usable[i] for i in order[unseen_count:]),
            "unseen": sorted(usable[i] for i in order[:unseen_count]),
        }
        for part in ("val", "test"):
            by_id = {w.house_id: w for w in worlds[part]}
            for kind in ("seen", "unseen"):
                splits[f"{part}-{kind}"] = _episodes(by_id, goals, categories[kind], EPISODES_PER_SPLIT, rng)
    return {
        "suite": name,
        "version": f"{name}-v1",
        "navgraph": NAVGRAPH_VERSION,
        "goal_rule": DEFAULT_RULE.to_json(),
        "goal_camera": GOAL_CAMERA.to_dict(),
        "start_steps": list(START_STEPS),
        "max_steps": MAX_STEPS,
        "categories": categories,
        "houses": houses,
        "training_houses": training,
        "goals": goals,
        "splits": splits,
    }


if __name__ == "__main__":
    names = sys.argv[1:] or list(SUITE_NAMES)
    for suite_name in names:
        write_json(DATA_DIR / f"{suite_name}.json", build_suite(suite_name), indent=None)
        print(f"wrote {DATA_DIR / f'{suite_name}.json'}")
