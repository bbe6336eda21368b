"""Batched decisions of the house agents: N episodes, one forward pass per level per step.

Training (N parallel episodes on tables of every pose) and evaluation (N = 1, on tables
of the 4 frames the agent was given) run this same code, so what is trained is what is
evaluated. Observations are rows of an ``ObservationTables`` and ``hist`` (N, 4) pose ids;
nodes and network inputs are ``house.world``'s.

What differs by method is its strategy (``objsearch_agents.methods``: ``a3c``, ``dqn``,
``hdqn``, ``hrl_grg``); this module holds what they share. Hierarchical methods: envs
without a sub-goal pick one among the candidates (object categories visible in the last 4
frames, not already reached at this pose unless it is the target, plus ``RANDOM``) as the
method chooses; the low level (the actor-critic) acts on the sub-goal's mask, or on depth
alone for ``RANDOM``. An option ends when its sub-goal is reached (``REACH_RULE``, judged
from the observation), after ``option_steps``, when the episode ends, or when the method
ends it (HRL-GRG's plan termination); ended options are counted into the GRG, if any.
"""

from __future__ import annotations

import numpy as np
import torch

from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch_agents.core.nets import as_tensor, seeded_init
from objsearch_agents.core.rows import rows_of
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.episodes import object_node
from objsearch_agents.house.nets import ActorCritic
from objsearch_agents.house.tables import NUM_OBJECTS, VISIBLE_PIXELS, ObservationTables
from objsearch_agents.house.world import (
    HOUSE,
    NUM_NODES,
    RANDOM,
    candidates,
    low_input,
    node_category,
    sample_actions,
)
from objsearch_agents.methods import method_of


class HousePolicy:
    """Networks, GRG and the per-episode option state of N house episodes."""

    def __init__(self, config: HouseAgentConfig):
        self.config = c = config
        self.method = m = method_of(c.method)
        self.world = HOUSE
        self.perception_key: str | None = None
        """Loaded from a policy trained on predicted observations: the key of the perception network it learned from."""
        self.ac = seeded_init(ActorCritic, c.seed) if m.actor_critic else None
        self.explore = seeded_init(ActorCritic, c.seed + 2) if m.hierarchical and c.explorer else None
        self.q = m.q_network(c, HOUSE)
        self.grg = m.graph(c, HOUSE)
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
        choice = self.method.choose_subgoals(self, (tables, h), targets, cand, explore, noise, need)
        self.subgoal[need] = choice
        self.option_steps[need] = 0
        self.first_seen[need] = 0

    def acting_category(self) -> np.ndarray:
        """The category the actor-critic is pointed at: the target (A3C) or the sub-goal."""
        return self.method.acting_category(self)

    @torch.no_grad()
    def actions(
        self, tables: ObservationTables, hist: np.ndarray, epsilon: np.ndarray, rng
    ) -> tuple[np.ndarray, tuple | None]:
        """Primitive actions (DQN epsilon-greedy; the actor-critic's sampled from its policy)
        and the actor-critic's inputs they were chosen from (None for DQN)."""
        return self.method.actions(self, (tables, hist), epsilon, rng)

    @torch.no_grad()
    def actor_critic_actions(self, tables: ObservationTables, hist: np.ndarray, rng) -> tuple[np.ndarray, tuple]:
        """Actions sampled from the actor-critic pointed at ``acting_category``; the back-up
        node's options run the explorer instead, if there is one."""
        inputs = low_input(tables, hist, self.acting_category())
        logits, _ = self.ac(*map(as_tensor, inputs))
        if self.explore is not None:  # the back-up node's options: the explorer's policy
            rows = np.flatnonzero(self.subgoal == RANDOM)
            if len(rows):
                explore_in = [x[rows] for x in inputs]
                if self.config.explorer_target:  # the explorer searches for the target: its mask, the same depth
                    explore_in[0] = tables.masks(hist[rows], self.target[rows])
                logits[rows] = self.explore(*map(as_tensor, explore_in))[0]
        return sample_actions(logits, rng), inputs

    def advance(self, tables: ObservationTables, hist: np.ndarray, episode_over: np.ndarray, count: bool) -> np.ndarray:
        """Update the options after an env step (``hist``: the histories it led to). Ends
        options, counts them into the GRG if ``count``; returns bool (N,): options ended.
        ``self.reached`` is then bool (N,): options whose (non-target) sub-goal was reached."""
        if not self.method.hierarchical:
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
        ended_by_method = self.method.ends_options(self, (tables, hist), sg)
        if ended_by_method is not None:
            ended |= active & ended_by_method
        if count and self.grg is not None and ended.any():
            ix = np.flatnonzero(ended)
            self.grg.record_options(self.subgoal[ix], self.first_seen[ix])
        self.subgoal[ended] = -1
        return ended
