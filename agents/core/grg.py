"""The Goals Relational Graph (GRG) of HRL-GRG (Ye et al., CVPR 2021, section 3.2).

A complete directed graph over ``num_nodes`` goal nodes. Edge ``(i, j)`` holds a
Dirichlet-categorical model of "what happens to goal j while the low level chases goal i":
categories ``k = 1..K`` ("j is first seen after k low-level steps") and one last category
"j is not seen in this option". The edge weight is the posterior mean of
``X_ij = gamma^(k-1)`` (0 for "not seen"):

    P(k) = (alpha_k + c_ijk) / sum_k (alpha_k + c_ijk),   w_ij = sum_{k<=K} P(k) gamma^(k-1),

with ``w_ii = 1``. Planning finds, for every node, the plan to a target that maximises the
product of edge weights (Dijkstra on ``-log w``, run backwards from the target); its value
``C`` is the relation of the node to the target. Facts the paper leaves open (the prior
``(0, ..., 0, 1)``, how options are counted, the termination rule) follow the authors'
code, as ``docs/gridworld_agents.md`` ("Choices and deviations") and ``docs/house_agents.md``
("The hierarchy") write them down.

The module knows nothing about grids or any simulator: a node is an index, an option's
outcome is "on which step was each node first seen". The grid-world and 3D agents share it.
It lives in ``objsearch_agents`` rather than ``objsearch`` because it is part of one method
(HRL-GRG), not of the benchmark, which knows nothing about particular agents.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from objsearch import digests
from objsearch.errors import UserError
from objsearch.fileio import atomic_write

NOT_SEEN = 0  # value of ``first_seen`` for a node never seen during an option


@dataclass(frozen=True, eq=False)
class Plans:
    """Best plans from every node to every target (or to one target).

    Attributes:
        values: float (T, n): ``values[t, i]`` = max over plans i -> target t of the
            product of edge weights (1 for i == target, 0 when no plan has weight).
        next_node: int (T, n): the node after i on its best plan to target t (-1 for the
            target itself and for nodes with no plan).
        targets: int (T,): the target of each row.
    """

    values: np.ndarray
    next_node: np.ndarray
    targets: np.ndarray

    def row(self, target: int) -> int:
        hits = np.flatnonzero(self.targets == target)
        if not len(hits):
            raise KeyError(f"no plans to target {target}")
        return int(hits[0])

    def path(self, node: int, target: int) -> list[int]:
        """The best plan ``[node, ..., target]``; ``[node]`` if there is none (value 0)."""
        r = self.row(target)
        path = [int(node)]
        while self.next_node[r, path[-1]] >= 0 and len(path) <= self.values.shape[1]:
            path.append(int(self.next_node[r, path[-1]]))
        return path

    def successors(self) -> np.ndarray:
        """bool (T, n, n): ``[t, i, j]`` is True when j comes after i on i's plan to t."""
        num_t, n = self.next_node.shape
        out = np.zeros((num_t, n, n), dtype=bool)
        rows = np.arange(num_t)[:, None]
        cur = np.broadcast_to(np.arange(n), (num_t, n)).copy()
        for _ in range(n):
            cur = np.where(cur >= 0, self.next_node[rows, np.maximum(cur, 0)], -1)
            live = cur >= 0
            if not live.any():
                break
            t_ix, i_ix = np.nonzero(live)
            out[t_ix, i_ix, cur[t_ix, i_ix]] = True
        return out


def plan_termination(plan: list[int], visible) -> bool:
    """The GRG termination rule: while chasing ``plan[0]`` toward the final goal
    ``plan[-1]``, stop as soon as any node after ``plan[0]`` on the plan (the final goal
    included) is visible. ``visible`` is a bool array over nodes or a set of node ids."""
    later = plan[1:]
    if isinstance(visible, np.ndarray):
        return bool(len(later) and np.asarray(visible, dtype=bool)[later].any())
    return any(node in visible for node in later)


def max_product_plans(weights: np.ndarray, targets=None) -> Plans:
    """Best (max-product) plans from every node to each target, for all targets at once.

    Dijkstra backwards from each target on costs ``-log w`` (weights must lie in [0, 1]):
    repeatedly settle the unsettled node with the largest value, then relax its
    predecessors. Ties settle the lowest node index first and a value is replaced only by
    a strictly larger one, so the result is deterministic.
    """
    w = np.asarray(weights, dtype=np.float64)
    n = w.shape[0]
    if w.shape != (n, n):
        raise ValueError(f"weights must be square, got {w.shape}")
    if np.any(w < 0) or np.any(w > 1 + 1e-12):
        raise ValueError("edge weights must lie in [0, 1] for max-product planning")
    targets = np.arange(n) if targets is None else np.atleast_1d(np.asarray(targets, dtype=np.int64))
    num_t = len(targets)
    rows = np.arange(num_t)
    values = np.zeros((num_t, n))
    values[rows, targets] = 1.0
    next_node = np.full((num_t, n), -1, dtype=np.int64)
    settled = np.zeros((num_t, n), dtype=bool)
    off_diag = ~np.eye(n, dtype=bool)
    for _ in range(n):
        open_values = np.where(settled, -1.0, values)
        u = open_values.argmax(axis=1)  # (T,)
        active = open_values[rows, u] > 0
        if not active.any():
            break
        settled[rows[active], u[active]] = True
        # Predecessors i of u: candidate value w[i, u] * value[u].
        cand = w[:, u].T * values[rows, u][:, None]  # (T, n)
        better = (cand > values) & ~settled & active[:, None] & off_diag[u]
        values = np.where(better, cand, values)
        next_node = np.where(better, u[:, None], next_node)
    return Plans(values=values, next_node=next_node, targets=targets)


class GoalsRelationalGraph:
    """Dirichlet-categorical edge model over ``num_nodes`` nodes, counted from options.

    Args:
        num_nodes: number of nodes (grid world: 16 goals + the back-up "random" node).
        max_option_steps: K, the number of "first seen after k steps" categories.
        gamma: discount of the event values ``gamma^(k-1)``.
        prior: the Dirichlet pseudo-counts alpha, length K + 1 (default ``(0, ..., 0, 1)``:
            one pseudo-count on "not seen", so an edge never observed weighs 0).
        observable: number of nodes that can be seen (the first ``observable`` node ids);
            the others (the "random" node) are never counted as seen, so edges into them
            keep the prior's weight (0).
    """

    def __init__(
        self,
        num_nodes: int,
        max_option_steps: int = 10,
        gamma: float = 0.99,
        prior=None,
        observable: int | None = None,
    ):
        self.num_nodes = int(num_nodes)
        self.max_option_steps = int(max_option_steps)
        self.gamma = float(gamma)
        k = self.max_option_steps
        if prior is None:
            prior = np.zeros(k + 1)
            prior[-1] = 1.0
        self.prior = np.asarray(prior, dtype=np.float64)
        if self.prior.shape != (k + 1,) or np.any(self.prior < 0) or self.prior.sum() <= 0:
            raise ValueError(f"prior must be {k + 1} non-negative pseudo-counts with a positive sum")
        self.observable = self.num_nodes if observable is None else int(observable)
        self.counts = np.zeros((self.num_nodes, self.num_nodes, k + 1), dtype=np.int64)

    # -- counting -----------------------------------------------------------------------
    def add_counts(self, source, target, category, count=1) -> None:
        """Add ``count`` to ``counts[source, target, category]`` (arrays broadcast;
        repeated index triples accumulate). ``category`` is 0-based: ``k - 1`` for "first
        seen after k steps", ``K`` for "not seen"."""
        np.add.at(self.counts, (np.asarray(source), np.asarray(target), np.asarray(category)), count)

    def record_options(self, sources, first_seen) -> None:
        """Count finished options.

        Args:
            sources: int (B,): the node each option chased.
            first_seen: int (B, observable): for every observable node, the number of
                low-level steps after which it was first seen during that option (1..K),
                or ``NOT_SEEN`` (0) if it never was.
        """
        sources = np.atleast_1d(np.asarray(sources, dtype=np.int64))
        first_seen = np.asarray(first_seen, dtype=np.int64).reshape(len(sources), -1)
        if first_seen.shape[1] != self.observable:
            raise ValueError(f"first_seen must have {self.observable} columns, got {first_seen.shape[1]}")
        if np.any(first_seen < 0) or np.any(first_seen > self.max_option_steps):
            raise ValueError(f"first_seen values must lie in 0..{self.max_option_steps}")
        category = np.where(first_seen == NOT_SEEN, self.max_option_steps, first_seen - 1)
        src = np.broadcast_to(sources[:, None], first_seen.shape)
        tgt = np.broadcast_to(np.arange(self.observable), first_seen.shape)
        self.add_counts(src.ravel(), tgt.ravel(), category.ravel())

    def record_option(self, source: int, first_seen) -> None:
        """Count one finished option (see ``record_options``)."""
        self.record_options([source], np.asarray(first_seen)[None, :])

    # -- the model ----------------------------------------------------------------------
    def posterior_mean(self) -> np.ndarray:
        """float (n, n, K+1): E[theta_ij | counts] = (alpha + c_ij) / sum(alpha + c_ij)."""
        post = self.prior + self.counts
        return post / post.sum(axis=2, keepdims=True)

    def edge_weights(self) -> np.ndarray:
        """float (n, n): w_ij = sum_k P(k) gamma^(k-1) over k = 1..K; w_ii = 1."""
        k = self.max_option_steps
        event_values = self.gamma ** np.arange(k)  # gamma^(k-1), k = 1..K
        w = self.posterior_mean()[:, :, :k] @ event_values
        np.fill_diagonal(w, 1.0)
        return np.clip(w, 0.0, 1.0)

    def plans(self, targets=None) -> Plans:
        """Max-product plans from every node to each of ``targets`` (default: all nodes)."""
        return max_product_plans(self.edge_weights(), targets)

    def plan(self, node: int, target: int) -> tuple[list[int], float]:
        """The best plan ``[node, ..., target]`` and its value C."""
        p = self.plans([target])
        return p.path(node, target), float(p.values[0, node])

    # -- files --------------------------------------------------------------------------
    def state_dict(self) -> dict[str, np.ndarray]:
        return {
            "counts": self.counts.copy(),
            "prior": self.prior.copy(),
            "gamma": np.float64(self.gamma),
            "observable": np.int64(self.observable),
        }

    @classmethod
    def from_state_dict(cls, state: dict) -> "GoalsRelationalGraph":
        counts = np.asarray(state["counts"], dtype=np.int64)
        graph = cls(
            counts.shape[0],
            max_option_steps=counts.shape[2] - 1,
            gamma=float(state["gamma"]),
            prior=np.asarray(state["prior"]),
            observable=int(state["observable"]),
        )
        graph.counts[...] = counts
        return graph

    def save(self, path: str | os.PathLike) -> None:
        """Write the graph (counts, prior, gamma) to a compressed ``.npz`` file atomically, and
        record its digest in ``SHA256SUMS`` beside it."""
        with atomic_write(path, "wb") as f:
            np.savez_compressed(f, **self.state_dict())
        digests.record(path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> "GoalsRelationalGraph":
        path = Path(path)
        try:
            digests.verify(path)
            with np.load(path, allow_pickle=False) as data:
                return cls.from_state_dict({key: data[key] for key in ("counts", "prior", "gamma", "observable")})
        except (OSError, ValueError, KeyError) as err:
            raise UserError(
                f"cannot read GRG file {path}: {err}; expected an .npz written by GoalsRelationalGraph.save"
            ) from None
