"""The checks of a submission (``check_submission``): its fields' types (``results_schema``), its
schema version, that its suite and episode-set version are the benchmark's own, that it covers
every split of the suite with its standard seeds unless it is marked partial, that every
episode of its splits, seeds and training runs is present exactly once, none ended in an
agent error, each matches the suite's episode, and its summaries equal those recomputed from
its records; and which of its suite settings are not the suite's standard."""

from __future__ import annotations

import functools
import json
import math
from collections import Counter

from objsearch.errors import UserError
from objsearch.eval.metrics import episode_spl, summarize
from objsearch.eval.results import SCHEMA_VERSION
from objsearch.eval.suites import SUITES, make_suite, standard_seeds
from objsearch.leaderboard.results_schema import REQUIRED, type_problems

TOLERANCE = 1e-4  # summaries are rounded to 4 decimals
# suite options that say where objsearch writes, never what an episode is: a submission's are
# ignored (verify builds its caches where the verifier's settings say, never where a file says)
WRITE_OPTIONS = ("cache_dir",)
# suite options that say what the agent observed (shown in the observation column): the only
# ones a ranked entry may set to other than the suite's standard
OBSERVATION_OPTIONS = ("observation", "perception", "perception_key")


def _differs(a, b) -> bool:
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() != b.keys() or any(_differs(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) != len(b) or any(_differs(x, y) for x, y in zip(a, b))
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return not math.isclose(a, b, abs_tol=TOLERANCE)
    return a != b


@functools.lru_cache(maxsize=64)
def _suite(name: str, suite_config: str):
    """The suite and its episodes by split and id (built once per process: stored entries share
    suites; a house suite's houses are not loaded: ``HousePath``)."""
    suite = make_suite(name, **json.loads(suite_config))
    return suite, {split: {ep.episode_id: ep for ep in suite.episodes(split)} for split in suite.splits}


def check_submission(results: dict) -> list[str]:
    """Every problem that keeps ``results`` off the leaderboard (empty when it is valid)."""
    missing = [key for key in REQUIRED if key not in results]
    if missing:
        return [f"missing field(s) {', '.join(missing)}: not a results JSON of objsearch-eval"]
    problems = type_problems(results)
    if problems:
        return problems
    if results["config"].get("episodes") is not None:
        return [
            f"played only the first {results['config']['episodes']} episodes of each split (objsearch-eval "
            "--episodes): a quick look, not a result; evaluate without --episodes to add it"
        ]
    if results["schema_version"] != SCHEMA_VERSION:
        return [f"schema_version {results['schema_version']!r} is not the supported {SCHEMA_VERSION}"]
    suite_name = results["suite"]
    if suite_name not in SUITES:
        return [f"unknown suite {suite_name!r}"]
    config = results["config"]
    if (config["agent"], config["suite"]) != (results["agent"], suite_name):
        return [
            f"agent {results['agent']!r} on {suite_name!r} is not the config's {config['agent']!r} on {config['suite']!r}"
        ]
    try:
        suite, episodes = _suite(
            suite_name, json.dumps(playable_config(config.get("suite_config", {})), sort_keys=True)
        )
    except (UserError, TypeError, ValueError) as err:
        return [f"suite configuration {config.get('suite_config')!r} is not valid: {err}"]
    if results.get("protocol", "paper") != suite.protocol:  # results before protocols existed: the paper's
        return [f"protocol {results.get('protocol', 'paper')!r} is not the suite's {suite.protocol!r}"]
    if results["episode_set_version"] != suite.episode_set_version:
        return [
            f"episode set {results['episode_set_version']!r} is not the suite's current {suite.episode_set_version!r}"
        ]
    if results["episode_set_version"].startswith("custom:"):
        return ["custom maps/tasks are not a leaderboard episode set; evaluate on the suite's own splits"]
    splits = config["splits"]
    seeds = results["seeds"]
    if config["seeds"] != seeds:
        return [f"seeds {seeds} differ from the config's {config['seeds']}"]
    unknown = [s for s in splits if s not in suite.splits]
    if unknown or not splits:
        return [f"splits {unknown or splits} are not splits of {suite_name} ({', '.join(suite.splits)})"]
    if sorted(results["splits"]) != sorted(splits):
        return [f"summary splits {sorted(results['splits'])} differ from the config's {sorted(splits)}"]
    wanted = standard_seeds(suite_name)
    full = sorted(splits) == sorted(suite.splits) and sorted(seeds) == sorted(wanted)
    standard = f"every split of {suite_name} ({', '.join(suite.splits)}) with seeds {','.join(map(str, wanted))}"
    if not full and not results.get("partial", False):
        return [
            f"covers splits {', '.join(splits)} with seeds {','.join(map(str, seeds))}, not {standard}; "
            "evaluate with objsearch-eval's default splits and seeds, or add it with --partial (shown apart, not ranked)"
        ]
    if full and results.get("partial", False):
        return [f"is marked partial but covers {standard}; add it without --partial"]
    differing = nonstandard_settings(results)
    if differing and not results.get("partial", False):
        return [
            f"suite settings {', '.join(differing)} differ from {suite_name}'s standard: entries made under other "
            "rules are not ranked; evaluate with the suite's own settings, or add it with --partial "
            "(shown apart with its settings named, not ranked)"
        ]

    problems = _run_problems(results)
    if problems:
        return problems
    runs = played_runs(results)
    expected = {(split, seed, i, run) for split in splits for seed in seeds for i in episodes[split] for run in runs}
    keys = Counter(_unit(r) for r in results["episodes"])
    duplicated = [k for k, n in keys.items() if n > 1]
    absent = expected - set(keys)
    extra = set(keys) - expected
    for label, units in (("missing", absent), ("duplicated", duplicated), ("unexpected", extra)):
        if units:
            shown = ", ".join(_where(unit) for unit in sorted(units, key=str)[:3])
            problems.append(f"{len(units)} {label} episode(s), e.g. {shown}")
    if problems:
        return problems
    failed = [r for r in results["episodes"] if r.get("error")]
    if failed:
        first = failed[0]
        return [
            f"{len(failed)} episode(s) ended in an agent error, e.g. {first['split']}/seed {first['seed']}/"
            f"{first['episode_id']}: {first['error']}; a run that did not run is not a result"
        ]
    limit = getattr(suite, "max_steps", None)
    for r in results["episodes"]:
        ep = episodes[r["split"]][r["episode_id"]]
        where = f"episode {r['split']}/seed {r['seed']}/{r['episode_id']}"
        if r["min_steps"] != ep.min_steps or r["task"] != ep.describe or r["goal"] != ep.goal_name:
            problems.append(f"{where} does not match the suite's episode (task, goal or min_steps changed)")
        elif r["steps"] < 0 or (limit is not None and r["steps"] > limit):
            bound = "" if limit is None else f"..{limit}"
            problems.append(f"{where}: {r['steps']} steps, not within the suite's step limit 0{bound}")
        elif r.get("spl") is not None and _differs(r["spl"], episode_spl(r["success"], r["min_steps"], r["steps"])):
            problems.append(f"{where}: spl {r['spl']} does not follow from its success and steps")
        elif r["success"] and r["steps"] < r["min_steps"]:
            problems.append(f"{where}: succeeded in {r['steps']} steps, fewer than the minimal {r['min_steps']}")
        if len(problems) >= 3:
            break
    if problems:
        return problems
    summaries = [("", results["splits"], lambda r: True)] + [
        (
            f"training run {run['seed']}, ",
            run["splits"],
            lambda r, seed=run["seed"]: r.get("training_run", seed) == seed,
        )
        for run in results.get("training_runs", [])
    ]
    for where, stored, of_it in summaries:
        if sorted(stored) != sorted(splits):
            problems.append(f"{where}summary splits {sorted(stored)} differ from the config's {sorted(splits)}")
            continue
        for split in splits:
            recomputed = summarize([r for r in results["episodes"] if r["split"] == split and of_it(r)])
            if _differs(stored[split], recomputed):
                fields = [k for k in recomputed if _differs(stored[split].get(k), recomputed[k])]
                problems.append(
                    f"{where}split {split}: summary ({', '.join(fields)}) differs from the one recomputed from its episodes"
                )
    return problems


def playable_config(suite_config: dict) -> dict:
    """A submission's ``suite_config`` without the options that say where objsearch writes
    (``WRITE_OPTIONS``): a submission never chooses the folders a check or replay writes to."""
    return {k: v for k, v in suite_config.items() if k not in WRITE_OPTIONS}


def nonstandard_settings(results: dict) -> list[str]:
    """The suite settings of ``results`` that differ from its suite's standard ones, as
    ``name=value (standard: value)``: every option of the suite's config but what the agent
    observed (``OBSERVATION_OPTIONS``) and where objsearch writes (``WRITE_OPTIONS``).
    ``results`` must have passed ``check_submission``'s checks up to its suite."""
    given = playable_config(results["config"].get("suite_config", {}))
    suite, _ = _suite(results["suite"], json.dumps(given, sort_keys=True))
    standard, _ = _suite(results["suite"], "{}")
    ignored = (*OBSERVATION_OPTIONS, *WRITE_OPTIONS)
    mine, theirs = suite.config(), standard.config()
    return [
        f"{key}={json.dumps(mine.get(key))} (standard: {json.dumps(theirs.get(key))})"
        for key in sorted(set(mine) | set(theirs))
        if key not in ignored and mine.get(key) != theirs.get(key)
    ]


def played_runs(results: dict) -> list:
    """The training seeds whose records ``results`` holds: [None] for a single run, whose
    records carry no ``training_run``."""
    runs = results.get("training_runs", [])
    return [run["seed"] for run in runs] if len(runs) > 1 else [None]


def _unit(record: dict) -> tuple:
    return record["split"], record["seed"], record["episode_id"], record.get("training_run")


def _where(unit: tuple) -> str:
    run = "" if unit[3] is None else f" of training run {unit[3]}"
    return f"{unit[0]}/seed {unit[1]}/episode {unit[2]}{run}"


def _run_problems(results: dict) -> list[str]:
    """How ``training_runs`` disagrees with the config and the records, if it does."""
    runs = results.get("training_runs", [])
    seeds = [run["seed"] for run in runs]
    if len(set(seeds)) != len(seeds):
        return [f"training_runs names a training seed twice ({seeds})"]
    config = results["config"]
    if len(runs) > 1 and (config.get("weights_sha256") or config.get("checkpoint") or "training_run" in config):
        return ["a result of several training runs names no checkpoint, weights or training_run in its config"]
    if len(runs) == 1 and runs[0]["weights_sha256"] != config.get("weights_sha256"):
        return ["training_runs[0] names other weights than the config"]
    if "training_run" in config and seeds != [config["training_run"]]:
        return [f"the config's training_run {config['training_run']} is not the one run of training_runs {seeds}"]
    tagged = {r.get("training_run") for r in results["episodes"]}
    if tagged != (set(seeds) if len(runs) > 1 else {None}):
        return [
            f"the records' training runs {sorted(tagged, key=str)} are not those of training_runs "
            f"({seeds if len(runs) > 1 else 'none: one run'})"
        ]
    return []
