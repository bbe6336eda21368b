"""Checking a submission (a results JSON from ``objsearch-eval``) before it is trusted.

A submission passes when its fields have the types of a results JSON, its schema version
is known, its suite and episode-set version are the benchmark's own, it covers every split
of the suite with its standard seeds (``objsearch.eval.suites.standard_seeds``: the paper's five,
or those a suite file records) unless it is marked partial
(``"partial": true``, set by ``objsearch leaderboard add --partial``; the results of
``objsearch-eval --episodes N``, the first N episodes only, are refused), every episode of its
splits and seeds is present exactly once, none ended in an agent error, each matches the
suite's episode, and its summary equals the one recomputed from its records.

``verify_submission`` goes further: it replays a sample of the episodes with the agent,
checkpoint and suite config the submission names and requires identical records
(evaluation is deterministic), which a renamed or fabricated submission cannot pass. The
sample is drawn with fresh OS randomness at verify time (``replay_sample``), never from the
submission's content, so a submitter cannot know which records will be replayed; its size
(``sample_size``) catches a submission with ``DETECT_FRACTION`` of its records altered with
probability at least ``DETECT_PROBABILITY``.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import re
from collections import Counter
from dataclasses import replace
from pathlib import Path

import numpy as np

from objsearch.errors import UserError
from objsearch.eval.config import EvalConfig
from objsearch.eval.metrics import episode_spl, summarize
from objsearch.eval.registry import is_file_spec
from objsearch.eval.results import SCHEMA_VERSION
from objsearch.eval.runner import run_units
from objsearch.eval.runs import agent_of
from objsearch.eval.suites import SUITES, make_suite, standard_seeds
from objsearch.sim.goals import PROTOCOLS

REQUIRED = (
    "schema_version",
    "agent",
    "suite",
    "episode_set_version",
    "objsearch_version",
    "seeds",
    "config",
    "splits",
    "episodes",
)
TOLERANCE = 1e-4  # summaries are rounded to 4 decimals
# the fields of a record that a replay must reproduce exactly (spl follows from them; no timing fields exist)
REPLAYED = ("goal", "min_steps", "task", "success", "steps", "error")
# a replay sample catches a submission with DETECT_FRACTION of its records altered with at least this probability
DETECT_FRACTION = 0.05
DETECT_PROBABILITY = 0.99
# suite options that say where objsearch writes, never what an episode is: a submission's are
# ignored (verify builds its caches where the verifier's settings say, never where a file says)
WRITE_OPTIONS = ("cache_dir",)
# suite options that say what the agent observed (shown in the observation column): the only
# ones a ranked entry may set to other than the suite's standard
OBSERVATION_OPTIONS = ("observation", "perception", "perception_key")


# Parsing limits: a hostile file is refused with a message, never a traceback or a stall.
MAX_BYTES = 32 * 2**20  # the largest stored entries (rooms: 4,000 episodes x 5 seeds) are 16 MB
MAX_DEPTH = 16  # a results JSON nests 5 deep (results > episodes > record > task > start)
MAX_DIGITS = 20  # digits of a number: any 64-bit integer; Python's own limit, 4300, is a traceback
_JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"')
_LONG_NUMBER = re.compile(rb"[0-9]{%d,}" % (MAX_DIGITS + 1))
_NOT_BRACKETS = bytes(b for b in range(256) if b not in b"[]{}")


def _past_limits(raw: bytes) -> str | None:
    """What of the JSON text ``raw`` is past ``MAX_DIGITS`` or ``MAX_DEPTH``, if anything:
    looked for outside its strings, before parsing (which would recurse that deep)."""
    skeleton = _JSON_STRING.sub(b'""', raw)
    long = _LONG_NUMBER.search(skeleton)
    if long:
        return f"a number of {len(long.group())} digits (at most {MAX_DIGITS})"
    brackets = np.frombuffer(skeleton.translate(None, _NOT_BRACKETS), dtype=np.uint8)
    steps = np.where((brackets == ord("[")) | (brackets == ord("{")), 1, -1)
    if steps.size and steps.cumsum().max() > MAX_DEPTH:
        return f"nests deeper than {MAX_DEPTH} levels"
    return None


def _finite(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"the number {text[:30]} is out of range")
    return value


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number JSON allows")


def load_submission(path: str | Path) -> dict:
    """The results dict in the JSON file ``path``; ``UserError`` if it cannot be read, is no
    JSON object, or is past the parsing limits (``MAX_BYTES``, ``MAX_DEPTH``, ``MAX_DIGITS``;
    NaN and infinities are refused too)."""
    path = Path(path)
    try:
        with path.open("rb") as f:
            raw = f.read(MAX_BYTES + 1)
    except OSError as err:
        raise UserError(f"cannot read submission {path}: {err.strerror}") from None
    if len(raw) > MAX_BYTES:
        raise UserError(
            f"submission {path} is larger than the limit of {MAX_BYTES // 2**20} MiB: not a results JSON of objsearch-eval"
        )
    problem = _past_limits(raw)
    if problem is None:
        try:
            data = json.loads(raw.decode("utf-8"), parse_float=_finite, parse_constant=_no_constant)
        except RecursionError:  # only past the checks above when the file is no JSON at all
            problem = f"nests deeper than {MAX_DEPTH} levels"
        except ValueError as err:  # also JSONDecodeError, UnicodeDecodeError and the number checks
            problem = str(err)
    if problem is not None:
        raise UserError(f"submission {path} cannot be read as a results JSON: {problem}")
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


def _is_int(x) -> bool:
    return isinstance(x, int) and not isinstance(x, bool)


def _is_seeds(x) -> bool:
    return isinstance(x, list) and all(_is_int(v) and v >= 0 for v in x)


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def _format(pattern: str, what: str, optional: bool = False) -> tuple:
    """(test, description) of a string field: ``pattern`` must match the whole string."""
    regex = re.compile(pattern)
    test = lambda x: (optional and x is None) or (isinstance(x, str) and regex.fullmatch(x) is not None)
    return test, what + (" (or null)" if optional else "")


# The declared format of every string a submission holds: what reaches the pages or a terminal
# is one of these, never free text (and the pages escape it as well).
ENTRY_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,99}")  # fullmatch: "abc\n" is no name
_NAME_CHARS = "a letter or digit, then letters, digits, '_', '.' or '-'"
_NAME = _format(ENTRY_NAME.pattern, f"a name: {_NAME_CHARS} (at most 100 characters)")
# a file agent is recorded by its absolute path (objsearch.eval.registry.recorded_spec): any path a checkpoint may have
_AGENT = _format(
    r"[A-Za-z0-9_./:-]{1,200}|[^\x00-\x1f\x7f-\x9f\u2028\u2029]{1,1024}\.py:[A-Za-z_][A-Za-z0-9_.]{0,199}",
    "an agent name or module:Class of letters, digits, '_', '.', '/', ':' or '-' (at most 200 characters), "
    "or path/file.py:Class (a path of at most 1024 characters, no control characters)",
)
_VERSION = _format(
    r"[A-Za-z0-9][A-Za-z0-9_.:+!-]{0,99}",
    "a version: a letter or digit, then letters, digits, '_', '.', ':', '+', '!' or '-' (at most 100 characters)",
)
_COMMIT = _format(r"[0-9a-f]{7,64}", "a git commit: 7 to 64 lowercase hex digits", optional=True)
_SHA256 = _format(r"[0-9a-f]{64}", "a SHA-256 digest: 64 lowercase hex digits", optional=True)
_KEY = _format(r"[0-9a-f]{1,64}", "a perception key: up to 64 lowercase hex digits", optional=True)
_PATH = _format(
    r"[^\x00-\x1f\x7f-\x9f\u2028\u2029]{1,1024}",
    "a path or word of at most 1024 characters, no control characters",
    optional=True,
)


def _text(limit: int) -> tuple:
    return _format(
        rf"[^\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029]{{0,{limit}}}",
        f"text of at most {limit} characters, no control characters but tab and line breaks",
    )


_INT = (_is_int, "an integer")
_SEEDS = (_is_seeds, "a list of non-negative integers")
_NAMES = (lambda x: isinstance(x, list) and all(_NAME[0](v) for v in x), f"a list of names ({_NAME_CHARS})")
_BOOL = (lambda x: isinstance(x, bool), "true or false")
_DICT = (lambda x: isinstance(x, dict), "an object")
_OPT_NUMBER = (lambda x: x is None or _is_number(x), "a number or null")
_OPT_COUNT = (lambda x: x is None or (_is_int(x) and x >= 0), "a non-negative integer or null")
_SEED = (lambda x: _is_int(x) and x >= 0, "a non-negative integer")
# field: (test, what it must be, required)
TOP_FIELDS = {
    "schema_version": (*_INT, True),
    "agent": (*_AGENT, True),
    "suite": (*_NAME, True),
    "episode_set_version": (*_VERSION, True),
    "objsearch_version": (*_VERSION, True),
    "git_commit": (*_COMMIT, False),
    "seeds": (*_SEEDS, True),
    "config": (*_DICT, True),
    "splits": (*_DICT, True),
    "episodes": ((lambda x: isinstance(x, list)), "a list", True),
    "partial": (*_BOOL, False),
    "training_runs": ((lambda x: isinstance(x, list) and 0 < len(x) <= 100), "a list of 1 to 100 runs", False),
    "loaded_checkpoint": (*_PATH, False),
    "protocol": (lambda x: x in PROTOCOLS, f"one of the protocols {', '.join(PROTOCOLS)}", False),
    # written by `objsearch leaderboard verify` into a stored entry; `add` drops a submission's own
    "verified": (
        lambda x: (
            isinstance(x, dict)
            and x.keys() == {"replayed", "episodes", "sha256"}
            and all(_is_int(x[k]) and x[k] >= 0 for k in ("replayed", "episodes"))
            and _SHA256[0](x["sha256"])
            and x["sha256"] is not None
        ),
        "an object {replayed, episodes, sha256} written by objsearch leaderboard verify",
        False,
    ),
}
CONFIG_FIELDS = {
    "agent": (*_AGENT, True),
    "suite": (*_NAME, True),
    "splits": (*_NAMES, True),
    "seeds": (*_SEEDS, True),
    "checkpoint": (*_PATH, False),
    "suite_config": (*_DICT, False),
    "step_time_limit": (*_OPT_NUMBER, False),
    "weights_sha256": (*_SHA256, False),
    "training_run": (*_SEED, False),
    "episodes": ((lambda x: x is None or (_is_int(x) and x > 0)), "a positive integer or null", False),
}
RUN_FIELDS = {  # an entry of training_runs (objsearch.eval.runs.run_entry)
    "seed": (*_SEED, True),
    "weights_sha256": (*_SHA256, True),
    "env_steps": (*_OPT_COUNT, True),
    "wall_s": (*_OPT_NUMBER, True),
    "splits": (*_DICT, True),
    "loaded_checkpoint": (*_PATH, False),
}
# the strings of a suite's options (the suite checks their values): the perception key is
# shown on the pages; any other string option is a path
SUITE_CONFIG_STRINGS = {"perception_key": _KEY}
RECORD_FIELDS = {
    "split": (*_NAME, True),
    "seed": (*_INT, True),
    "episode_id": (*_INT, True),
    "goal": (*_NAME, True),
    "success": (*_BOOL, True),
    "steps": (*_INT, True),
    "min_steps": (*_INT, True),
    "spl": (*_OPT_NUMBER, False),
    "task": (*_DICT, True),
    "error": (*_text(2000), False),
    "traceback": (*_text(20000), False),
    "training_run": (*_SEED, False),
}


def _short(value, limit: int = 60) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _field_problems(obj: dict, fields: dict, where: str) -> list[str]:
    problems = []
    for key, (test, what, required) in fields.items():
        if key not in obj:
            if required:
                problems.append(f"{where} has no field {key!r}")
        elif not test(obj[key]):
            problems.append(f"{where} field {key!r} is {_short(obj[key])}, not {what}")
    return problems


def type_problems(results: dict) -> list[str]:
    """Fields of ``results`` whose type is not the one a results JSON has (at most 3 shown)."""
    problems = _field_problems(results, TOP_FIELDS, "results")
    if not problems:
        problems = _field_problems(results["config"], CONFIG_FIELDS, "config")
    if not problems:
        suite_config = results["config"].get("suite_config", {})
        strings = {
            k: (*SUITE_CONFIG_STRINGS.get(k, _PATH), False) for k, v in suite_config.items() if isinstance(v, str)
        }
        problems = _field_problems(suite_config, strings, "config.suite_config")
    for i, run in enumerate([] if problems else results.get("training_runs", [])):
        problems += (
            _field_problems(run, RUN_FIELDS, f"training_runs[{i}]")
            if isinstance(run, dict)
            else [f"training_runs[{i}] is {_short(run)}, not an object"]
        )
    if not problems:
        problems = [
            f"summary of split {split!r} is {_short(s)}, not an object"
            for split, s in results["splits"].items()
            if not isinstance(s, dict)
        ]
    for i, record in enumerate([] if problems else results["episodes"]):
        problems += (
            _field_problems(record, RECORD_FIELDS, f"episodes[{i}]")
            if isinstance(record, dict)
            else [f"episodes[{i}] is {_short(record)}, not an object"]
        )
        if len(problems) >= 3:
            break
    return problems[:3]


@functools.lru_cache(maxsize=8)
def _suite(name: str, suite_config: str):
    """The suite and its episodes by split and id (built once per process: stored entries share suites)."""
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


def sample_size(total: int, fraction: float = DETECT_FRACTION, probability: float = DETECT_PROBABILITY) -> int:
    """How many of ``total`` records a uniform sample without replacement must hold to
    include at least one of ``ceil(fraction * total)`` altered ones with ``probability``:
    the smallest ``n`` whose hypergeometric miss probability, the product over ``i < n`` of
    ``(total - altered - i) / (total - i)``, is at most ``1 - probability`` (90 for large
    entries, where it tends to the binomial bound ``(1 - fraction) ** n``); at most ``total``."""
    altered = max(1, math.ceil(fraction * total - 1e-9))
    miss, n = 1.0, 0
    while n < total and miss > 1 - probability:
        miss *= max(0, total - altered - n) / (total - n)
        n += 1
    return n


def miss_probability(total: int, n: int, fraction: float = DETECT_FRACTION) -> float:
    """The probability that a sample of ``n`` of ``total`` records holds none of
    ``ceil(fraction * total)`` altered ones (see ``sample_size``)."""
    altered = max(1, math.ceil(fraction * total - 1e-9))
    return math.prod(max(0, total - altered - i) / (total - i) for i in range(min(n, total)))


def replay_units(results: dict) -> list[tuple]:
    """Every (split, seed, episode_id, training run) unit of ``results``, in a fixed order."""
    return sorted({_unit(r) for r in results["episodes"]}, key=str)


def replay_sample(results: dict, k: int | None, rng: np.random.Generator) -> list[tuple]:
    """``k`` (``None``: ``sample_size``; at most all) units of ``results`` drawn uniformly
    without replacement by ``rng``. The verifier passes a generator seeded from fresh OS
    randomness (``fresh_rng``), so nothing in a submission decides, or predicts, its sample."""
    units = replay_units(results)
    return [units[i] for i in sorted(rng.choice(len(units), size=replay_count(results, k), replace=False))]


def replay_count(results: dict, k: int | None) -> int:
    """How many units ``replay_sample(results, k, ...)`` draws."""
    total = len(replay_units(results))
    return sample_size(total) if k is None else min(k, total)


def fresh_rng() -> np.random.Generator:
    """A generator seeded from the operating system's randomness at the time of the call:
    the verifier's own, unknown to any submitter."""
    return np.random.default_rng()


def content_sha256(results: dict) -> str:
    """The digest of a submission's content, its ``verified`` record left out: a stored
    verification counts only for the content it replayed."""
    content = {k: v for k, v in results.items() if k != "verified"}
    return hashlib.sha256(json.dumps(content, sort_keys=True).encode()).hexdigest()


def replayed_of(results: dict) -> tuple[int, int] | None:
    """(episodes replayed, episodes) of the stored entry ``results``'s last verification,
    if one was recorded for its present content; None if none was."""
    verified = results.get("verified")
    if not isinstance(verified, dict) or verified.get("sha256") != content_sha256(results):
        return None
    return verified["replayed"], verified["episodes"]


def untrusted_code(agent: str) -> str | None:
    """What code verifying an entry of ``agent`` would import that is not a registered agent
    (a file agent, or a ``module:Class`` that no installed package registers), said in a few
    words; None for a registered agent (by name or by its registered ``module:Class``)."""
    from objsearch.eval.registry import registered_agents

    registered = registered_agents()
    if agent in registered or agent in registered.values():
        return None
    if is_file_spec(agent):
        return f"the Python file {agent.rpartition(':')[0]} (class {agent.rpartition(':')[2]})"
    return f"the module {agent.rpartition(':')[0]!r} (class {agent.rpartition(':')[2]}), not a registered agent"


def verify_submission(
    results: dict, k: int | None = None, rng: np.random.Generator | None = None, trust: bool = False
) -> list[str]:
    """Problems found by replaying ``k`` (None: ``sample_size``) of the episodes of a valid
    submission, drawn by ``rng`` (None: ``fresh_rng()``), with the agent, checkpoint and suite
    config it names (empty when every replayed record is identical). An agent that is not a
    registered one (``untrusted_code``) is imported only with ``trust``; the suite's
    ``WRITE_OPTIONS`` are the verifier's, never the submission's."""
    problems = check_submission(results)
    if problems:
        return problems
    if is_file_spec(results["agent"]):
        path = Path(results["agent"].rpartition(":")[0])
        if not path.is_file():
            return [
                f"its agent file {path.resolve()} is missing: replay loads the file the evaluation recorded; "
                "put the file back there, or evaluate again and add the new results with --replace"
            ]
    code = untrusted_code(results["agent"])
    if code is not None and not trust:
        return [
            f"replaying it would import and run {code}; read that code, then pass --trust to run it "
            "(registered agents need no --trust)"
        ]
    c = results["config"]
    config = EvalConfig(
        agent=results["agent"],
        suite=results["suite"],
        splits=tuple(c["splits"]),
        seeds=tuple(results["seeds"]),
        checkpoint=c.get("checkpoint"),
        suite_config=playable_config(c.get("suite_config", {})),
        step_time_limit=None,
        training_run=c.get("training_run"),
    )
    runs = results.get("training_runs", [])
    claims = {None: c.get("weights_sha256")} if len(runs) <= 1 else {run["seed"]: run["weights_sha256"] for run in runs}
    stored = {_unit(r): r for r in results["episodes"]}
    units = replay_sample(results, k, fresh_rng() if rng is None else rng)
    for run, claimed in claims.items():
        play = config if run is None else replace(config, training_run=run)
        if claimed is not None:  # the weights the submission names must be the ones that load now
            loaded = getattr(agent_of(play), "weights_sha256", None)
            if loaded != claimed:
                what = f"checkpoint {config.checkpoint or 'shipped'}" + ("" if run is None else f", training run {run}")
                return [
                    f"the submission used weights {claimed[:12]}, but agent {results['agent']!r} loads "
                    f"{str(loaded)[:12]} ({what}); replay it with the weights it names"
                ]
        mine = [u[:3] for u in units if u[3] == run]
        for replayed in run_units(play, mine, progress=False) if mine else []:
            unit = (replayed["split"], replayed["seed"], replayed["episode_id"], run)
            for key in REPLAYED:
                if stored[unit].get(key) != replayed.get(key):
                    problems.append(
                        f"episode {_where(unit)}: {key} is {stored[unit].get(key)!r} in the "
                        f"submission but {replayed.get(key)!r} when replayed with agent {results['agent']!r}"
                    )
                    break
    return problems[:3] + ([f"{len(problems)} of {len(units)} replayed episodes differ"] if len(problems) > 3 else [])
