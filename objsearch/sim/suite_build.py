"""Building the house suite files: the shipped ones from their fixed seeds (``build_suite``,
``objsearch suite rebuild NAME``) and a user's own houses (``suite_from_houses``, ``objsearch
suite make``). Reading them, and what the harness needs of them, is ``objsearch.sim.suites``.

Episodes: ``EPISODES_PER_SPLIT`` per split, house and target drawn uniformly, the start
uniformly among poses 6 to 40 minimal steps from the nearest goal pose (``START_STEPS``);
a new shipped suite is a record in ``objsearch.sim.suites.SHIPPED`` (whose ``recipe`` names
its builder in ``RECIPES``) and its file. What every builder shares (a house's entry, goal
poses, episodes, the file's record) is ``objsearch.sim.suite_record``. Under the ObjectNav protocol (``objsearch.sim.goals.PROTOCOLS``)
goal poses come from its rule, ``min_steps`` counts the STOP and episodes have its step limit;
``objectnav_suite`` makes a paper-protocol suite's episodes into such a suite.
"""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np

from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.sim.goals import PROTOCOLS
from objsearch.sim.house_task import START_STEPS, STARTS, entrance_poses
from objsearch.sim.large_suite import build_tier_suite
from objsearch.sim.rooms_suite import build_rooms_suite
from objsearch.sim.start_rules import MadeRules, far_episodes, far_tables
from objsearch.sim.suite_record import _episodes, _goal_ids, _goal_table, _suite_record, house_entry, steps_range
from objsearch.sim.suites import (
    SHIPPED_SUITES,
    SUITE_NAMES,
    load_house,
    load_houses,
    load_suite_file,
)
from objsearch.sim.world import HouseRef, World

HOUSE_SINGLE_TARGETS = 12  # house-single's target categories (6 seen, 6 unseen)
EPISODES_PER_SPLIT = 100
SUITE_SEED = 20211201
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


def _found_in_half(goals: dict, house_ids: list[str]) -> list[str]:
    """The ``TARGETS`` with goal poses in at least half of the houses ``house_ids``."""
    return sorted(t for t in TARGETS if sum(t in goals[house] for house in house_ids) >= len(house_ids) / 2)


def objectnav_suite(name: str, paper: dict, cache_dir: str | None = None) -> dict:
    """The suite ``name``: the paper-protocol suite ``paper`` (its file's content) under the
    ObjectNav protocol. The same houses, categories, splits and starts; goal poses by the
    ObjectNav rule for the same houses and targets; the episodes whose start reaches one of
    them (in the same order), ``min_steps`` counted again with the STOP."""
    protocol = PROTOCOLS["objectnav"]
    worlds = load_houses(paper)
    goals, ids = {}, {}
    for house, table in paper["goals"].items():
        ids[house] = _goal_ids(worlds[house], sorted(table), cache_dir, protocol.goal_rule)
        goals[house] = {
            t: [list(worlds[house].graph.pose_of(int(g))) for g in found] for t, found in ids[house].items()
        }
    splits = {}
    for split, items in paper["splits"].items():
        splits[split] = []
        for item in items:
            if item["target"] not in ids[item["house"]]:
                continue
            graph = worlds[item["house"]].graph
            moves = int(graph.shortest_steps(ids[item["house"]][item["target"]])[graph.pose_id(*item["start"])])
            if moves >= 0:
                splits[split].append({**item, "min_steps": moves + protocol.stop})
    return _suite_record(
        name, f"{name}-v1", paper["categories"], paper["houses"], paper["training_houses"], goals, splits, protocol
    )


def build_suite(name: str, cache_dir: str | None = None) -> dict:
    """Build a suite from its fixed seeds (renders every pose of its evaluation houses): by
    its recipe (``RECIPES``), or made from the suite it plays under the ObjectNav protocol."""
    if name not in SHIPPED_SUITES:
        raise UserError(f"unknown house suite {name!r}; known: {', '.join(SUITE_NAMES)}")
    shipped = SHIPPED_SUITES[name]
    if shipped.objectnav_of:
        return objectnav_suite(name, load_suite_file(shipped.objectnav_of), cache_dir)
    base = SHIPPED_SUITES[shipped.shuffled_of or name]  # a shuffled suite is made as its base suite, with its draws
    rng = np.random.default_rng([SUITE_SEED, SUITE_NAMES.index(base.name)])
    return RECIPES[base.recipe](name, base.generator, rng, cache_dir)


def _house_single_refs(name: str, gen: str | None, cache_dir) -> tuple[dict, list]:
    """The house of the most target categories among generator seeds 0-9 (medium), passing
    over one where fewer than ``HOUSE_SINGLE_TARGETS`` of them have goal poses in reach of
    starts (never the case for house-single's house); no training houses."""
    candidates = {s: World.load(HouseRef(seed=s, size_class="medium", generator=gen)) for s in range(10)}

    def present(s):
        return len({o.category for o in candidates[s].spec.objects} & set(TARGETS))

    ranked = sorted(candidates, key=lambda s: (-present(s), s))
    seed = next(
        (s for s in ranked if len(_goal_table(candidates[s], TARGETS, cache_dir)) >= HOUSE_SINGLE_TARGETS), None
    )
    if seed is None:
        raise RuntimeError(f"no {name} candidate house has {HOUSE_SINGLE_TARGETS} target categories with goal poses")
    return {"eval": [HouseRef(seed=seed, size_class="medium", generator=gen)]}, []


def _house_single_splits(name: str, worlds: dict, goals: dict, rng) -> tuple[dict, dict]:
    """``HOUSE_SINGLE_TARGETS`` targets of the house, half seen and half unseen, and a split of each."""
    (world,) = worlds["eval"]
    usable = _common_targets(goals, [world])
    picked = [usable[i] for i in sorted(rng.choice(len(usable), size=HOUSE_SINGLE_TARGETS, replace=False))]
    order = rng.permutation(HOUSE_SINGLE_TARGETS)
    categories = {"seen": sorted(picked[i] for i in order[:6]), "unseen": sorted(picked[i] for i in order[6:])}
    by_id = {world.house_id: world}
    return categories, {
        "seen-goals": _episodes(by_id, goals, categories["seen"], EPISODES_PER_SPLIT, rng),
        "unseen-goals": _episodes(by_id, goals, categories["unseen"], EPISODES_PER_SPLIT, rng),
    }


def _house_multi_refs(name: str, gen: str | None, cache_dir) -> tuple[dict, list]:
    """Four seen and four unseen houses (medium); no training houses."""
    return {
        "seen-envs": [HouseRef(seed=s, size_class="medium", generator=gen) for s in (100, 101, 102, 103)],
        "unseen-envs": [HouseRef(seed=s, size_class="medium", generator=gen) for s in (200, 201, 202, 203)],
    }, []


def _house_multi_splits(name: str, worlds: dict, goals: dict, rng) -> tuple[dict, dict]:
    """Six targets common to all the houses, and a split of each set of houses."""
    usable = _common_targets(goals, worlds["seen-envs"] + worlds["unseen-envs"])
    if len(usable) < 6:
        raise RuntimeError(f"only {len(usable)} targets common to all {name} houses: {usable}")
    categories = {"targets": [usable[i] for i in sorted(rng.choice(len(usable), size=6, replace=False))]}
    splits = {}
    for split in ("seen-envs", "unseen-envs"):
        by_id = {w.house_id: w for w in worlds[split]}
        splits[split] = _episodes(by_id, goals, categories["targets"], EPISODES_PER_SPLIT, rng)
    return categories, splits


def _house_gen_refs(name: str, gen: str | None, cache_dir) -> tuple[dict, list]:
    """40 training houses, 10 validation and 10 test houses generated as test houses."""
    return {
        "val": [HouseRef(seed=s, split="test", generator=gen) for s in range(2000, 2010)],
        "test": [HouseRef(seed=s, split="test", generator=gen) for s in range(3000, 3010)],
    }, [HouseRef(seed=s, generator=gen) for s in range(1000, 1040)]


def _house_gen_splits(name: str, worlds: dict, goals: dict, rng) -> tuple[dict, dict]:
    """Targets found in at least half of the evaluation houses (an episode's house always has
    its target), a third of them (at least 3) unseen; seen and unseen splits of both parts."""
    evaluated = worlds["val"] + worlds["test"]
    usable = _found_in_half(goals, [w.house_id for w in evaluated])
    order = rng.permutation(len(usable))
    unseen_count = max(3, len(usable) // 3)
    categories = {
        "seen": sorted(usable[i] for i in order[unseen_count:]),
        "unseen": sorted(usable[i] for i in order[:unseen_count]),
    }
    splits = {}
    for part in ("val", "test"):
        by_id = {w.house_id: w for w in worlds[part]}
        for kind in ("seen", "unseen"):
            splits[f"{part}-{kind}"] = _episodes(by_id, goals, categories[kind], EPISODES_PER_SPLIT, rng)
    return categories, splits


def _common_targets(goals: dict, worlds: list[World]) -> list[str]:
    """The targets with goal poses in every house of ``worlds``, sorted."""
    return sorted(set.intersection(*(set(goals[w.house_id]) for w in worlds)))


def _house_recipe(pick, draw):
    """A recipe of generated houses: ``pick(name, generator, cache_dir)`` picks the evaluation
    houses by part and the training houses, ``draw(name, worlds, goals, rng)`` the categories and
    splits. A shuffled suite's houses are its base suite's with their objects shuffled."""

    def build(name: str, gen: str | None, rng: np.random.Generator, cache_dir) -> dict:
        eval_refs, train_refs = pick(name, gen, cache_dir)
        if SHIPPED_SUITES[name].shuffled_of:  # the same houses, their objects shuffled
            eval_refs = {key: [replace(r, placement="shuffled") for r in refs] for key, refs in eval_refs.items()}
            train_refs = [replace(r, placement="shuffled") for r in train_refs]
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
        categories, splits = draw(name, worlds, goals, rng)
        return _suite_record(name, f"{name}-v1", categories, houses, training, goals, splits)

    return build


# How each recipe (``ShippedSuite.recipe``) builds a suite: (name, generator, rng, cache_dir) -> the file's content
RECIPES = {
    "house-single": _house_recipe(_house_single_refs, _house_single_splits),
    "house-multi": _house_recipe(_house_multi_refs, _house_multi_splits),
    "house-gen": _house_recipe(_house_gen_refs, _house_gen_splits),
    # single functional rooms, the paper's AI2-THOR protocol
    "rooms": lambda name, gen, rng, cache_dir: build_rooms_suite(name, f"{name}-v1", rng, cache_dir),
    # the large-house tier and its sweep: a tier's placements are drawn together
    "house-large": lambda name, gen, rng, cache_dir: build_tier_suite(name, cache_dir),
}


def suite_from_houses(
    houses_dir: str | os.PathLike,
    out: str | os.PathLike,
    targets: list[str] | None = None,
    episodes: int = EPISODES_PER_SPLIT,
    seed: int = 0,
    cache_dir: str | None = None,
    starts: str = "anywhere",
    protocol: str = "paper",
    rules: MadeRules | None = None,
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
    entrance (``objsearch.sim.house_task.draw_start``; the file then records ``"starts": "entrance"``);
    a house without an entrance (``house-gen-1``) is a ``UserError`` before anything is rendered.

    ``protocol``: ``paper`` (default) or ``objectnav`` (``objsearch.sim.goals.PROTOCOLS``): its
    goal rule picks the goal poses, its step limit is the file's, and under ``objectnav``
    ``min_steps`` counts the STOP; the file records it (only when not ``paper``).

    ``rules`` (``start_rules.MadeRules``; None: none): the large-house tier's rules for the file, where set: the goal
    rule's pixels and distance (ObjectNav), far starts (walking metres and doors from the
    target: then drawn uniformly among every pose that meets them, not ``START_STEPS``), the
    step limit and the standard seeds."""
    if starts not in STARTS:
        raise UserError(f"unknown starts {starts!r}; use one of {', '.join(STARTS)}")
    if protocol not in PROTOCOLS:
        raise UserError(f"unknown protocol {protocol!r}; use one of {', '.join(PROTOCOLS)}")
    made = rules or MadeRules()
    rules = made.protocol(PROTOCOLS[protocol])
    if made.far and starts != "anywhere":
        raise UserError(
            f"--starts {starts} and far starts (--min-distance, --min-room-hops) exclude each other; give one"
        )
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
    if made.far:
        tables, far = far_tables(worlds, wanted, cache_dir, rules.goal_rule, made)
    else:
        tables = {house: _goal_table(world, wanted, cache_dir, rules.goal_rule) for house, world in worlds.items()}
    if targets:
        for target in wanted:
            if not any(target in table for table in tables.values()):
                where = made.describe() if made.far else f"{START_STEPS[0]}-{START_STEPS[1]} steps"
                raise UserError(
                    f"target {target!r} has no goal pose with a start {where} from it in any house under "
                    f"{root}; drop it from --targets"
                )
    else:
        wanted = _found_in_half(tables, list(worlds))
        if not wanted:
            raise UserError(
                f"no target category has goal poses in at least half of the houses under {root}; "
                "name the targets with --targets"
            )
    goals = {house: {t: poses for t, poses in table.items() if t in wanted} for house, table in tables.items()}
    rng = np.random.default_rng(seed)
    if made.far:
        drawn = far_episodes(worlds, far, wanted, episodes, rng, rules.stop)
        start_steps = steps_range(drawn, rules.stop)
        limit, longest = made.max_steps or rules.max_steps, start_steps[1] + rules.stop
        if longest > limit:
            raise UserError(
                f"a start drawn {made.describe()} from its target needs {longest} steps, past the step limit "
                f"{limit}: raise --max-steps or lower --min-distance / --min-room-hops"
            )
    else:
        drawn, start_steps = _episodes(worlds, goals, wanted, episodes, rng, starts, rules.stop), START_STEPS
    return _suite_record(
        Path(out).stem,
        None,
        {"targets": wanted},
        houses,
        {},
        goals,
        {Path(out).stem: drawn},
        rules,
        starts,
        max_steps=made.max_steps,
        start_steps=start_steps,
        seeds=made.seeds,
    )


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
