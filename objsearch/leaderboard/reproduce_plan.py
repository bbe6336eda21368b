"""The plan of ``objsearch reproduce`` (``reproduce.py``): a table, or a suite and methods,
turned into steps (``Step``), each with its output and the ids of the steps it needs.

A training run's recipe is the ``command.txt`` shipped beside its checkpoint (of its seed,
else seed 0's with the seed changed), or the agent's default; a ``--set`` naming a file of
another run (``pretrained``, ``explorer``) makes that run a step it needs. A run trained on
the perception network's predictions (observation ``predicted_trained``, the paper's setting)
is its own run, in the ``predicted/`` folder of the agent's seed-0 run, with the recipe
shipped there; Table 3 plans it for the methods that ship one.
"""

from __future__ import annotations

import argparse
import re
import shlex
from dataclasses import dataclass, field, replace
from pathlib import Path

from objsearch.errors import UserError

WORK = "build/reproduce"  # the work folder without --out (results, step records, the table)
GT_ONLY = ("random",)  # ignores what it sees: its gt row serves both observations (so do privileged agents')
# --config tiny: a test-sized run (seconds a step); training budgets by world, then config fields set where the agent has them
TINY = {"runs": 1, "budget": {"house": 2000, "gridworld": 50}, "max_steps": 10, "verify_episodes": 5}
TINY_FIELDS = {"pretrain_steps": 1000, "pretrain_episodes": 20}
# a file of another training run named by a recipe's --set: in the shipped folders, or in runs/ as `objsearch train` names them
RUN_FILE = (
    re.compile(
        r"(?:.*/)?agents/checkpoints/(?P<suite>[^/]+)/(?P<agent>[^/]+)/(?:seed(?P<seed>\d+)/)?"
        r"(?:(?P<variant>predicted)/)?(?P<rest>.+)"
    ),
    re.compile(r"runs/(?P<suite>[^/]+)/(?P<agent>[^/]+)-seed(?P<seed>\d+)/(?P<rest>.+)"),
)
OBSERVATIONS = ("gt", "predicted", "predicted_trained")  # predicted_trained: trained on the predictions too
PREDICTED_RUN = "predicted"  # the folder of a run trained on predictions, in its agent's seed-0 run


@dataclass(frozen=True)
class Table:
    """What one of the paper's tables holds: its heading in ``paper_tables.md``, suites,
    methods (``baseline``: rows the others are read against) and observations."""

    heading: str
    suites: tuple[str, ...]
    methods: tuple[str, ...]
    observations: tuple[str, ...]
    baseline: tuple[str, ...] = ()
    greedy: bool = False  # also each learned method played greedily (``<method>_greedy``), as the grid tables show


def tables() -> dict[str, Table]:
    """The paper's Tables 1-4, from the leaderboard's own declarations of them."""
    from objsearch.leaderboard.paper import GRIDWORLD_TABLES, HOUSE3D_SPLITS, HOUSE3D_TABLE
    from objsearch.leaderboard.table4 import ROOMS_SUITE, TABLE4_METHODS

    grid = list(GRIDWORLD_TABLES.values())
    house3d = tuple(dict.fromkeys(suite for suite, _ in HOUSE3D_SPLITS))
    return {
        "table1": Table("## Table 1", ("gridworld",), grid[0], ("gt",), greedy=True),
        "table2": Table("## Table 2", ("gridworld",), grid[1], ("gt",), greedy=True),
        "table3": Table("## Table 3", house3d, HOUSE3D_TABLE, OBSERVATIONS),
        "table4": Table("## Table 4", (ROOMS_SUITE,), TABLE4_METHODS, ("gt", "predicted"), ("random",)),
    }


@dataclass
class Step:
    """One step of a plan: ``kind`` (train, eval, add, verify, render), ``name``, the ids of
    the steps it ``needs``, and its arguments (plain data: they travel to Ray workers)."""

    kind: str
    name: str
    needs: list[str] = field(default_factory=list)
    args: dict = field(default_factory=dict)

    @property
    def id(self) -> str:
        """``kind name``, e.g. ``train rooms/a3c/seed0``."""
        return f"{self.kind} {self.name}"


@dataclass
class Plan:
    """The steps of a reproduction in an order that runs each after those it needs."""

    title: str
    steps: list[Step]
    checkpoints: Path
    shipped: Path
    leaderboard: Path
    work: Path

    def record(self, step: Step) -> Path:
        """The record a finished step leaves (its wall time): ``WORK/steps/<kind>-<name>.json``."""
        return self.work / "steps" / f"{step.kind}-{step.name.replace('/', '-')}.json"


def _pick(table: str | None, suite: str | None, methods: tuple | None) -> tuple[str, Table]:
    """The title and ``Table`` that TABLE, ``--suite`` and ``--methods`` name."""
    from objsearch.eval.registry import resolve_agent
    from objsearch.eval.suites import SUITES

    if suite is not None and suite not in SUITES:
        raise UserError(f"--suite {suite}: unknown suite; choose one of {', '.join(SUITES)}")
    if table is None:
        if suite is None or not methods:
            raise UserError(
                "name a table (objsearch reproduce table4), or a suite and methods: --suite rooms --methods a3c"
            )
        for method in methods:
            resolve_agent(method)  # unknown agent: a UserError that names it and the fix
        return f"{suite}: {', '.join(methods)}", Table("", (suite,), methods, ("gt",))
    known = tables()
    key = re.sub(r"[\s_-]", "", table.lower())
    key = f"table{key}" if key.isdigit() else key
    if key not in known:
        raise UserError(
            f"unknown table {table!r}; choose one of {', '.join(known)} (the paper's Tables 1-4), or pass --suite and --methods"
        )
    chosen = known[key]
    if suite is not None and suite not in chosen.suites:
        raise UserError(
            f"--suite {suite} is not in {key} (its suites: {', '.join(chosen.suites)}); drop --suite or pick one of those"
        )
    unknown = [m for m in methods or () if m not in chosen.methods + chosen.baseline]
    if unknown:
        raise UserError(
            f"--methods {','.join(unknown)}: not in {key} (its methods: {', '.join(chosen.methods)}); pick some of those"
        )
    picked = tuple(m for m in chosen.baseline + chosen.methods if not methods or m in methods or m in chosen.baseline)
    return key, replace(chosen, suites=(suite,) if suite else chosen.suites, methods=tuple(dict.fromkeys(picked)))


def make_plan(args: argparse.Namespace) -> Plan:
    """The plan for the parsed ``objsearch reproduce`` arguments (``UserError`` for bad input)."""
    import importlib.util

    from objsearch.eval.registry import is_privileged, registered_agents
    from objsearch.eval.suites import suite_world

    title, table = _pick(args.table, args.suite, args.methods)
    tiny = args.config == "tiny"
    if tiny and args.out is None:
        raise UserError(
            "--config tiny makes test-sized checkpoints and entries: pass --out DIR to keep them apart from the shipped ones"
        )
    observations = args.observations or (("gt",) if tiny else table.observations)
    bad = [o for o in observations if o not in OBSERVATIONS]
    if bad:
        raise UserError(f"--observations {','.join(bad)}: choose some of {', '.join(OBSERVATIONS)}")
    shipped = Path(importlib.util.find_spec("objsearch_agents").submodule_search_locations[0]) / "checkpoints"
    out = Path(args.out).resolve() if args.out else None
    plan = Plan(
        title,
        [],
        out / "checkpoints" if out else shipped,
        shipped,
        Path(args.leaderboard or (out / "leaderboard" if out else "leaderboard")).resolve(),
        out or Path(WORK).resolve(),
    )
    agents = registered_agents()
    for suite in table.suites:
        world = suite_world(suite)
        runs = args.runs or (TINY["runs"] if tiny else 1 if world == "gridworld" else 3)
        if runs > 1 and world == "gridworld":
            raise UserError(
                "grid-world agents are evaluated from one training run (their checkpoint folder); pass --runs 1"
            )
        budget = args.train_budget or (TINY["budget"][world] if tiny else None)
        train = _Trainer(plan, world, budget, list(args.train_set), tiny)
        evals = []
        for method in table.methods:
            base = method.removesuffix("_greedy") if method.removesuffix("_greedy") in agents else method
            needs = [train.need(suite, base, k) for k in range(runs)] if _trainable(base) else []
            greedy = [f"{method}_greedy"] if table.greedy and f"{method}_greedy" in agents and needs else []
            for name in [method, *greedy]:
                for observation in ("gt",) if name in GT_ONLY or is_privileged(name) else observations:
                    runs_of = needs
                    if observation == "predicted_trained":
                        if not needs or not _recipe_file(plan.shipped, suite, base, 0, PREDICTED_RUN).is_file():
                            continue  # no run of it on predictions is shipped: no recipe to reproduce
                        runs_of = [train.need(suite, base, 0, PREDICTED_RUN)]
                    evals.append(_entry_steps(plan, args, suite, name, observation, runs_of, base, tiny))
        plan.steps += train.steps + [step for steps in evals for step in steps]
    verified = [s.id for s in plan.steps if s.kind == "verify"]
    render = {
        "leaderboard": str(plan.leaderboard),
        "heading": table.heading,
        "table": str(plan.work / f"{title.split(':')[0]}.md"),
    }
    plan.steps.append(Step("render", title.split(":")[0], verified, render))
    return plan


def _trainable(agent: str) -> bool:
    """Whether ``agent`` is learned: it has a ``train`` hook and does not declare itself training-free."""
    from objsearch.eval.registry import is_training_free, resolve_agent

    return not is_training_free(agent) and callable(getattr(resolve_agent(agent), "train", None))


def run_folder(root: Path, suite: str, agent: str, seed: int, variant: str = "") -> Path:
    """A training run's folder: ``ROOT/SUITE/AGENT`` for seed 0, ``.../seedK`` for the others;
    a run trained on predictions (``variant`` ``predicted``) in that folder's ``predicted/``."""
    return root / suite / agent / (f"seed{seed}" if seed else "") / variant


class _Trainer:
    """The training steps of one suite's plan, with the runs they need (added first)."""

    def __init__(self, plan: Plan, world: str, budget: int | None, overrides: list, tiny: bool):
        self.plan, self.world, self.budget, self.overrides, self.tiny = plan, world, budget, overrides, tiny
        self.steps: list[Step] = []

    def need(self, suite: str, agent: str, seed: int, variant: str = "") -> str:
        """The id of the step that trains ``agent``'s run ``seed`` (of ``variant``) on ``suite``, planned if new."""
        name = f"{suite}/{agent}/{variant or f'seed{seed}'}"
        if any(s.name == name for s in self.steps):
            return f"train {name}"
        recipe, source = _recipe(self.plan.shipped, suite, agent, seed, variant)
        needs, overrides = [], {}
        for key, value in recipe.overrides:
            ref = next((m for m in (p.fullmatch(value) for p in RUN_FILE) if m), None)
            # another run's file: that run (of this run's seed, if the recipe is seed 0's)
            if ref and key in ("pretrained", "explorer"):
                of = int(ref["seed"] or 0)
                of = seed if of == recipe.seed else of
                of_variant = ref.groupdict().get("variant") or ""
                needs.append(self.need(ref["suite"], ref["agent"], of, of_variant))
                value = str(run_folder(self.plan.checkpoints, ref["suite"], ref["agent"], of, of_variant) / ref["rest"])
            overrides[key] = value
        if self.tiny:
            overrides |= _tiny_fields(agent, suite, self.budget)
        overrides |= dict(self.overrides)
        budget = {"steps": recipe.steps, "episodes": recipe.episodes}
        if self.budget is not None:
            budget = (
                {"steps": self.budget, "episodes": None}
                if self.world == "house"
                else {"steps": None, "episodes": self.budget}
            )
        out = run_folder(self.plan.checkpoints, suite, agent, seed, variant)
        argv = (
            ["--agent", agent, "--suite", suite, "--seed", str(seed)]
            + [x for key in ("steps", "episodes") if budget[key] for x in (f"--{key}", str(budget[key]))]
            + [x for kv in overrides.items() for x in ("--set", "=".join(kv))]
            + ["--out", str(out)]
        )
        args = {"agent": agent, "suite": suite, "seed": seed, "variant": variant, "out": str(out)}
        args["overrides"] = list(overrides.items())
        args |= {**budget, "argv": argv, "command": "objsearch train " + shlex.join(argv), "recipe": source}
        self.steps.append(Step("train", name, needs, args))
        return f"train {name}"


@dataclass
class _Recipe:
    seed: int
    steps: int | None
    episodes: int | None
    overrides: list


def _recipe_file(shipped: Path, suite: str, agent: str, seed: int, variant: str = "") -> Path:
    """Where the shipped recipe of a training run lies (whether or not it is there)."""
    return run_folder(shipped, suite, agent, seed, variant) / "command.txt"


def _recipe(shipped: Path, suite: str, agent: str, seed: int, variant: str = "") -> tuple[_Recipe, str]:
    """The shipped recipe of ``agent``'s run ``seed`` (of ``variant``) on ``suite`` (its
    ``command.txt``, else seed 0's), and where it came from; the agent's default recipe if
    none is shipped."""
    from objsearch.train import add_parser as train_parser

    for command, of_seed in (
        (_recipe_file(shipped, suite, agent, seed, variant), seed),
        (_recipe_file(shipped, suite, agent, 0, variant), 0),
    ):
        lines = (
            [line for line in command.read_text().splitlines() if line.startswith("objsearch train")]
            if command.is_file()
            else []
        )
        if lines:
            parser = argparse.ArgumentParser(prog="objsearch", add_help=False)
            train_parser(parser.add_subparsers())
            parsed = parser.parse_args(shlex.split(lines[0])[1:])
            return _Recipe(of_seed, parsed.steps, parsed.episodes, parsed.overrides), str(command)
    return _Recipe(seed, None, None, []), f"{agent}'s default recipe (no command.txt is shipped for {suite})"


def agent_config(agent: str, suite: str):
    """The training config (a dataclass) ``agent`` trains with on ``suite``'s world by
    default; None if its class shows none."""
    import dataclasses

    from objsearch.eval.registry import resolve_agent
    from objsearch.eval.suites import suite_world

    cls = resolve_agent(agent)
    owner = cls.house if suite_world(suite) == "house" and getattr(cls, "house", None) else cls
    config = getattr(owner, "config", None)
    return config if dataclasses.is_dataclass(config) else None


def _tiny_fields(agent: str, suite: str, budget: int) -> dict:
    """``--config tiny``'s training fields that ``agent``'s config has for ``suite``: short
    pretraining, a log row and a checkpoint within the budget."""
    config = agent_config(agent, suite)
    wanted = {**TINY_FIELDS, "log_every": max(1, budget // 2), "checkpoint_every": budget}
    return {key: str(value) for key, value in wanted.items() if hasattr(config, key)}


def _entry_steps(
    plan: Plan, args, suite: str, name: str, observation: str, needs: list, base: str, tiny: bool
) -> list[Step]:
    """The eval, add and verify steps of the entry ``name`` (with ``_predicted`` for predicted
    observations, ``_predicted_trained`` for a run trained on them: its checkpoint named)."""
    from objsearch.eval.suites import make_suite, standard_seeds, suite_world
    from objsearch.leaderboard.paper import PREDICTED_SUFFIX, TRAINED_ON_PREDICTED_SUFFIX

    suffix = {"predicted": PREDICTED_SUFFIX, "predicted_trained": TRAINED_ON_PREDICTED_SUFFIX}
    entry = name + suffix.get(observation, "")
    suite_config = {"observation": "predicted"} if observation != "gt" else {}
    max_steps = args.max_steps or (TINY["max_steps"] if tiny else None)
    if max_steps:
        suite_config["max_steps"] = max_steps
    available = list(make_suite(suite).splits)
    unknown = [split for split in args.splits or () if split not in available]
    if unknown:
        raise UserError(f"--splits {','.join(unknown)}: not a split of {suite} (its splits: {', '.join(available)})")
    splits = args.splits or (available[:1] if tiny else ())
    seeds = args.seeds or (standard_seeds(suite)[:1] if tiny else standard_seeds(suite))
    # house agents find their runs under the plan's checkpoints (CHECKPOINTS_ENV, set by the step); the grid
    # world's agents load the one run they are given
    checkpoint = (
        str(run_folder(plan.checkpoints, suite, base, 0, PREDICTED_RUN))
        if observation == "predicted_trained"
        else None
        if plan.checkpoints == plan.shipped or not needs or suite_world(suite) == "house"
        else str(run_folder(plan.checkpoints, suite, base, 0) / "policy.pt")
    )
    results = plan.work / "results" / suite / f"{entry}.json"
    stored = plan.leaderboard / "submissions" / suite / f"{entry}.json"
    config = {"agent": name, "suite": suite, "splits": list(splits), "seeds": list(seeds), "checkpoint": checkpoint}
    common = {"leaderboard": str(plan.leaderboard), "results": str(results), "entry": entry, "stored": str(stored)}
    common["checkpoints"] = None if plan.checkpoints == plan.shipped else str(plan.checkpoints)
    key = f"{suite}/{entry}"
    # the add step's record says which stored content the plan wrote: only that, it may replace unasked
    added = {"replace": bool(getattr(args, "replace", False)), "record": str(plan.record(Step("add", key)))}
    return [
        Step(
            "eval",
            key,
            needs,
            {**config, "suite_config": suite_config, "batch": args.batch, "results": str(results)}
            | {"checkpoints": common["checkpoints"]},
        ),
        Step("add", key, [f"eval {key}"], common | added),
        Step(
            "verify",
            key,
            [f"add {key}"],
            {**common, "episodes": args.verify_episodes or (TINY["verify_episodes"] if tiny else None)},
        ),
    ]
