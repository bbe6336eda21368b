"""The grid world as the methods see it (``GridWorldAdapter``): nodes (goals ``0..G-1`` and
the back-up "random" node ``G``), the high levels' networks, their Q-values on the
17-channel images (obstacles, then one channel per goal) and their losses (Double DQN,
``core.double_dqn``, on the grid world's inputs; ``flat_loss`` also trains the low level)."""

from __future__ import annotations

import numpy as np
import torch

from objsearch_agents.core.double_dqn import Learner, candidate_argmax, candidate_double_dqn_loss, double_dqn_loss
from objsearch_agents.core.grg import GoalsRelationalGraph
from objsearch_agents.core.nets import as_tensor, seeded_init
from objsearch_agents.gridworld.inputs import candidate_inputs, candidates, visible_goals
from objsearch_agents.gridworld.nets import grg_high_net, hdqn_high_net


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
        return candidate_argmax(net, candidate_score(images, weights), cand)

    def visible_nodes(self, images: np.ndarray) -> np.ndarray:
        """bool (N, G+1): goals in the 7x7 window ("random" never)."""
        vis = visible_goals(images)
        return np.concatenate([vis, np.zeros((len(vis), 1), dtype=bool)], axis=1)

    def loss_plan_values(self, plan_values: np.ndarray, batch: dict) -> np.ndarray:
        """(G, G+1): the plan values to each goal (the loss picks each transition's goal's row)."""
        return plan_values[: self.num_goals]

    def node_q_loss(self, learner, batch: dict, tables) -> torch.Tensor:
        """h-DQN's high level: 17-channel image + one-hot goal -> G+1 Q-values; the next value
        maximises over the candidates visible in the next observation."""
        onehot = as_tensor(np.eye(self.num_goals)[batch["goal"]])
        nxt = batch["next_obs"]
        return double_dqn_loss(
            learner,
            (as_tensor(batch["obs"]), onehot),
            batch["subgoal"],
            (as_tensor(nxt), onehot),
            batch,
            candidates(nxt),
        )

    def candidate_q_loss(self, learner, batch: dict, tables, weights: np.ndarray) -> torch.Tensor:
        """HRL-GRG's high level: one Q per (obstacles, candidate channel * weight); ``weights``
        (G, G+1): the relation weights toward each goal (``loss_plan_values``), each transition
        taking its goal's row."""
        weights = weights[batch["goal"]]
        nxt = batch["next_obs"]
        return candidate_double_dqn_loss(
            learner,
            candidate_score(batch["obs"], weights),
            candidate_score(nxt, weights),
            batch["subgoal"],
            candidates(nxt),
            batch,
        )


def candidate_score(images: np.ndarray, weights: np.ndarray):
    """``score(net, rows, nodes)``: the Q of (row, node) pairs of ``images`` (``core.double_dqn``)."""
    return lambda net, rows, nodes: net(torch.from_numpy(candidate_inputs(images, weights, rows, nodes)))[:, 0]


def flat_loss(learner: Learner, batch: dict) -> torch.Tensor:
    """Double DQN on the 4-action Q-network on 2-channel inputs (DQN; the low level)."""
    return double_dqn_loss(learner, (as_tensor(batch["obs"]),), batch["action"], (as_tensor(batch["next_obs"]),), batch)
