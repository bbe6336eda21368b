"""The partial-results file ``<out>.partial.jsonl``: an evaluation's finished records,
appended as they come, so that an interrupted run resumes where it stopped."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Iterable

from objsearch.errors import UserError
from objsearch.eval.config import EvalConfig, Unit
from objsearch.fileio import atomic_write, full_disk_as_error, full_disk_error

ELSEWHERE = "choose another --out"

RECORD_KEYS = frozenset(("split", "seed", "episode_id", "success", "steps", "min_steps"))
_INT = lambda x: isinstance(x, int) and not isinstance(x, bool)  # noqa: E731
RECORD_TYPES = {
    "split": lambda x: isinstance(x, str),
    "seed": _INT,
    "episode_id": _INT,
    "success": lambda x: isinstance(x, bool),
    "steps": lambda x: _INT(x) and x >= 0,
    "min_steps": lambda x: _INT(x) and x >= 0,
}


def is_record(record) -> bool:
    """Whether ``record`` is an episode record: a dict with ``RECORD_KEYS`` of their types."""
    return isinstance(record, dict) and all(k in record and test(record[k]) for k, test in RECORD_TYPES.items())


class PartialResults:
    """Finished records of an evaluation, appended to ``<out>.partial.jsonl`` as they come.

    The first line is the configuration; a rerun with the same configuration resumes, one
    with another is refused, naming the settings that differ. A last line cut short by an
    interruption is dropped; any other line that is not an episode record (``is_record``:
    also one whose fields have the wrong types) is dropped with a warning (its episode runs
    again), so that the run stays resumable. A second line for the same episode is dropped
    when it is the same record, and refused (``UserError`` naming the episode) when it is not:
    which outcome is the episode's is not for objsearch to guess.
    """

    def __init__(self, path: str | Path, config: EvalConfig):
        self.path = Path(path)
        expected = config.to_json()
        self.records: list[dict] = []
        rewrite = True  # a new file, or lines to drop
        if self.path.exists():
            text = self.path.read_text()
            lines = text.splitlines()
            try:
                first = json.loads(lines[0]) if lines else None
            except json.JSONDecodeError:
                first = None
            stored = first.get("partial_results_of") if isinstance(first, dict) else None
            if not isinstance(stored, dict):
                raise UserError(
                    f"{self.path} is not a partial-results file (its first line is not an evaluation's "
                    "settings); delete it or choose another --out"
                )
            if stored != expected:
                raise UserError(
                    f"{self.path} holds partial results of another evaluation ({_differences(stored, expected)}); "
                    "rerun with those settings to resume it, or delete it or choose another --out to start afresh"
                )
            rewrite = not text.endswith("\n")  # appending to a cut line would spoil the next record
            seen: dict = {}  # unit -> (line number, record)
            for number, line in enumerate(lines[1:], start=2):
                try:
                    record = json.loads(line)
                except json.JSONDecodeError:
                    record = None
                    if number == len(lines):
                        rewrite = True
                        break  # the write an interruption cut short
                if not is_record(record):
                    print(
                        f"warning: {self.path} line {number} is not an episode record ({line[:60]!r}); "
                        "dropped, its episode runs again",
                        file=sys.stderr,
                    )
                    rewrite = True
                    continue
                unit = (record["split"], record["seed"], record["episode_id"])
                if unit in seen:
                    first, other = seen[unit]
                    if other != record:
                        raise UserError(
                            f"{self.path} holds two different records of episode {unit[0]}/seed {unit[1]}/"
                            f"{unit[2]} (lines {first} and {number}); delete the wrong line (or the file, to "
                            "play every episode again) and rerun"
                        )
                    rewrite = True  # the same record twice: keep one
                    continue
                seen[unit] = (number, record)
                self.records.append(record)
        if rewrite:  # a full disk here leaves the records that were there
            _write(self.path, config, self.records)
        with full_disk_as_error(self.path, ELSEWHERE):
            self._file = open(self.path, "a")

    def done_units(self) -> set[Unit]:
        """The (split, seed, episode_id) units already finished."""
        return {(r["split"], r["seed"], r["episode_id"]) for r in self.records}

    def add(self, records: Iterable[dict]) -> None:
        """Append ``records`` and flush them to disk."""
        with full_disk_as_error(self.path, ELSEWHERE):  # a line cut short is dropped on resume
            for record in records:
                self._file.write(json.dumps(record) + "\n")
            self._file.flush()

    def close(self) -> None:
        """Close the file (it stays on disk until the results are written)."""
        try:
            self._file.close()
        except OSError as err:  # what a full disk kept of the last lines is dropped on resume
            if full_disk_error(err, self.path) is None:
                raise


def _differences(stored: dict, now: dict, prefix: str = "") -> str:
    """The settings that differ between two configurations, e.g. ``agent: 'random' there,
    'oracle' now``."""
    parts = []
    for key in sorted(set(stored) | set(now), key=str):
        there, here = stored.get(key), now.get(key)
        if there == here:
            continue
        if isinstance(there, dict) and isinstance(here, dict):
            parts.append(_differences(there, here, f"{prefix}{key}."))
        else:
            parts.append(f"{prefix}{key}: {there!r} there, {here!r} now")
    return "; ".join(parts)


def keep_what_did_not_fail(out: str | Path, config: EvalConfig, plays: list[EvalConfig], paths: list[str]) -> int:
    """``--retry-failed``: turn the results file at ``out`` into the partial-results files
    ``paths`` (one per play, ``plays``) holding every record that did not fail, so that the
    rerun plays only the episodes that ended in an agent error (a step-time limit hit on a
    busy machine, a crash) and keeps the rest. ``config``: the configuration the results must
    have been written with. Returns the number of episodes to replay, or -1 where partial
    files are already there: those are left alone (a retry that was interrupted resumes from them)."""
    out = Path(out)
    if any(Path(p).exists() for p in paths):
        return -1
    if not out.is_file():
        raise UserError(f"--retry-failed: {out} is not a results file; it repairs the --out file of a finished run")
    try:
        results = json.loads(out.read_text())
        stored, episodes = results["config"], results["episodes"]
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise UserError(f"--retry-failed: {out} is not a results file written by objsearch-eval ({err})") from None
    bad = next((i for i, r in enumerate(episodes) if not is_record(r)), None) if isinstance(episodes, list) else -1
    if bad is not None:
        what = "its 'episodes' is not a list" if bad < 0 else f"episodes[{bad}] is not an episode record"
        raise UserError(
            f"--retry-failed: {out} is not a results file written by objsearch-eval ({what}); "
            "drop --retry-failed to evaluate afresh"
        )
    if stored != config.to_json():
        raise UserError(
            f"--retry-failed: {out} holds the results of another evaluation ({_differences(stored, config.to_json())}); "
            "rerun with those settings, or drop --retry-failed to start afresh"
        )
    several = len(plays) > 1
    for play, path in zip(plays, paths):
        kept = [
            {k: v for k, v in r.items() if k not in ("training_run", "spl")}
            for r in episodes
            if "error" not in r and (not several or r.get("training_run") == play.training_run)
        ]
        _write(path, play, kept)
    return sum("error" in r for r in episodes)


def _write(path: str | Path, config: EvalConfig, records: list[dict]) -> None:
    """Write a whole partial-results file: ``config``'s header line, then ``records``."""
    with atomic_write(path, elsewhere=ELSEWHERE) as f:
        f.write("".join(json.dumps(x) + "\n" for x in [{"partial_results_of": config.to_json()}, *records]))
