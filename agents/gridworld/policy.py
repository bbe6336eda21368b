"""Batched decisions of the grid-world agents: N episodes, one forward pass per level per
step. Training (N parallel envs) and evaluation (N = 1, the agent protocol) run this same
code, so what is trained is exactly what is evaluated.

Observations are the 17-channel images of the grid world (obstacles, then one channel per
goal). Node ids: goals 0..G-1, and G for the back-up "random" sub-goal.

Per step of a hierarchical agent: envs without a sub-goal pick one among the candidates
(visible goals other than the one under the agent, plus "random"); the low level acts on
(obstacles, sub-goal channel), or uniformly at random for "random"; after the env step,
``advance`` ends the options whose sub-goal was reached, whose 10 steps are spent, whose
episode ended, or (HRL-GRG) where a later node of the plan from the sub-goal to the final
goal came into view, and counts the GRG (training only).
"""

from __future__ import annotations

import numpy as np
import torch

from objsearch_agents.core.nets import as_tensor, seeded_init
from objsearch_agents.core.rows import rows_of
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.gridworld.inputs import (  # noqa: F401  (imported from here too)
    CENTRE,
    candidate_inputs,
    candidates,
    goal_input,
    goals_under_agent,
    visible_goals,
)
from objsearch_agents.gridworld.nets import low_level_net
from objsearch_agents.gridworld.world import GridWorldAdapter
from objsearch_agents.methods import method_of


class GridPolicy:
    """Networks, GRG and the per-episode option state of N grid-world episodes."""

    def __init__(self, config: GridAgentConfig, num_goals: int = 16):
        self.config = config
        self.method = method_of(config.method)
        self.num_goals = g = int(num_goals)
        self.random_node = g
        self.world = GridWorldAdapter(g)
        self.low = seeded_init(low_level_net, config.seed)
        self.high = self.method.q_network(config, self.world)
        self.grg = self.method.graph(config, self.world)
        self.refresh_plans()
        self.start(0)

    @property
    def q(self):
        """The high level's Q-network, learned by Double DQN (the methods' name for it; None: none)."""
        return self.high

    # -- GRG plans ----------------------------------------------------------------------
    def refresh_plans(self) -> None:
        """Re-plan from every node to every goal with the current GRG."""
        if self.grg is None:
            return
        plans = self.grg.plans()
        self.plan_values = plans.values  # (target, node)
        self.plan_successors = plans.successors()  # (target, node, node)

    # -- episode state --------------------------------------------------------------------
    def start(self, num_envs: int) -> None:
        n, g = num_envs, self.num_goals
        self.goal = np.zeros(n, dtype=np.int64)
        self.subgoal = np.full(n, -1, dtype=np.int64)
        self.option_steps = np.zeros(n, dtype=np.int64)
        self.first_seen = np.zeros((n, g), dtype=np.int64)
        self.values = np.zeros((n, g + 1))
        self.successors = np.zeros((n, g + 1, g + 1), dtype=bool)

    def begin_episodes(self, env_ids: np.ndarray, goals: np.ndarray) -> None:
        """New episodes in ``env_ids``: no sub-goal yet; snapshot the plans to their goals
        (the reference plans once per episode)."""
        self.goal[env_ids] = goals
        self.subgoal[env_ids] = -1
        self.option_steps[env_ids] = 0
        self.first_seen[env_ids] = 0
        if self.grg is not None:
            self.values[env_ids] = self.plan_values[goals]
            self.successors[env_ids] = self.plan_successors[goals]

    def state_dict(self) -> dict:
        keys = ["goal", "subgoal", "option_steps", "first_seen", "values", "successors"]
        if self.grg is not None:  # the plans of the moment, which may predate the latest counts
            keys += ["plan_values", "plan_successors"]
        return {k: getattr(self, k).copy() for k in keys}

    def load_state_dict(self, state: dict) -> None:
        for k, v in state.items():
            setattr(self, k, np.array(v))

    # -- acting -----------------------------------------------------------------------------
    @torch.no_grad()
    def select_subgoals(self, images: np.ndarray, epsilon: np.ndarray, rng) -> None:
        """Give a sub-goal to every env that has none (hierarchical agents only). ``rng``: a
        Generator, or an ``objsearch_agents.core.rows.RowRandom`` with one per row."""
        need = np.flatnonzero(self.subgoal < 0)
        if not len(need):
            return
        imgs, cand = images[need], candidates(images[need])
        rng = rows_of(rng, need)
        explore = rng.random(len(need)) < epsilon[need]
        noise = rng.random(cand.shape)
        choice = self.method.choose_subgoals(self, imgs, self.goal[need], cand, explore, noise, need)
        self.subgoal[need] = choice
        self.option_steps[need] = 0
        self.first_seen[need] = 0

    @torch.no_grad()
    def actions(self, images: np.ndarray, epsilon: float | np.ndarray, rng) -> tuple[np.ndarray, np.ndarray]:
        """Primitive actions of all envs and the low-level inputs they were chosen from.

        Flat DQN acts on (obstacles, final-goal channel) with ``epsilon`` per env;
        hierarchical agents on (obstacles, sub-goal channel), uniformly for "random".
        """
        n = len(images)
        node = self.subgoal if self.method.hierarchical else self.goal
        low_in = goal_input(images, node)
        q = self.low(as_tensor(low_in)).numpy()
        greedy = q.argmax(axis=1)
        explore = rng.random(n) < epsilon
        random_actions = rng.integers(q.shape[1], size=n)
        act = np.where(explore | (node == self.random_node), random_actions, greedy)
        return act, low_in

    def advance(self, images: np.ndarray, episode_over: np.ndarray, count: bool) -> np.ndarray:
        """Update the options after an env step (``images``: the observations it led to,
        before any reset). Ends options, counts them into the GRG if ``count``, and returns
        bool (N,): the options that ended."""
        if not self.method.hierarchical:
            return np.zeros(len(images), dtype=bool)
        active = self.subgoal >= 0
        self.option_steps[active] += 1
        vis = visible_goals(images)
        fresh = vis & (self.first_seen == 0) & active[:, None]
        self.first_seen = np.where(fresh, self.option_steps[:, None], self.first_seen)
        sg = np.maximum(self.subgoal, 0)
        real = sg < self.num_goals
        under = goals_under_agent(images)
        reached = active & real & under[np.arange(len(sg)), np.minimum(sg, self.num_goals - 1)]
        ended = active & (reached | (self.option_steps >= self.config.option_steps) | episode_over)
        ended_by_method = self.method.ends_options(self, images, sg)  # HRL-GRG: plan termination
        if ended_by_method is not None:
            ended |= active & ended_by_method
        if count and self.grg is not None and ended.any():
            ix = np.flatnonzero(ended)
            self.grg.record_options(self.subgoal[ix], self.first_seen[ix])
        self.subgoal[ended] = -1
        return ended
