"""Randomness for a batch of episodes: one Generator per row.

Batched evaluation (``objsearch-eval --batch N``) gives each episode its own ``task.rng``.
A policy that decides for N rows at once draws through ``RowRandom``, so that each row's
numbers come from its own Generator in the order a one-row call would draw them: an
episode's record then does not depend on which episodes share its batch. (numpy fills
``random((1, k))`` and ``random((k,))``, ``integers(h, size=1)`` and ``integers(h)`` from the
same stream, so one row through ``RowRandom`` draws what a plain Generator would.)
Training passes one Generator for the whole batch.
"""

from __future__ import annotations

import numpy as np


class RowRandom:
    """One Generator per row (evaluation: each episode's ``task.rng``). Draws for a row come
    from its own Generator, in the order the policy makes them, so an episode's stream does
    not depend on which other episodes share the batch. Training passes one Generator."""

    def __init__(self, generators):
        self.generators = list(generators)

    def rows(self, ix) -> "RowRandom":
        return RowRandom([self.generators[i] for i in ix])

    def random(self, shape) -> np.ndarray:
        shape = (shape,) if np.isscalar(shape) else tuple(shape)
        return np.array([g.random(shape[1:]) for g in self.generators], dtype=np.float64).reshape(shape)

    def integers(self, high: int, size) -> np.ndarray:
        return np.array([g.integers(high) for g in self.generators], dtype=np.int64)


def rows_of(rng, ix):
    """The generator(s) of rows ``ix``: ``rng`` itself if it is one Generator."""
    return rng.rows(ix) if isinstance(rng, RowRandom) else rng
