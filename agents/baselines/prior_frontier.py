"""``room_prior_frontier`` and ``object_prior_frontier``: frontier exploration toward where the
target usually is, by priors counted on the suite's training houses.

A semantic frontier explorer (SemExp's recipe, without the learning): ``grg_frontier``'s map of
what was seen where and its frontier score (``agents/baselines/grg_frontier.py``), with a prior counted
from the training houses in place of the GRG. No ground truth is read at test time: the agent
sees categories (``semantic``) and infers from them where it is.

* **Room prior** (``room_prior_frontier``): how likely the target stands in the same room as a
  category seen, ``sum_r P(r | c) * P(g in a room | r)``: ``P(r | c)`` is the share of ``c``'s
  instances that stand in rooms of type ``r`` (which room the agent is in, from what it sees),
  ``P(g in a room | r)`` the share of rooms of type ``r`` that hold a ``g`` (which room types
  hold the target). Room placement alone decides it: it holds in ``roomwise`` houses too.
* **Object prior** (``object_prior_frontier``): how likely an instance of the target stands
  within ``NEAR`` metres of an instance of the category seen (a cup near a coffee table, an
  alarm clock near a bed): object-object relations, which ``roomwise`` houses break.
* **No prior** (``inspect_frontier``, the control): every object category relates with
  ``UNIFORM``; what the two priors gain over it is what the prior, not the close look, buys.

All three also look closely (``PriorSlotState``): a small target is seen only from about a
metre, so besides frontiers they weigh close views of the furniture their prior relates to it.

Both priors are counted once per suite (``counted_priors``) on the functional placement of the
suite's training houses (``training_refs``; for ``house-large-roomwise`` and ``-shuffled``, the
same seeds as ``house-large``'s; for a suite without training houses, those of the suite made
for unseen houses of its generator): the agent learns where things go in real homes and is
tested, on the other placements, in houses where they are not. Results: ``docs/large_houses.md``.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from objsearch.errors import UserError
from objsearch.eval.agent import AgentTask
from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID, ROOM_TYPES
from objsearch.sim.env import NUM_CATEGORY_IDS
from objsearch_agents.baselines.frontier import STEPS, FrontierAgent, turns
from objsearch_agents.baselines.grg_frontier import GRGFrontierConfig, GRGSlotState

NEAR = 1.5  # metres between object centres: "near" for the object prior
UNIFORM = 0.5  # the uniform control's relation of every category to every target
PRIORS = ("room", "object", "uniform")


@dataclass(frozen=True)
class PriorFrontierConfig(GRGFrontierConfig):
    """``grg_frontier``'s settings, with the weights of a counted prior (probabilities, not plan
    values), and the close look at what the target stands by."""

    relation: str = "room"
    """The prior: ``room`` (same room as a category seen) or ``object`` (within ``NEAR`` m of one)."""
    relation_weight: float = 40.0
    min_relation: float = 0.1
    inspect_weight: float = 40.0
    """Steps a close view of a cell whose category relates with value 1 is worth (0: no close looks)."""
    inspect_range: float = 1.2
    """Cells seen nearer than this (metres) have been looked at closely: a small target there would show."""


def ahead_of(grid: np.ndarray, k: int, reach: int) -> np.ndarray:
    """``grid`` seen from ``reach`` cells behind along heading ``k``: ``out[i, j] = grid[(i, j) + reach * STEPS[k]]`` (0 outside)."""
    di, dj = STEPS[k] * reach
    h, w = grid.shape
    out = np.zeros_like(grid)
    out[max(-di, 0) : h + min(-di, 0), max(-dj, 0) : w + min(-dj, 0)] = grid[
        max(di, 0) : h + min(di, 0), max(dj, 0) : w + min(dj, 0)
    ]
    return out


class PriorSlotState(GRGSlotState):
    """``grg_frontier``'s episode state, and which cells were seen from close by.

    Besides the frontier poses (scored by the prior as ``grg_frontier`` scores them), it weighs
    close views: a reachable pose facing, 1-3 cells ahead, a cell where a related category was
    seen and that was not yet seen from within ``inspect_range``, at ``steps - inspect_weight *
    relation``. A small target stands on furniture, and is seen only from close by: the prior
    says which furniture to look at, and this is how it looks.
    """

    def __init__(self, task: AgentTask, config: PriorFrontierConfig, relation: np.ndarray):
        super().__init__(task, config, relation)
        self.inspected = np.zeros(self.seen.shape, bool)

    def update_map(self, cell, heading: int, p: dict, semantic: np.ndarray) -> None:
        super().update_map(cell, heading, p, semantic)
        close = p["valid"] & (p["range"] <= self.config.inspect_range)
        self.inspected[np.rint(p["x"][close]).astype(int), np.rint(p["y"][close]).astype(int)] = True

    def extra_goals(self, dist: np.ndarray, lo, heading: int) -> tuple | None:
        cfg = self.config
        if cfg.inspect_weight == 0 or len(self.voxels):
            return None
        box = (slice(lo[0], lo[0] + dist.shape[0]), slice(lo[1], lo[1] + dist.shape[1]))
        worth = np.where(self.inspected[box], 0.0, self.related[box])
        cells, headings, scores = [], [], []
        for k in range(4):
            score = np.maximum.reduce([ahead_of(worth, k, reach) for reach in (1, 2, 3)])
            ij = np.argwhere((score > 0) & (dist >= 0))
            cells.append(ij)
            headings.append(np.full(len(ij), k))
            scores.append(score[ij[:, 0], ij[:, 1]])
        cells, headings, scores = np.concatenate(cells), np.concatenate(headings), np.concatenate(scores)
        cost = dist[cells[:, 0], cells[:, 1]] + turns(heading, headings) - cfg.inspect_weight * scores
        return cells, headings, cost


def count_priors(specs) -> dict[str, np.ndarray]:
    """The ``room`` and ``object`` priors (float (ids, ids), ``[g, c]``: how likely target id ``g``
    is where category id ``c`` is seen) counted over the house specs ``specs``."""
    types = {t: k for k, t in enumerate(ROOM_TYPES)}
    in_type = np.zeros((NUM_CATEGORY_IDS, len(types)))  # instances of c in rooms of type r
    rooms_of_type = np.zeros(len(types))
    rooms_holding = np.zeros((NUM_CATEGORY_IDS, len(types)))  # rooms of type r holding a g
    instances = np.zeros(NUM_CATEGORY_IDS)
    near = np.zeros((NUM_CATEGORY_IDS, NUM_CATEGORY_IDS))  # [g, c]: instances of c with a g near
    for spec in specs:
        room_type = {r.id: types[r.type] for r in spec.rooms}
        for r in spec.rooms:
            rooms_of_type[types[r.type]] += 1
        ids = np.array([CATEGORY_IDS[o.category] for o in spec.objects])
        xy = np.array([o.position[:2] for o in spec.objects])
        for o, c in zip(spec.objects, ids):
            in_type[c, room_type[o.room]] += 1
        for room in {(o.room, CATEGORY_IDS[o.category]) for o in spec.objects}:
            rooms_holding[room[1], room_type[room[0]]] += 1
        close = ((xy[:, None, :] - xy[None, :, :]) ** 2).sum(-1) <= NEAR**2
        for k, c in enumerate(ids):
            instances[c] += 1
            near[np.unique(ids[close[k]]), c] += 1
    p_type_given_c = in_type / np.maximum(instances[:, None], 1)
    p_g_given_type = rooms_holding / np.maximum(rooms_of_type[None, :], 1)
    room = p_g_given_type @ p_type_given_c.T  # [g, c]
    obj = near / np.maximum(instances[None, :], 1)
    for table in (room, obj):
        np.fill_diagonal(table, 0.0)  # the target itself: approach on sight handles it
    return {"room": room, "object": obj}


def uniform_prior() -> np.ndarray:
    """The control's table: every object category relates to every other target with ``UNIFORM``."""
    table = np.zeros((NUM_CATEGORY_IDS, NUM_CATEGORY_IDS))
    table[FIRST_OBJECT_ID:, FIRST_OBJECT_ID:] = UNIFORM
    np.fill_diagonal(table, 0.0)
    return table


def training_refs(suite: str) -> tuple:
    """The functional ``HouseRef`` of every training house of ``suite``, or, for a suite without
    any (``house-single``, a user's suite file), of the suite made for unseen houses of its
    houses' generator (``GENERALISATION_SUITES``: ``house-large`` for ``house-gen-3``); a
    ``UserError`` if there is none."""
    from objsearch.sim.suites import load_suite_file
    from objsearch.sim.world import HouseRef
    from objsearch_agents.house.agent import GENERALISATION_SUITES, suite_generator

    data = load_suite_file(suite)
    if not data["training_houses"]:
        generator = suite_generator(suite)
        if generator not in GENERALISATION_SUITES:
            raise UserError(
                f"suite {suite} lists no training houses to count a prior on, and its houses (generator "
                f"{generator or 'several'}) have no suite made for unseen houses; add training houses to the suite"
            )
        data = load_suite_file(GENERALISATION_SUITES[generator])
    refs = (HouseRef(**info) for info in data["training_houses"].values())
    # a moved house's functional twin: the same seed without the placement (its hash is the moved house's)
    return tuple(ref if ref.placement is None else replace(ref, placement=None, spec_sha256=None) for ref in refs)


@lru_cache(maxsize=4)
def counted_priors(refs: tuple) -> dict[str, np.ndarray]:
    """``count_priors`` over the houses ``refs`` (regenerated from their seeds), once per process."""
    from objsearch.sim.world import World

    return count_priors(World.load(ref).spec for ref in refs)


class PriorFrontierAgent(FrontierAgent):
    """Frontier exploration scored by a prior counted on training houses (the module docstring)."""

    config = PriorFrontierConfig()

    def __init__(self, relations: np.ndarray | None = None):
        self.relations = relations
        self.loaded_from: str | None = None
        self.weights_sha256: str | None = None

    @classmethod
    def for_suite(cls, suite: str, checkpoint=None) -> "PriorFrontierAgent":
        """The agent with the prior counted on ``suite``'s training houses (no checkpoint: ``checkpoint`` must be None)."""
        if checkpoint is not None:
            raise UserError(f"{cls.__name__} counts its prior on the suite's training houses; drop --checkpoint")
        if cls.config.relation not in PRIORS:
            raise UserError(f"unknown prior {cls.config.relation!r}; pick one of {', '.join(PRIORS)}")
        if cls.config.relation == "uniform":  # nothing to count: training-free
            return cls(uniform_prior())
        refs = training_refs(suite)
        agent = cls(counted_priors(refs)[cls.config.relation])
        agent.loaded_from = f"{cls.config.relation} prior counted on the {len(refs)} training houses of {suite}"
        agent.weights_sha256 = hashlib.sha256(agent.relations.astype(np.float64).tobytes()).hexdigest()
        return agent

    def new_slot(self, task: AgentTask) -> PriorSlotState:
        if self.relations is None:
            raise UserError(f"{type(self).__name__} has no prior; build it with for_suite(suite)")
        return PriorSlotState(task, self.config, self.relations[task.goal])


class ObjectPriorFrontierAgent(PriorFrontierAgent):
    """``object_prior_frontier``: the object prior (a target near the categories it stands by)."""

    config = PriorFrontierConfig(relation="object")


class UniformPriorFrontierAgent(PriorFrontierAgent):
    """``inspect_frontier``: the control, every category alike (close looks at all furniture, no prior)."""

    config = PriorFrontierConfig(relation="uniform")
