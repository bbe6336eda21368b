"""``grg_frontier``: the ``frontier`` agent whose choice of frontier is scored by the GRG.

The modular ObjectNav recipe of SemExp and L3MVN (score exploration frontiers by how likely
the target lies near what has been seen there), with HRL-GRG's Goals Relational Graph as the
prior instead of a learned network or a language model. Everything else is ``frontier``'s
(``agents/baselines/frontier.py``): the map, approach on sight, recovery.

* **Relation.** ``relation[c]`` of a seen object category ``c`` to the episode's target ``g``
  is the GRG's plan value ``C(c -> g)`` (``relation="plan"``, the max-product plan of
  ``GoalsRelationalGraph.plans``) or its direct edge weight ``w(c -> g)`` (``"edge"``): how
  soon ``g`` comes into view while the agent heads for ``c``, learned from search in the
  training houses. Structure (walls, floor, doors), the target itself and categories that
  relate less than ``min_relation`` count 0 (the weak relations only perturbed the order).
* **Memory.** Each map cell keeps the strongest relation among the categories seen there
  (pixels of a category that fills ``min_category_pixels`` of a frame, projected by depth as
  ``frontier`` projects obstacles).
* **Score.** A frontier pose's score is the strongest relation kept within
  ``relation_radius`` metres of its cell, and the agent goes to the pose of least
  ``steps - relation_weight * score``: a frontier beside a category that relates with value
  1 is worth ``relation_weight`` steps of detour. ``relation_weight = 0`` is ``frontier``.
  Only while the target has not been seen: once it has, what relates to it lies beside the
  instance found, so exploring on for another instance goes by distance alone.

The GRG is the one the shipped ``hrl_grg_explorer`` run counted on the suite's training
houses (``agents/checkpoints/<suite>/hrl_grg_explorer/grg.npz``), or, for a suite without
one, that of the run made for unseen houses of its generator (``house-gen-v2``'s for every
``house-gen-2`` suite, ``house-gen-v2-shuffled`` included); ``--checkpoint`` names another
``grg.npz``. Deterministic but for ``frontier``'s recovery moves (``task.rng``), so records do
not depend on the batch. Results and tuning: ``docs/grg_frontier.md``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.ndimage import maximum_filter

from objsearch import digests
from objsearch.errors import UserError
from objsearch.eval.agent import AgentTask
from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch.sim.env import NUM_CATEGORY_IDS
from objsearch_agents.baselines.frontier import CELL, FrontierAgent, FrontierConfig, SlotState
from objsearch_agents.core.grg import GoalsRelationalGraph

GRG_RUN = "hrl_grg_explorer"  # the shipped training run whose GRG is used
GRG_FILE = "grg.npz"
RELATIONS = ("plan", "edge")


@dataclass(frozen=True)
class GRGFrontierConfig(FrontierConfig):
    """``frontier``'s settings and the relation score's (the defaults are what the leaderboard ran)."""

    relation: str = "plan"
    """How a seen category relates to the target: ``plan`` (the GRG's plan value C(c -> g)) or
    ``edge`` (its edge weight w(c -> g))."""
    relation_weight: float = 80.0
    """Steps a frontier pose's relation score of 1 is worth (0: choose as ``frontier`` does)."""
    relation_radius: float = 2.0
    """A frontier pose scores the categories seen this close to its cell (metres)."""
    min_relation: float = 0.5
    """Categories that relate to the target less than this count 0 (the GRG's weak relations are
    mostly noise of what happened to be in view)."""
    min_category_pixels: int = 20
    """A category counts as seen in a frame when it covers this many pixels (the house agents'
    ``VISIBLE_PIXELS``)."""


def relation_table(grg: GoalsRelationalGraph, relation: str = "plan") -> np.ndarray:
    """float (ids, ids): ``[g, c]`` = how category id ``c`` relates to target id ``g`` (the plan
    value C(c -> g) or the edge weight w(c -> g)); 0 for ids without a GRG node and for c == g."""
    nodes = NUM_CATEGORY_IDS - FIRST_OBJECT_ID
    if grg.observable != nodes:
        raise UserError(
            f"the GRG has {grg.observable} object nodes, the category table {nodes}; "
            "pass a grg.npz trained on house suites of this version"
        )
    if relation == "plan":
        values = grg.plans(np.arange(nodes)).values[:, :nodes]  # [target node, node]
    elif relation == "edge":
        values = grg.edge_weights()[:nodes, :nodes].T
    else:
        raise UserError(f"unknown relation {relation!r}; pick one of {', '.join(RELATIONS)}")
    table = np.zeros((NUM_CATEGORY_IDS, NUM_CATEGORY_IDS))
    table[FIRST_OBJECT_ID:, FIRST_OBJECT_ID:] = values
    np.fill_diagonal(table, 0.0)  # the target itself: approach on sight handles it
    return table


class GRGSlotState(SlotState):
    """``frontier``'s episode state, and how related to the target what was seen in each cell is."""

    def __init__(self, task: AgentTask, config: GRGFrontierConfig, relation: np.ndarray):
        super().__init__(task, config)
        # (ids,): each category id's relation to this episode's target, weak ones dropped
        self.relation = np.where(relation >= config.min_relation, relation, 0.0)
        self.related = np.zeros(self.seen.shape, np.float32)  # the strongest relation seen in each cell
        r = int(np.floor(config.relation_radius / CELL))
        di, dj = np.mgrid[-r : r + 1, -r : r + 1]
        self.footprint = di**2 + dj**2 <= (config.relation_radius / CELL) ** 2

    def update_map(self, cell, heading: int, p: dict, semantic: np.ndarray) -> None:
        super().update_map(cell, heading, p, semantic)
        labels = np.where(p["valid"] & (semantic >= 0) & (semantic < len(self.relation)), semantic, 0)
        pixels = np.bincount(labels.ravel(), minlength=len(self.relation))
        seen = (pixels >= self.config.min_category_pixels) & (self.relation > 0)
        shown = seen[labels]
        self.note(np.rint(p["x"][shown]).astype(int), np.rint(p["y"][shown]).astype(int), labels[shown])

    def note(self, i: np.ndarray, j: np.ndarray, categories: np.ndarray) -> None:
        """Categories (ids) seen in map cells (i, j)."""
        np.maximum.at(self.related, (i, j), self.relation[categories].astype(np.float32))

    def relation_scores(self, cells: np.ndarray) -> np.ndarray:
        """The strongest relation kept within ``relation_radius`` of each of ``cells`` (map coordinates)."""
        r = self.footprint.shape[0] // 2
        lo, hi = np.maximum(cells.min(0) - r, 0), np.minimum(cells.max(0) + r + 1, self.related.shape)
        near = maximum_filter(self.related[lo[0] : hi[0], lo[1] : hi[1]], footprint=self.footprint, mode="constant")
        return near[cells[:, 0] - lo[0], cells[:, 1] - lo[1]]

    def frontier_cost(self, cells: np.ndarray, cost: np.ndarray) -> np.ndarray:
        if self.config.relation_weight == 0 or len(self.voxels):
            # once the target is seen, what relates to it is beside the instance found: exploring
            # on for another one, as frontier does, it would be drawn back there
            return cost
        return cost - self.config.relation_weight * self.relation_scores(cells)


class GRGFrontierAgent(FrontierAgent):
    """Frontier exploration scored by the GRG's relations (``objsearch-eval --agent grg_frontier``).

    Args:
        grg: the Goals Relational Graph (``for_suite`` loads the one shipped for a suite).
    """

    config = GRGFrontierConfig()
    training_free = False  # its GRG is learned (HRL-GRG's training runs)

    def __init__(self, grg: GoalsRelationalGraph | None = None):
        self.grg = grg
        self.relations = None if grg is None else relation_table(grg, self.config.relation)
        self.loaded_from: str | None = None
        self.weights_sha256: str | None = None

    @classmethod
    def for_suite(cls, suite: str, checkpoint: str | os.PathLike | None = None) -> "GRGFrontierAgent":
        """The agent with the GRG for ``suite`` (``grg_file``)."""
        path = grg_file(suite, checkpoint)
        agent = cls(GoalsRelationalGraph.load(path))
        agent.loaded_from, agent.weights_sha256 = str(path), digests.of_files([path])
        return agent

    def new_slot(self, task: AgentTask) -> GRGSlotState:
        if self.relations is None:
            raise UserError("grg_frontier has no GRG; build it with GRGFrontierAgent.for_suite(suite) or pass one")
        return GRGSlotState(task, self.config, self.relations[task.goal])


def grg_file(suite: str, checkpoint: str | os.PathLike | None = None) -> Path:
    """The GRG for ``suite``: ``checkpoint`` (a ``grg.npz`` or a run folder holding one) if
    given, else the shipped ``hrl_grg_explorer`` run's for the suite, else that of the run made
    for unseen houses of the suite's generator; a ``UserError`` when there is none."""
    if checkpoint is not None:
        path = Path(checkpoint)
        path = path / GRG_FILE if path.is_dir() else path
        if not path.is_file():
            raise UserError(f"--checkpoint {checkpoint}: no GRG file there; pass a grg.npz or a run folder holding one")
        return path
    from objsearch_agents.house.agent import checkpoint_source, default_checkpoint, generalisation_checkpoint

    policy = default_checkpoint(suite, GRG_RUN)
    if policy is None:
        policy, generator = generalisation_checkpoint(suite, GRG_RUN)
        if policy is None:
            raise UserError(
                f"grg_frontier: no GRG is {checkpoint_source()} for suite {suite} (houses of generator {generator or 'several'}); "
                f"train one on its training houses with `objsearch train --agent {GRG_RUN} --suite {suite}` and pass "
                "--checkpoint RUN_FOLDER"
            )
    path = policy.parent / GRG_FILE
    if not path.is_file():
        raise UserError(f"grg_frontier: the {GRG_RUN} run {policy.parent} has no {GRG_FILE}")
    return path
