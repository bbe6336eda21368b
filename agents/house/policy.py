"""Batched decisions of the house agents: N episodes, one forward pass per level per step.

Training (N parallel episodes on tables of every pose) and evaluation (N = 1, on tables
of the 4 frames the agent was given) run this same code, so what is trained is what is
evaluated. Observations are rows of an ``ObservationTables`` and ``hist`` (N, 4) pose ids.

Nodes (sub-goals, GRG): object categories ``0..NUM_OBJECTS-1`` (category id minus
``FIRST_OBJECT_ID``) and ``RANDOM`` = NUM_OBJECTS, the back-up sub-goal.

* ``a3c``: actions sampled from the actor-critic on (target mask, depth).
* ``dqn``: epsilon-greedy on ``CategoryQ`` (every mask, depth, target one-hot).
* ``hdqn`` / ``hrl_grg``: envs without a sub-goal pick one among the candidates (object
  categories visible in the last 4 frames, not already reached at this pose unless it is
  the target, plus ``RANDOM``): h-DQN by its 62 Q-values (uniformly when exploring),
  HRL-GRG by scoring each candidate's mask times its plan value C(sg -> g) (exploring:
  softmax over the plan values). The low level (the actor-critic) acts on the sub-goal's
  mask, or on depth alone for ``RANDOM``. An option ends when its sub-goal is reached
  (``REACH_RULE``, judged from the observation), after ``option_steps``, when the episode
  ends, or (HRL-GRG) when a later node of the sub-goal's plan to the target is in view.
"""

from __future__ import annotations

import numpy as np
import torch

from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch_agents.grg import GoalsRelationalGraph
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.episodes import object_node
from objsearch_agents.house.nets import NUM_ACTIONS, ActorCritic, CandidateQ, CategoryQ
from objsearch_agents.house.tables import (
    DEPTH_SCALE,
    NUM_CATEGORIES,
    NUM_OBJECTS,
    REACH_RULE,
    VISIBLE_PIXELS,
    ObservationTables,
)
from objsearch_agents.nets import seeded_init
from objsearch_agents.rows import rows_of

RANDOM = NUM_OBJECTS
NUM_NODES = NUM_OBJECTS + 1


def node_category(nodes: np.ndarray) -> np.ndarray:
    """Category id of each node (-1 for ``RANDOM``: an all-zero mask)."""
    nodes = np.asarray(nodes)
    return np.where(nodes < RANDOM, nodes + FIRST_OBJECT_ID, -1)


def _t(x: np.ndarray) -> torch.Tensor:
    return torch.from_numpy(np.ascontiguousarray(x, dtype=np.float32))


def depth_input(tables: ObservationTables, hist: np.ndarray) -> np.ndarray:
    return tables.depth[hist] / np.float32(DEPTH_SCALE)


def low_input(tables: ObservationTables, hist: np.ndarray, categories: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(mask (N, 4, 10, 10), depth (N, 4, 10, 10)): the actor-critic's input."""
    return tables.masks(hist, categories), depth_input(tables, hist)


def category_input(tables: ObservationTables, hist: np.ndarray, targets: np.ndarray) -> tuple[torch.Tensor, ...]:
    """``CategoryQ``'s input: the categories in view and their masks, depth, the target's one-hot."""
    onehot = np.eye(NUM_CATEGORIES, dtype=np.float32)[targets]
    cats, masks = tables.present_masks(hist)
    return torch.from_numpy(cats), _t(masks), _t(depth_input(tables, hist)), _t(onehot)


def candidates(tables: ObservationTables, hist: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """bool (N, NUM_NODES): object categories visible in the 4 frames, less those already
    reached at the current pose (except the target), plus ``RANDOM``."""
    vis = tables.visible(hist)[:, FIRST_OBJECT_ID:]
    reached = tables.near[hist[:, -1], FIRST_OBJECT_ID:] >= REACH_RULE.min_pixels
    reached[np.arange(len(targets)), object_node(targets)] = False
    return np.concatenate([vis & ~reached, np.ones((len(hist), 1), bool)], axis=1)


def candidate_inputs(
    tables: ObservationTables, hist: np.ndarray, env_ix: np.ndarray, node_ix: np.ndarray, weights: np.ndarray
) -> tuple[torch.Tensor, torch.Tensor]:
    """``CandidateQ``'s input for (env, node) pairs: the node's mask times its weight
    (``RANDOM``: ones times its weight), and depth."""
    cats = node_category(node_ix)
    mask = tables.masks(hist[env_ix], cats)
    mask[cats < 0] = 1.0
    mask *= weights[env_ix, node_ix][:, None, None, None].astype(np.float32)
    return _t(mask), _t(depth_input(tables, hist[env_ix]))


class HousePolicy:
    """Networks, GRG and the per-episode option state of N house episodes."""

    def __init__(self, config: HouseAgentConfig):
        self.config = c = config
        self.perception_key: str | None = None
        """Loaded from a policy trained on predicted observations: the key of the perception network it learned from."""
        self.ac = seeded_init(ActorCritic, c.seed) if c.method != "dqn" else None
        self.explore = seeded_init(ActorCritic, c.seed + 2) if c.hierarchical and c.explorer else None
        self.q = None
        if c.method == "dqn":
            self.q = seeded_init(CategoryQ, c.seed + 1, NUM_CATEGORIES, NUM_ACTIONS)
        elif c.method == "hdqn":
            self.q = seeded_init(CategoryQ, c.seed + 1, NUM_CATEGORIES, NUM_NODES)
        elif c.method == "hrl_grg" and c.high_level:
            self.q = seeded_init(CandidateQ, c.seed + 1)
        self.grg = None
        if c.method == "hrl_grg":
            self.grg = GoalsRelationalGraph(NUM_NODES, c.option_steps, c.grg_gamma, observable=NUM_OBJECTS)
        self.refresh_plans()
        self.start(0)

    # -- GRG plans --------------------------------------------------------------------------
    def refresh_plans(self) -> None:
        """Re-plan from every node to every object target with the current GRG."""
        if self.grg is None:
            return
        plans = self.grg.plans(np.arange(NUM_OBJECTS))
        self.plan_values = plans.values  # (target node, node)
        self.plan_successors = plans.successors()  # (target node, node, node)

    def relation_weights(self, values: np.ndarray) -> np.ndarray:
        return values if self.config.relation else np.ones_like(values)

    # -- episode state ----------------------------------------------------------------------
    def start(self, num_envs: int) -> None:
        n = num_envs
        self.target = np.zeros(n, np.int64)  # category id
        self.subgoal = np.full(n, -1, np.int64)  # node
        self.option_steps = np.zeros(n, np.int64)
        self.first_seen = np.zeros((n, NUM_OBJECTS), np.int64)
        self.values = np.zeros((n, NUM_NODES))
        self.successors = np.zeros((n, NUM_NODES, NUM_NODES), bool)

    def begin_episodes(self, env_ids: np.ndarray, targets: np.ndarray) -> None:
        """New episodes: no sub-goal yet; snapshot the plans to their targets."""
        self.target[env_ids] = targets
        self.subgoal[env_ids] = -1
        self.option_steps[env_ids] = 0
        self.first_seen[env_ids] = 0
        if self.grg is not None:
            nodes = object_node(targets)
            self.values[env_ids] = self.plan_values[nodes]
            self.successors[env_ids] = self.plan_successors[nodes]

    def state_dict(self) -> dict:
        keys = ["target", "subgoal", "option_steps", "first_seen", "values", "successors"]
        if self.grg is not None:
            keys += ["plan_values", "plan_successors"]
        return {k: getattr(self, k).copy() for k in keys}

    def load_state_dict(self, state: dict) -> None:
        for k, v in state.items():
            setattr(self, k, np.array(v))

    # -- acting -----------------------------------------------------------------------------
    @torch.no_grad()
    def select_subgoals(self, tables: ObservationTables, hist: np.ndarray, epsilon: np.ndarray, rng) -> None:
        """Give a sub-goal to every env that has none (hierarchical methods only). ``rng``: a
        Generator, or a ``RowRandom`` with one per row."""
        need = np.flatnonzero(self.subgoal < 0)
        if not len(need):
            return
        h, targets = hist[need], self.target[need]
        cand = candidates(tables, h, targets)
        rng = rows_of(rng, need)
        explore = rng.random(len(need)) < epsilon[need]
        noise = rng.random(cand.shape)
        if self.config.method == "hdqn":
            q = self.q(*category_input(tables, h, targets)).numpy()
            greedy = np.where(cand, q, -np.inf).argmax(axis=1)
            choice = np.where(explore, np.where(cand, noise, -1.0).argmax(axis=1), greedy)
        else:
            values = self.values[need]
            if self.q is not None:
                greedy = self.candidate_argmax(self.q, tables, h, cand, values)
            else:  # "-high-level": the candidate with the best plan value
                greedy = np.where(cand, values, -1.0).argmax(axis=1)
            gumbel = -np.log(-np.log(np.clip(noise, 1e-12, 1 - 1e-12)))  # softmax(plan values) by Gumbel-max
            choice = np.where(explore, np.where(cand, values + gumbel, -np.inf).argmax(axis=1), greedy)
        self.subgoal[need] = choice
        self.option_steps[need] = 0
        self.first_seen[need] = 0

    def candidate_argmax(self, net, tables, hist, cand, values) -> np.ndarray:
        """argmax over each row's candidates of ``CandidateQ``, one forward pass for all."""
        env_ix, node_ix = np.nonzero(cand)
        q = np.full(cand.shape, -np.inf, np.float32)
        q[env_ix, node_ix] = net(
            *candidate_inputs(tables, hist, env_ix, node_ix, self.relation_weights(values))
        ).numpy()
        return q.argmax(axis=1)

    def acting_category(self) -> np.ndarray:
        """The category the actor-critic is pointed at: the target (A3C) or the sub-goal."""
        return self.target if self.config.method == "a3c" else node_category(self.subgoal)

    @torch.no_grad()
    def actions(
        self, tables: ObservationTables, hist: np.ndarray, epsilon: np.ndarray, rng
    ) -> tuple[np.ndarray, tuple | None]:
        """Primitive actions (DQN epsilon-greedy; the actor-critic's sampled from its policy)
        and the actor-critic's inputs they were chosen from (None for DQN)."""
        n = len(hist)
        if self.config.method == "dqn":
            q = self.q(*category_input(tables, hist, self.target)).numpy()
            explore = rng.random(n) < epsilon
            return np.where(explore, rng.integers(NUM_ACTIONS, size=n), q.argmax(axis=1)), None
        inputs = low_input(tables, hist, self.acting_category())
        logits, _ = self.ac(*map(_t, inputs))
        if self.explore is not None:  # the back-up node's options: the explorer's policy
            rows = np.flatnonzero(self.subgoal == RANDOM)
            if len(rows):
                explore_in = [x[rows] for x in inputs]
                if self.config.explorer_target:  # the explorer searches for the target: its mask, the same depth
                    explore_in[0] = tables.masks(hist[rows], self.target[rows])
                logits[rows] = self.explore(*map(_t, explore_in))[0]
        return sample_actions(logits, rng), inputs

    def advance(self, tables: ObservationTables, hist: np.ndarray, episode_over: np.ndarray, count: bool) -> np.ndarray:
        """Update the options after an env step (``hist``: the histories it led to). Ends
        options, counts them into the GRG if ``count``; returns bool (N,): options ended.
        ``self.reached`` is then bool (N,): options whose (non-target) sub-goal was reached."""
        if not self.config.hierarchical:
            self.reached = np.zeros(len(hist), bool)
            return self.reached
        active = self.subgoal >= 0
        self.option_steps[active] += 1
        now = hist[:, -1]
        vis_now = tables.pixels[now, FIRST_OBJECT_ID:] >= VISIBLE_PIXELS
        fresh = vis_now & (self.first_seen == 0) & active[:, None]
        self.first_seen = np.where(fresh, self.option_steps[:, None], self.first_seen)
        sg = np.maximum(self.subgoal, 0)
        cats = node_category(sg)
        real = active & (sg < RANDOM) & (cats != self.target)
        reached = self.reached = real & tables.reached(now, cats)
        ended = active & (reached | (self.option_steps >= self.config.option_steps) | episode_over)
        if self.grg is not None and self.config.termination:
            vis4 = np.concatenate([tables.visible(hist)[:, FIRST_OBJECT_ID:], np.zeros((len(hist), 1), bool)], axis=1)
            later = self.successors[np.arange(len(sg)), sg]
            ended |= active & (vis4 & later).any(axis=1)
        if count and self.grg is not None and ended.any():
            ix = np.flatnonzero(ended)
            self.grg.record_options(self.subgoal[ix], self.first_seen[ix])
        self.subgoal[ended] = -1
        return ended


def sample_actions(logits: torch.Tensor, rng) -> np.ndarray:
    """One action per row from softmax(logits), drawn with ``rng`` (inverse CDF)."""
    p = torch.softmax(logits, dim=1).double().numpy()
    cdf = np.cumsum(p, axis=1)
    u = rng.random(len(p))[:, None] * cdf[:, -1:]
    return np.minimum((cdf < u).sum(axis=1), p.shape[1] - 1)
