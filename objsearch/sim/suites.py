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
* ``house-gen-v2``: ``house-gen`` made again with the generator ``house-gen-2`` (circulation
  through a public core, rooms of real sizes, an entrance; the same seeds, splits and rule
  for targets). ``house-gen`` stays, since the shipped agents were trained and measured on it.

Episodes: 100 per split, house and target drawn uniformly, the start uniformly among poses
6 to 40 minimal steps from the nearest goal pose (``START_STEPS``); 1000 steps at most.
Rebuild (deliberately; bump the version): ``objsearch suite rebuild NAME``.

``SUITE_NAMES`` is the one list of the shipped house suites (the harness's registry,
``objsearch.eval.suites.SUITES``, takes them from here); a new house suite is a name there,
its branch in ``build_suite`` and its file.

A user's own houses (folders written by ``objsearch generate``) make a suite file with
``objsearch suite make`` (``suite_from_houses``): the same fields, with each house recorded
by its folder (a path relative to the suite file) and spec hash. ``load_suite_file`` takes a
shipped suite's name or such a file's path; ``load_house`` refuses a house folder that is
missing, does not load, or no longer matches its spec or the suite, naming the house.
"""

from __future__ import annotations

import hashlib
import json
import os
from functools import lru_cache
from pathlib import Path

import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import write_json
from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.sim.env import START_STEPS, STARTS, HouseTask, draw_start, entrance_poses
from objsearch.sim.goals import DEFAULT_RULE, GOAL_CAMERA, goal_poses
from objsearch.sim.navgraph import NAVGRAPH_VERSION
from objsearch.sim.world import HouseRef, World

DATA_DIR = Path(__file__).parent / "data"
# The shipped house suites, in this order for good: a suite's index seeds its builder.
SUITE_NAMES = ("house-single", "house-multi", "house-gen", "house-gen-v2", "house-single-v2", "house-multi-v2")
# The generator of each suite's houses (None: house-gen-1).
SUITE_GENERATORS = {"house-gen-v2": "house-gen-2", "house-single-v2": "house-gen-2", "house-multi-v2": "house-gen-2"}
# The protocol (the suite of house-gen-1 houses) each suite follows.
SUITE_PROTOCOLS = {"house-gen-v2": "house-gen", "house-single-v2": "house-single", "house-multi-v2": "house-multi"}
HOUSE_SINGLE_TARGETS = 12  # house-single's target categories (6 seen, 6 unseen)
EPISODES_PER_SPLIT = 100
MAX_STEPS = 1000
SUITE_SEED = 20211201
# The fields the harness reads from a suite file.
SUITE_FILE_KEYS = ("version", "max_steps", "categories", "houses", "training_houses", "goals", "splits")
# Targets: objects large enough to be found from across a room (the kind House3D used).
TARGETS = (
    "armchair",
    "bathtub",
    "bed",
    "bookshelf",
    "chair",
    "coffee_table",
    "counter",
    "desk",
    "dining_table",
    "dishwasher",
    "dresser",
    "filing_cabinet",
    "floor_lamp",
    "fridge",
    "kitchen_sink",
    "mirror",
    "nightstand",
    "office_chair",
    "painting",
    "plant",
    "side_table",
    "sink",
    "sofa",
    "stove",
    "toilet",
    "trash_can",
    "tv",
    "tv_stand",
    "wardrobe",
    "whiteboard",
)


def load_suite_file(name: str) -> dict:
    """The suite file of a shipped house suite (a name of ``SUITE_NAMES``), or the one at the
    path ``name`` (``*.json``, made by ``objsearch suite make``) with its house folders
    resolved against the file's folder."""
    if name in SUITE_NAMES:
        return _shipped_suite_file(name)
    if not name.endswith(".json"):
        raise UserError(
            f"unknown house suite {name!r}; known: {', '.join(SUITE_NAMES)}, "
            "or the path of a suite file (.json) made by objsearch suite make"
        )
    path = Path(name)
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise UserError(
            f"suite file {path} does not exist; make it with objsearch suite make --houses DIR --out {path}"
        ) from None
    except OSError as err:
        raise UserError(f"cannot read suite file {path}: {err.strerror}") from None
    except json.JSONDecodeError as err:
        raise UserError(f"suite file {path} is not JSON ({err}); remake it with objsearch suite make") from None
    missing = [key for key in SUITE_FILE_KEYS if not isinstance(data, dict) or key not in data]
    if missing:
        raise UserError(f"{path} is not a suite file (no {', '.join(missing)}); make one with objsearch suite make")
    for info in data["houses"].values():
        if "path" in info:
            info["path"] = os.path.abspath(path.parent / info["path"])
    return data


@lru_cache(maxsize=None)
def _shipped_suite_file(name: str) -> dict:
    path = DATA_DIR / f"{name}.json"
    if not path.exists():
        raise UserError(f"suite file {path} is missing; rebuild it with objsearch suite rebuild {name}")
    return json.loads(path.read_text())


def write_suite_file(path: str | os.PathLike, suite: dict) -> None:
    """Write a suite file as the shipped ones are written (one line of JSON, atomically)."""
    write_json(path, suite, indent=None)


def load_house(ref: HouseRef, name: str) -> World:
    """``World.load(ref)``, with a house folder (``ref.path``) checked further: it must exist,
    load, hold the ``house.xml`` its ``spec.json`` compiles to, and match ``ref.spec_sha256``.
    A bad one is a one-line ``UserError`` naming the house (``name``) and the fix."""
    if ref.path is None:
        return World.load(ref)
    from objsearch.house.mjcf import compile_house

    folder = Path(ref.path)
    if not folder.is_dir():
        raise UserError(
            f"house {name}: folder {folder} is missing; restore it, or remake the suite with objsearch suite make"
        )
    try:
        world = World.load(HouseRef(path=ref.path))
        if ref.spec_sha256 is not None and world.spec_sha256 != ref.spec_sha256:
            raise UserError(
                f"{folder / 'spec.json'} changed after the suite was made (spec hash {world.spec_sha256[:12]}, "
                f"the suite has {ref.spec_sha256[:12]}); restore the house, or remake the suite with "
                "objsearch suite make"
            )
        if compile_house(world.spec)[1] != (folder / "house.xml").read_text():
            raise UserError(
                f"{folder / 'spec.json'} no longer matches its house.xml (one was edited, or they come from "
                "another objsearch or MuJoCo version); regenerate the house with objsearch generate"
            )
    except UserError as err:
        raise UserError(f"house {name}: {' '.join(str(err).split())}") from None
    except (ValueError, KeyError, TypeError, AttributeError) as err:
        raise UserError(
            f"house {name}: {folder / 'spec.json'} is not a house spec ({' '.join(str(err).split())}); "
            "regenerate the house with objsearch generate"
        ) from None
    return world


def load_houses(suite: dict) -> dict[str, World]:
    """A suite's evaluation houses by house id, each loaded and checked by ``load_house``."""
    worlds = (load_house(HouseRef(**info), house_id) for house_id, info in suite["houses"].items())
    return {world.house_id: world for world in worlds}


def house_refs(suite: dict) -> list[HouseRef]:
    """The ``HouseRef`` of every evaluation house of a suite dict."""
    return [HouseRef(**info) for info in suite["houses"].values()]


def episode_task(suite: dict, item: dict) -> HouseTask:
    """The ``HouseTask`` of one split entry ``item`` of a suite dict, with its goal poses."""
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


def _episodes(
    worlds: dict[str, World], goals: dict, targets: list[str], count: int, rng, starts: str = "anywhere"
) -> list[dict]:
    """``count`` episodes: house and target drawn uniformly (again while the house lacks the
    target, or, with ``starts="entrance"``, while ``draw_start`` finds no start near its
    entrance), the start by ``draw_start``."""
    names = sorted(worlds)
    near = {house: entrance_poses(world) for house, world in worlds.items()} if starts == "entrance" else {}

    def steps_to_goals(house, target):
        graph = worlds[house].graph
        return graph.shortest_steps([graph.pose_id(*g) for g in goals[house][target]])

    if near and not any(
        (near[h] & (steps_to_goals(h, t) >= START_STEPS[0])).any() for h in names for t in targets if t in goals[h]
    ):  # draw_start would find no start for any house and target: the loop below would not end
        raise UserError(
            f"no target ({', '.join(targets)}) has goal poses {START_STEPS[0]} steps or more from the entrance "
            f"of any of the houses {', '.join(names)}; draw the starts anywhere (starts='anywhere')"
        )
    out = []
    while len(out) < count:
        house = names[rng.integers(len(names))]
        target = targets[rng.integers(len(targets))]
        if target not in goals[house]:
            continue
        graph = worlds[house].graph
        dist = steps_to_goals(house, target)
        start = draw_start(dist, rng, near.get(house))
        if start is None:
            continue
        out.append(
            {"house": house, "start": list(graph.pose_of(start)), "target": target, "min_steps": int(dist[start])}
        )
    return out


def house_entry(world: World, ref: HouseRef) -> dict:
    """The fields a suite file stores for a house (``HouseRef`` fields, with the spec hash):
    its generator seed, or its folder (``ref.path``)."""
    if ref.path is not None:
        return {"path": ref.path, "spec_sha256": world.spec_sha256}
    entry = {
        "seed": ref.seed,
        "split": ref.split,
        "size_class": world.spec.size_class,
        "spec_sha256": world.spec_sha256,
    }
    if ref.generator is not None:  # left out for house-gen-1 houses, so v1 suite files keep their bytes
        entry["generator"] = ref.generator
    return entry


def _found_in_half(goals: dict, house_ids: list[str]) -> list[str]:
    """The ``TARGETS`` with goal poses in at least half of the houses ``house_ids``."""
    return sorted(t for t in TARGETS if sum(t in goals[house] for house in house_ids) >= len(house_ids) / 2)


def _suite_record(
    name: str, version: str, categories: dict, houses: dict, training: dict, goals: dict, splits: dict
) -> dict:
    """A suite file's content: the given parts and the settings every suite records."""
    return {
        "suite": name,
        "version": version,
        "navgraph": NAVGRAPH_VERSION,
        "goal_rule": DEFAULT_RULE.to_json(),
        "goal_camera": GOAL_CAMERA.to_json(),
        "start_steps": list(START_STEPS),
        "max_steps": MAX_STEPS,
        "categories": categories,
        "houses": houses,
        "training_houses": training,
        "goals": goals,
        "splits": splits,
    }


def build_suite(name: str, cache_dir: str | None = None) -> dict:
    """Build a suite from its fixed seeds (renders every pose of its evaluation houses)."""
    if name not in SUITE_NAMES:
        raise UserError(f"unknown house suite {name!r}; known: {', '.join(SUITE_NAMES)}")
    rng = np.random.default_rng([SUITE_SEED, SUITE_NAMES.index(name)])
    gen, protocol = SUITE_GENERATORS.get(name), SUITE_PROTOCOLS.get(name, name)
    if protocol == "house-single":
        candidates = {s: World.load(HouseRef(seed=s, size_class="medium", generator=gen)) for s in range(10)}

        def present(s):
            return len({o.category for o in candidates[s].spec.objects} & set(TARGETS))

        # the house with the most target categories, passing over one where fewer than 12 of
        # them have goal poses in reach of starts (never the case for house-single's house)
        ranked = sorted(candidates, key=lambda s: (-present(s), s))
        seed = next(
            (s for s in ranked if len(_goal_table(candidates[s], TARGETS, cache_dir)) >= HOUSE_SINGLE_TARGETS), None
        )
        if seed is None:
            raise RuntimeError(
                f"no {name} candidate house has {HOUSE_SINGLE_TARGETS} target categories with goal poses"
            )
        eval_refs = {"eval": [HouseRef(seed=seed, size_class="medium", generator=gen)]}
        train_refs: list[HouseRef] = []
    elif protocol == "house-multi":
        eval_refs = {
            "seen-envs": [HouseRef(seed=s, size_class="medium", generator=gen) for s in (100, 101, 102, 103)],
            "unseen-envs": [HouseRef(seed=s, size_class="medium", generator=gen) for s in (200, 201, 202, 203)],
        }
        train_refs = []
    else:
        train_refs = [HouseRef(seed=s, generator=gen) for s in range(1000, 1040)]
        eval_refs = {
            "val": [HouseRef(seed=s, split="test", generator=gen) for s in range(2000, 2010)],
            "test": [HouseRef(seed=s, split="test", generator=gen) for s in range(3000, 3010)],
        }

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
    if protocol == "house-single":
        (world,) = worlds["eval"]
        usable = common([world])
        picked = [usable[i] for i in sorted(rng.choice(len(usable), size=HOUSE_SINGLE_TARGETS, replace=False))]
        order = rng.permutation(HOUSE_SINGLE_TARGETS)
        categories = {"seen": sorted(picked[i] for i in order[:6]), "unseen": sorted(picked[i] for i in order[6:])}
        by_id = {world.house_id: world}
        splits["seen-goals"] = _episodes(by_id, goals, categories["seen"], EPISODES_PER_SPLIT, rng)
        splits["unseen-goals"] = _episodes(by_id, goals, categories["unseen"], EPISODES_PER_SPLIT, rng)
    elif protocol == "house-multi":
        usable = common(worlds["seen-envs"] + worlds["unseen-envs"])
        if len(usable) < 6:
            raise RuntimeError(f"only {len(usable)} targets common to all {name} houses: {usable}")
        categories = {"targets": [usable[i] for i in sorted(rng.choice(len(usable), size=6, replace=False))]}
        for split in ("seen-envs", "unseen-envs"):
            by_id = {w.house_id: w for w in worlds[split]}
            splits[split] = _episodes(by_id, goals, categories["targets"], EPISODES_PER_SPLIT, rng)
    else:
        # targets found in at least half of the evaluation houses (an episode's house always has its target)
        evaluated = worlds["val"] + worlds["test"]
        usable = _found_in_half(goals, [w.house_id for w in evaluated])
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
    return _suite_record(name, f"{name}-v1", categories, houses, training, goals, splits)


def suite_from_houses(
    houses_dir: str | os.PathLike,
    out: str | os.PathLike,
    targets: list[str] | None = None,
    episodes: int = EPISODES_PER_SPLIT,
    seed: int = 0,
    cache_dir: str | None = None,
    starts: str = "anywhere",
) -> dict:
    """The suite file to write at ``out`` for the houses under ``houses_dir`` (the folders
    ``objsearch generate --out`` writes), made as ``build_suite`` makes the shipped ones: goal
    poses by the goal rule (rendering every pose into the cache), spec hashes, and one split
    (named after ``out``) of ``episodes`` episodes drawn with ``seed``. Targets: ``targets``,
    else the ``TARGETS`` with goal poses in at least half of the houses (as ``house-gen``
    picks them). Houses are recorded by their folder relative to ``out``'s folder, so the
    file and the houses move together; every house is checked (``load_house``) before any
    is rendered. The same houses, arguments and paths give the same file.

    ``starts``: ``anywhere`` (default), or ``entrance``: every start is drawn near the house's
    entrance (``objsearch.sim.env.draw_start``; the file then records ``"starts": "entrance"``);
    a house without an entrance (``house-gen-1``) is a ``UserError`` before anything is rendered."""
    if starts not in STARTS:
        raise UserError(f"unknown starts {starts!r}; use one of {', '.join(STARTS)}")
    root, base = Path(houses_dir), Path(out).resolve().parent
    wanted = _check_targets(targets) if targets else list(TARGETS)
    worlds, houses, folders = {}, {}, {}
    for folder in house_folders(root):
        world = load_house(HouseRef(path=str(folder)), folder.name)
        if world.house_id in worlds:
            raise UserError(
                f"{folders[world.house_id]} and {folder} hold the same house {world.house_id} "
                "(a copied folder?); keep one of them"
            )
        worlds[world.house_id], folders[world.house_id] = world, folder
        stored = Path(os.path.relpath(folder.resolve(), base)).as_posix()
        houses[world.house_id] = house_entry(world, HouseRef(path=stored))
        if starts == "entrance":
            entrance_poses(world)  # a house without an entrance: UserError now, not after rendering
    tables = {house: _goal_table(world, wanted, cache_dir) for house, world in worlds.items()}
    if targets:
        for target in wanted:
            if not any(target in table for table in tables.values()):
                raise UserError(
                    f"target {target!r} has no goal pose {START_STEPS[0]}-{START_STEPS[1]} steps from a "
                    f"start in any house under {root}; drop it from --targets"
                )
    else:
        wanted = _found_in_half(tables, list(worlds))
        if not wanted:
            raise UserError(
                f"no target category has goal poses in at least half of the houses under {root}; "
                "name the targets with --targets"
            )
    goals = {house: {t: poses for t, poses in table.items() if t in wanted} for house, table in tables.items()}
    splits = {Path(out).stem: _episodes(worlds, goals, wanted, episodes, np.random.default_rng(seed), starts)}
    spec_hashes = {house: entry["spec_sha256"] for house, entry in houses.items()}
    digest = hashlib.sha256(json.dumps([spec_hashes, goals, splits], sort_keys=True).encode()).hexdigest()[:12]
    suite = _suite_record(Path(out).stem, f"custom:{digest}", {"targets": wanted}, houses, {}, goals, splits)
    if starts != "anywhere":  # recorded only when not the default, so other files keep their bytes
        suite["starts"] = starts
    return suite


def house_folders(root: Path) -> list[Path]:
    """The house folders under ``root`` (those with a ``house.xml`` or ``spec.json``), by name."""
    if not root.is_dir():
        raise UserError(f"houses folder {root} does not exist; write houses there with objsearch generate --out {root}")
    folders = sorted(
        p
        for p in root.iterdir()
        if p.is_dir() and not p.name.startswith(".") and ((p / "house.xml").exists() or (p / "spec.json").exists())
    )
    if not folders:
        raise UserError(
            f"no houses under {root}: expected folders with house.xml and spec.json, as "
            f"objsearch generate --out {root} writes them"
        )
    return folders


def _check_targets(targets: list[str]) -> list[str]:
    """``targets`` sorted and checked: each must be an object category."""
    import difflib

    objects = [name for name, i in CATEGORY_IDS.items() if i >= FIRST_OBJECT_ID]
    for target in targets:
        if target not in objects:
            close = difflib.get_close_matches(target, objects, n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise UserError(
                f"unknown target category {target!r}; {hint}use object categories of the category "
                "table (objsearch generate writes it to categories.json)"
            )
    return sorted(set(targets))


if __name__ == "__main__":  # the old entry point, gone: say where it went
    raise SystemExit("python -m objsearch.sim.suites is now: objsearch suite rebuild NAME [NAME ...]")
