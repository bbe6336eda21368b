"""Checking a submission (a results JSON from ``objsearch-eval``) before it is trusted.

A submission passes when its schema version is known, its suite and episode-set version
are the benchmark's own, every episode of its splits and seeds is present exactly once,
none ended in an agent error, each matches the suite's episode, and its summary equals the
one recomputed from its records.
"""

from __future__ import annotations

import json
import math
from collections import Counter
from pathlib import Path

from objsearch.errors import UserError
from objsearch.eval.metrics import episode_spl, summarize
from objsearch.eval.results import SCHEMA_VERSION
from objsearch.eval.runner import plan_units
from objsearch.eval.suites import SUITES, make_suite

REQUIRED = ("schema_version", "agent", "suite", "episode_set_version", "objsearch_version", "seeds", "config", "splits", "episodes")
TOLERANCE = 1e-4  # summaries are rounded to 4 decimals


def load_submission(path: str | Path) -> dict:
    path = Path(path)
    try:
        data = json.loads(path.read_text())
    except OSError as err:
        raise UserError(f"cannot read submission {path}: {err.strerror}") from None
    except json.JSONDecodeError as err:
        raise UserError(f"submission {path} is not JSON: {err}") from None
    if not isinstance(data, dict):
        raise UserError(f"submission {path} is not a results object from objsearch-eval")
    return data


def _differs(a, b) -> bool:
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() != b.keys() or any(_differs(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) != len(b) or any(_differs(x, y) for x, y in zip(a, b))
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        return not math.isclose(a, b, abs_tol=TOLERANCE)
    return a != b


def check_submission(results: dict) -> list[str]:
    """Every problem that keeps ``results`` off the leaderboard (empty when it is valid)."""
    missing = [key for key in REQUIRED if key not in results]
    if missing:
        return [f"missing field(s) {', '.join(missing)}: not a results JSON of objsearch-eval"]
    if results["schema_version"] != SCHEMA_VERSION:
        return [f"schema_version {results['schema_version']!r} is not the supported {SCHEMA_VERSION}"]
    suite_name = results["suite"]
    if suite_name not in SUITES:
        return [f"unknown suite {suite_name!r}"]
    config = results["config"]
    try:
        suite = make_suite(suite_name, **config.get("suite_config", {}))
    except (UserError, TypeError) as err:
        return [f"suite configuration {config.get('suite_config')!r} is not valid: {err}"]
    if results["episode_set_version"] != suite.episode_set_version:
        return [
            f"episode set {results['episode_set_version']!r} is not the suite's current {suite.episode_set_version!r}"
        ]
    if results["episode_set_version"].startswith("custom:"):
        return ["custom maps/tasks are not a leaderboard episode set; evaluate on the suite's own splits"]
    splits = list(config.get("splits", []))
    seeds = results["seeds"]
    if list(config.get("seeds", [])) != list(seeds):
        return [f"seeds {seeds} differ from the config's {config.get('seeds')}"]
    unknown = [s for s in splits if s not in suite.splits]
    if unknown or not splits:
        return [f"splits {unknown or splits} are not splits of {suite_name} ({', '.join(suite.splits)})"]
    if sorted(results["splits"]) != sorted(splits):
        return [f"summary splits {sorted(results['splits'])} differ from the config's {sorted(splits)}"]

    problems = []
    episodes = {split: {ep.episode_id: ep for ep in suite.episodes(split)} for split in splits}
    expected = set(plan_units(suite, splits, tuple(seeds)))
    keys = Counter((r.get("split"), r.get("seed"), r.get("episode_id")) for r in results["episodes"])
    duplicated = [k for k, n in keys.items() if n > 1]
    absent = expected - set(keys)
    extra = set(keys) - expected
    for label, units in (("missing", absent), ("duplicated", duplicated), ("unexpected", extra)):
        if units:
            shown = ", ".join(f"{s}/seed {seed}/episode {e}" for s, seed, e in sorted(units, key=str)[:3])
            problems.append(f"{len(units)} {label} episode(s), e.g. {shown}")
    if problems:
        return problems
    failed = [r for r in results["episodes"] if r.get("error")]
    if failed:
        first = failed[0]
        return [f"{len(failed)} episode(s) ended in an agent error, e.g. {first['split']}/seed {first['seed']}/"
                f"{first['episode_id']}: {first['error']}; a run that did not run is not a result"]
    for r in results["episodes"]:
        ep = episodes[r["split"]][r["episode_id"]]
        where = f"episode {r['split']}/seed {r['seed']}/{r['episode_id']}"
        if r.get("min_steps") != ep.min_steps or r.get("task") != ep.describe or r.get("goal") != ep.goal_name:
            problems.append(f"{where} does not match the suite's episode (task, goal or min_steps changed)")
        elif r.get("spl") is not None and _differs(r["spl"], episode_spl(r["success"], r["min_steps"], r["steps"])):
            problems.append(f"{where}: spl {r['spl']} does not follow from its success and steps")
        elif r["success"] and r["steps"] < r["min_steps"]:
            problems.append(f"{where}: succeeded in {r['steps']} steps, fewer than the minimal {r['min_steps']}")
        if len(problems) >= 3:
            break
    if problems:
        return problems
    for split in splits:
        recomputed = summarize([r for r in results["episodes"] if r["split"] == split])
        if _differs(results["splits"][split], recomputed):
            fields = [k for k in recomputed if _differs(results["splits"][split].get(k), recomputed[k])]
            problems.append(f"split {split}: summary ({', '.join(fields)}) differs from the one recomputed from its episodes")
    return problems
