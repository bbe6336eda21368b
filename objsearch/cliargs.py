"""Argument types shared by the subcommands: each rejects bad text with a message naming it."""

from __future__ import annotations

import argparse
import math


def _int_at_least(text: str, minimum: int, what: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = minimum - 1
    if value < minimum:
        raise argparse.ArgumentTypeError(f"expected {what} (an integer >= {minimum}), got {text!r}")
    return value


def non_negative_int(text: str) -> int:
    """argparse type: an integer >= 0."""
    return _int_at_least(text, 0, "a non-negative integer")


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1."""
    return _int_at_least(text, 1, "a positive integer")


def positive_float(text: str) -> float:
    """argparse type: a finite number above 0 (metres, pixels' depth)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 < value < math.inf:  # also nan and what overflows to inf (1e400)
        raise argparse.ArgumentTypeError(f"expected a finite number above 0, got {text!r}")
    return value


MAX_SEED = 2**32 - 1  # what every generator takes (torch's manual_seed fails past 2**64)


def one_seed(text: str) -> int:
    """argparse type: one seed, an integer in 0..2**32-1."""
    value = non_negative_int(text)
    if value > MAX_SEED:
        raise argparse.ArgumentTypeError(f"expected a seed in 0..{MAX_SEED}, got {text!r}")
    return value


MAX_SECONDS = 1e9  # about 30 years: the most a timer (setitimer) takes on every platform


def seconds(text: str) -> float:
    """argparse type: a finite number of seconds from 0 to ``MAX_SECONDS``, as a float."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 <= value <= MAX_SECONDS:  # also nan, inf and what overflows to inf (1e400)
        raise argparse.ArgumentTypeError(f"expected a number of seconds from 0 to {MAX_SECONDS:g}, got {text!r}")
    return value


def seed_list(text: str) -> tuple[int, ...]:
    """argparse type: comma-separated integer seeds (at least one), e.g. ``1,5,13``."""
    try:
        seeds = tuple(int(s) for s in text.split(",") if s.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"seeds must be comma-separated integers, e.g. 1,5,13 (got {text!r})"
        ) from None
    if not seeds:
        raise argparse.ArgumentTypeError("give at least one seed")
    negative = [s for s in seeds if s < 0]
    if negative:
        raise argparse.ArgumentTypeError(f"seeds are integers >= 0; {negative[0]} is not (got {text!r})")
    repeated = sorted({s for s in seeds if seeds.count(s) > 1})
    if repeated:  # every episode would count twice, and the intervals would come out too narrow
        raise argparse.ArgumentTypeError(
            f"seed {repeated[0]} is given twice in {text!r}; give each seed once, e.g. "
            f"{','.join(str(s) for s in dict.fromkeys(seeds))}"
        )
    return seeds


def key_value(text: str) -> tuple[str, str]:
    """``KEY=VALUE`` (for ``--set`` overrides of config fields)."""
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    return key.strip(), value.strip()
