"""The partial-results file ``<out>.partial.jsonl``: an evaluation's finished records,
appended as they come, so that an interrupted run resumes where it stopped."""

from __future__ import annotations

import hashlib
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


DIGEST = "sha256"  # the field of the header and of every line that holds its digest


def _canonical(obj) -> str:
    """``obj``'s canonical JSON: what a JSON round trip gives, keys sorted, no spaces."""
    return json.dumps(json.loads(json.dumps(obj)), sort_keys=True, separators=(",", ":"))


def run_key(config: EvalConfig) -> str:
    """The digest of an evaluation's settings: the header's ``sha256`` and the key of its lines'
    digests (secret-free: it catches a line edited by hand or copied from another run, not a
    forger who recomputes it)."""
    return hashlib.sha256(_canonical(config.to_json()).encode()).hexdigest()


def line_digest(key: str, record: dict) -> str:
    """The digest a partial line carries: sha256 over ``key`` and the record's canonical JSON."""
    return hashlib.sha256(f"{key}\n{_canonical(record)}".encode()).hexdigest()


def _episode(record) -> str:
    """``split/seed S/ID`` of a record's episode, as far as its fields say."""
    get = record.get if isinstance(record, dict) else (lambda _key: "?")
    return f"{get('split')}/seed {get('seed')}/{get('episode_id')}"


class PartialResults:
    """Finished records of an evaluation, appended to ``<out>.partial.jsonl`` as they come.

    The first line is the configuration; a rerun with the same configuration resumes, one
    with another is refused, naming the settings that differ. A last line cut short by an
    interruption is dropped; any other line that is not an episode record (``is_record``:
    also one whose fields have the wrong types) is dropped with a warning (its episode runs
    again), so that the run stays resumable. A second line for the same episode is dropped
    when it is the same record, and refused (``UserError`` naming the episode) when it is not:
    which outcome is the episode's is not for objsearch to guess.

    Digests: the header carries ``sha256``, the digest of the settings (``run_key``), and every
    line the digest of its record keyed by it (``line_digest``). On resume a line whose digest
    does not match (a record edited by hand, a line copied from another run), or that carries
    none in a file whose header has one, is reported on stderr by episode, dropped and played
    again; so is every line of a file whose header's digest does not match its settings. A file
    written before digests (a header without one) is resumed as before: its lines without a
    digest are kept, unverified, with one warning; lines appended now carry digests, and the
    file is never rewritten with digests its old lines did not have.
    """

    def __init__(self, path: str | Path, config: EvalConfig):
        self.path = Path(path)
        expected = config.to_json()
        self.key = run_key(config)
        header = {"partial_results_of": expected, DIGEST: self.key}
        self.records: list[dict] = []
        lines: list[dict] = []  # the lines kept, as they are written back (digests included)
        rewrite = True  # a new file, or lines to drop
        if self.path.exists():
            text = self.path.read_text()
            split_lines = text.splitlines()
            try:
                first = json.loads(split_lines[0]) if split_lines else None
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
            signed = DIGEST in first  # written with digests: every line must carry its own
            if not signed:
                header = {"partial_results_of": expected}  # an old file stays one (see above)
            body = split_lines[1:]
            if signed and first[DIGEST] != self.key:
                print(
                    f"warning: {self.path}: its header's digest does not match its settings (edited by hand?); "
                    f"its {len(body)} line(s) are not trusted: dropped, their episodes run again",
                    file=sys.stderr,
                )
                body = []
            rewrite = not text.endswith("\n") or len(body) < len(split_lines) - 1
            seen: dict = {}  # unit -> (line number, record)
            unverified = 0
            for number, line in enumerate(body, start=2):
                try:
                    record = json.loads(line)
                except json.JSONDecodeError:
                    record = None
                    if number == len(split_lines):
                        rewrite = True
                        break  # the write an interruption cut short
                digest = record.pop(DIGEST, None) if isinstance(record, dict) else None
                if not is_record(record):
                    print(
                        f"warning: {self.path} line {number} is not an episode record ({line[:60]!r}); "
                        "dropped, its episode runs again",
                        file=sys.stderr,
                    )
                    rewrite = True
                    continue
                if digest is None and not signed:
                    unverified += 1  # a line of an old file: kept, unverified (said once, below)
                elif digest != line_digest(self.key, record):
                    what = "carries no digest" if digest is None else "does not match its digest"
                    print(
                        f"warning: {self.path} line {number} (episode {_episode(record)}) {what}: edited by hand? "
                        "dropped, its episode runs again",
                        file=sys.stderr,
                    )
                    rewrite = True
                    continue
                unit = (record["split"], record["seed"], record["episode_id"])
                if unit in seen:
                    first_number, other = seen[unit]
                    if other != record:
                        raise UserError(
                            f"{self.path} holds two different records of episode {unit[0]}/seed {unit[1]}/"
                            f"{unit[2]} (lines {first_number} and {number}); delete the wrong line (or the file, to "
                            "play every episode again) and rerun"
                        )
                    rewrite = True  # the same record twice: keep one
                    continue
                seen[unit] = (number, record)
                self.records.append(record)
                lines.append(record if digest is None else {**record, DIGEST: digest})
            if unverified:
                print(
                    f"warning: {self.path} was written before partial-results lines carried digests: its "
                    f"{unverified} record(s) without one are kept unverified (an edit by hand would go unnoticed); "
                    "delete the file to play them again",
                    file=sys.stderr,
                )
        if rewrite:  # a full disk here leaves the records that were there
            _write_lines(self.path, [header, *lines])
        with full_disk_as_error(self.path, ELSEWHERE):
            self._file = open(self.path, "a")

    def done_units(self) -> set[Unit]:
        """The (split, seed, episode_id) units already finished."""
        return {(r["split"], r["seed"], r["episode_id"]) for r in self.records}

    def add(self, records: Iterable[dict]) -> None:
        """Append ``records`` and flush them to disk."""
        with full_disk_as_error(self.path, ELSEWHERE):  # a line cut short is dropped on resume
            for record in records:
                self._file.write(json.dumps({**record, DIGEST: line_digest(self.key, record)}) + "\n")
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
    files are already there: those are left alone (a retry that was interrupted resumes from them).

    A results file whose records do not give its summaries (``_check_summaries``: a record
    edited by hand) is refused: its records are not resumed from."""
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
    _check_summaries(out, results, episodes, list(config.splits))
    several = len(plays) > 1
    for play, path in zip(plays, paths):
        kept = [
            {k: v for k, v in r.items() if k not in ("training_run", "spl")}
            for r in episodes
            if "error" not in r and (not several or r.get("training_run") == play.training_run)
        ]
        _write(path, play, kept)
    return sum("error" in r for r in episodes)


def _check_summaries(out: Path, results: dict, episodes: list[dict], splits: list[str]) -> None:
    """Refuse (``UserError`` naming ``out`` and the first number that differs) a results file
    whose records do not give what it says of them: each record's ``spl``, and every split's
    summary (and each training run's) recomputed with ``summarize`` as ``build_results`` made
    them. So a record edited by hand (a failure made a success, its steps changed) is not
    resumed from; an edit that changes no number the file reports (the steps of a failure) is
    not seen."""
    from objsearch.eval.metrics import episode_spl, summarize

    def refuse(what: str) -> None:
        raise UserError(
            f"--retry-failed: {out}'s records do not give its summaries ({what}): it was edited by hand, so its "
            "records cannot be trusted; drop --retry-failed to evaluate afresh (or restore the file as it was written)"
        )

    for i, r in enumerate(episodes):
        if r.get("spl") != round(episode_spl(r["success"], r["min_steps"], r["steps"]), 4):
            refuse(f"episodes[{i}].spl is {r.get('spl')!r}, its success and steps give another")
    outside = next((r for r in episodes if r["split"] not in splits), None)
    if outside is not None:
        refuse(f"a record of split {outside['split']!r}, which the evaluation did not play")

    def compare(where: str, summaries, records: list[dict]) -> None:
        if not isinstance(summaries, dict) or list(summaries) != splits:
            refuse(
                f"{where} lists splits {list(summaries) if isinstance(summaries, dict) else summaries!r}, not {splits}"
            )
        for split in splits:
            of_split = [r for r in records if r["split"] == split]
            now = summarize(of_split) if of_split else {"episodes": 0}
            there = summaries[split]
            if there != now:  # name the first number that differs, in the summary's order (sr first)
                keys = [*now, *(k for k in there if k not in now)] if isinstance(there, dict) else []
                key = next((k for k in keys if there.get(k) != now.get(k)), None)
                differ = (
                    f"{key}: {there.get(key)!r} there, {now.get(key)!r} from its records"
                    if key is not None
                    else f"{there!r} there"
                )
                refuse(f"{where}.{split}: {differ}")

    compare("splits", results.get("splits"), episodes)
    runs = results.get("training_runs") or []
    for run in runs if isinstance(runs, list) else []:
        if isinstance(run, dict) and "splits" in run:
            mine = [r for r in episodes if len(runs) == 1 or r.get("training_run") == run.get("seed")]
            compare(f"training_runs[seed {run.get('seed')}].splits", run["splits"], mine)


def _write(path: str | Path, config: EvalConfig, records: list[dict]) -> None:
    """Write a whole partial-results file: ``config``'s header line, then ``records``, each
    with its digest (``PartialResults``)."""
    key = run_key(config)
    header = {"partial_results_of": config.to_json(), DIGEST: key}
    _write_lines(path, [header, *({**r, DIGEST: line_digest(key, r)} for r in records)])


def _write_lines(path: str | Path, lines: list[dict]) -> None:
    """Write a whole partial-results file of ``lines`` (the header first)."""
    with atomic_write(path, elsewhere=ELSEWHERE) as f:
        f.write("".join(json.dumps(x) + "\n" for x in lines))
