"""The grid world as the methods see it (``GridWorldAdapter``): nodes (goals ``0..G-1`` and
the back-up "random" node ``G``), the high levels' networks, their Q-values on the
17-channel images (obstacles, then one channel per goal) and their losses."""

from __future__ import annotations

import numpy as np
import torch

from objsearch_agents.dqn_learner import grg_high_loss, hdqn_high_loss
from objsearch_agents.grg import GoalsRelationalGraph
from objsearch_agents.gridworld_inputs import as_tensor, candidate_inputs, visible_goals
from objsearch_agents.nets import grg_high_net, hdqn_high_net, seeded_init


class GridWorldAdapter:
    """The grid world's side of a method's strategy (``objsearch_agents.methods``); ``obs``:
    uint8 (N, 1 + G, 7, 7) images. A loss's ``tables`` are unused (its batch holds images)."""

    def __init__(self, num_goals: int):
        self.num_goals = num_goals
        self.num_nodes = num_goals + 1
        self.random_node = num_goals

    def action_q_net(self, seed: int):
        """None: the grid world's DQN acts and learns with the low-level network itself."""
        return None

    def node_q_net(self, seed: int):
        return seeded_init(hdqn_high_net, seed, self.num_goals)

    def candidate_q_net(self, seed: int):
        return seeded_init(grg_high_net, seed)

    def graph(self, config) -> GoalsRelationalGraph:
        return GoalsRelationalGraph(self.num_nodes, config.option_steps, config.grg_gamma, observable=self.num_goals)

    def node_q(self, net, images: np.ndarray, goals: np.ndarray) -> np.ndarray:
        onehot = np.eye(self.num_goals, dtype=np.float32)[goals]
        return net(as_tensor(images), as_tensor(onehot)).numpy()

    def candidate_argmax(self, net, images: np.ndarray, cand: np.ndarray, weights: np.ndarray) -> np.ndarray:
        """argmax over the candidates of Q(obstacles, candidate channel * weight), one forward
        pass for all (env, candidate) pairs."""
        env_ix, node_ix = np.nonzero(cand)
        inputs = candidate_inputs(images, weights, env_ix, node_ix)
        q = np.full(cand.shape, -np.inf, dtype=np.float32)
        q[env_ix, node_ix] = net(torch.from_numpy(inputs))[:, 0].numpy()
        return q.argmax(axis=1)

    def visible_nodes(self, images: np.ndarray) -> np.ndarray:
        """bool (N, G+1): goals in the 7x7 window ("random" never)."""
        vis = visible_goals(images)
        return np.concatenate([vis, np.zeros((len(vis), 1), dtype=bool)], axis=1)

    def loss_plan_values(self, plan_values: np.ndarray, batch: dict) -> np.ndarray:
        """(G, G+1): the plan values to each goal (the loss picks each transition's goal's row)."""
        return plan_values[: self.num_goals]

    def node_q_loss(self, learner, batch: dict, tables) -> torch.Tensor:
        return hdqn_high_loss(learner, batch, self.num_goals)

    def candidate_q_loss(self, learner, batch: dict, tables, weights: np.ndarray) -> torch.Tensor:
        return grg_high_loss(learner, batch, weights)
