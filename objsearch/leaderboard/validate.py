"""Checking a submission (a results JSON from ``objsearch-eval``) before it is trusted: the names
the leaderboard's commands import, from the modules that do each job.

A submission passes when its fields have the types of a results JSON (``results_schema``:
a JSON Schema document), its schema version is known, its suite and episode-set version are
the benchmark's own, it covers every split of the suite with its standard seeds
(``objsearch.eval.suites.standard_seeds``: the paper's five, or those a suite file records)
unless it is marked partial (``"partial": true``, set by ``objsearch leaderboard add
--partial``; the results of ``objsearch-eval --episodes N``, the first N episodes only, are
refused), every episode of its splits and seeds is present exactly once, none ended in an
agent error, each matches the suite's episode, and its summary equals the one recomputed
from its records (``checks``). Its file is read within limits (``parsing``).

``verify_submission`` goes further (``replay``): it replays a sample of the episodes with the
agent, checkpoint and suite config the submission names and requires identical records
(evaluation is deterministic), which a renamed or fabricated submission cannot pass. The
sample is drawn with fresh OS randomness at verify time (``replay_sample``), never from the
submission's content, so a submitter cannot know which records will be replayed; its size
(``sample_size``) catches a submission with ``DETECT_FRACTION`` of its records altered with
probability at least ``DETECT_PROBABILITY``.
"""

from __future__ import annotations

from objsearch.leaderboard.checks import (
    OBSERVATION_OPTIONS,
    TOLERANCE,
    WRITE_OPTIONS,
    check_submission,
    nonstandard_settings,
    playable_config,
    played_runs,
)
from objsearch.leaderboard.parsing import MAX_BYTES, MAX_DEPTH, MAX_DIGITS, load_submission
from objsearch.leaderboard.replay import (
    DETECT_FRACTION,
    DETECT_PROBABILITY,
    REPLAYED,
    content_sha256,
    fresh_rng,
    miss_probability,
    replay_count,
    replay_sample,
    replay_units,
    replayed_of,
    sample_size,
    untrusted_code,
    verify_submission,
)
from objsearch.leaderboard.results_schema import ENTRY_NAME, REQUIRED, SCHEMA, type_problems

__all__ = [
    "DETECT_FRACTION",
    "DETECT_PROBABILITY",
    "ENTRY_NAME",
    "MAX_BYTES",
    "MAX_DEPTH",
    "MAX_DIGITS",
    "OBSERVATION_OPTIONS",
    "REPLAYED",
    "REQUIRED",
    "SCHEMA",
    "TOLERANCE",
    "WRITE_OPTIONS",
    "check_submission",
    "content_sha256",
    "fresh_rng",
    "load_submission",
    "miss_probability",
    "nonstandard_settings",
    "playable_config",
    "played_runs",
    "replay_count",
    "replay_sample",
    "replay_units",
    "replayed_of",
    "sample_size",
    "type_problems",
    "untrusted_code",
    "verify_submission",
]
