"""Scene Priors' relation graph (``agents/baselines/scene_priors.py``, substitute 1 of ``docs/scene_priors.md``):
SAVN's Visual Genome adjacency becomes co-occurrence in an annotated scene corpus, the specs of
``house-gen-v2``'s 40 training houses (never an evaluation house). Category j is related to i
when j is in more than ``RELATION_THRESHOLD`` of the rooms that hold i (i to itself: a second
instance); binary, asymmetric, normalised as the authors' ``get_adjmat``: D^-1/2 A^T D^-1/2, D
the row sums, no added self-loops."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch_agents.house.tables import NUM_OBJECTS

GRAPH_SUITE = "house-gen-v2"
"""The suite whose TRAINING houses are the scene corpus (house-gen-2 houses)."""
RELATION_THRESHOLD = 0.5
"""A[i, j] = 1 when category j is in more than this fraction of the rooms that hold i."""


def object_node(category: str) -> int:
    """The graph node of an object category (its id less ``FIRST_OBJECT_ID``)."""
    return CATEGORY_IDS[category] - FIRST_OBJECT_ID


def room_counts(specs) -> np.ndarray:
    """int (R, NUM_OBJECTS): the objects of each category in every furnished room of ``specs``."""
    rows = []
    for spec in specs:
        counts = {room.id: np.zeros(NUM_OBJECTS, np.int64) for room in spec.rooms}
        for obj in spec.objects:
            counts[obj.room][object_node(obj.category)] += 1
        rows += [c for _, c in sorted(counts.items()) if c.any()]
    return np.stack(rows) if rows else np.zeros((0, NUM_OBJECTS), np.int64)


def relation_graph(specs, threshold: float = RELATION_THRESHOLD) -> np.ndarray:
    """uint8 (NUM_OBJECTS, NUM_OBJECTS) binary adjacency from the rooms of ``specs`` alone:
    A[i, j] = 1 when P(j in the room | i in the room) > ``threshold`` (j = i: a second
    instance of i). Asymmetric; a category in no room has no edges."""
    counts = room_counts(specs)
    has = (counts > 0).astype(np.int64)
    both = has.T @ has
    np.fill_diagonal(both, (counts >= 2).sum(axis=0))
    holding = has.sum(axis=0)
    p = both / np.maximum(holding, 1)[:, None]
    return (p > threshold).astype(np.uint8)


def normalized_adjacency(adjacency: np.ndarray) -> np.ndarray:
    """D^-1/2 A^T D^-1/2 with D the row sums of A, no self-loops added, 0 for a node with no
    out-edges (the authors' ``get_adjmat``, SAVN's ``normalize_adj``)."""
    a = np.asarray(adjacency, np.float64)
    rowsum = a.sum(axis=1)
    inv_sqrt = np.divide(1.0, np.sqrt(rowsum), out=np.zeros_like(rowsum), where=rowsum > 0)
    return (inv_sqrt[:, None] * a.T * inv_sqrt[None, :]).astype(np.float32)


def graph_refs(suite: str = GRAPH_SUITE):
    """The houses of the scene corpus: ``suite``'s training houses (spec-hash checked)."""
    from objsearch.sim.suites import load_suite_file, training_houses

    return training_houses(load_suite_file(suite))


@lru_cache(maxsize=2)
def prior_graph(suite: str = GRAPH_SUITE) -> np.ndarray:
    """The relation graph of ``suite``'s training houses (a few seconds: 40 specs generated)."""
    from objsearch.sim.world import World

    return relation_graph([World.load(ref).spec for ref in graph_refs(suite)])
