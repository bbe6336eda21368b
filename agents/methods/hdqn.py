"""h-DQN ("Hrl" in the paper's Table 3; appendix A.1): a DQN high level with one Q-value per
node (the grid world: the 17-channel image and the goal's one-hot; the houses: every
category's mask, the depth and the target's one-hot), argmax over the candidates in view,
uniform among them when exploring; the low level is pointed at the sub-goal. No graph, no
plan termination."""

from __future__ import annotations

import numpy as np
import torch

from objsearch_agents.methods.base import Method


class HDQN(Method):
    name = "hdqn"
    hierarchical = True

    def trains_actor_critic(self, config) -> bool:
        return config.train_low

    def q_network(self, config, world):
        return world.node_q_net(config.seed + 1)

    @torch.no_grad()
    def choose_subgoals(self, policy, obs, targets, cand, explore, noise, rows):
        q = policy.world.node_q(policy.q, obs, targets)
        greedy = np.where(cand, q, -np.inf).argmax(axis=1)
        uniform = np.where(cand, noise, -1.0).argmax(axis=1)
        return np.where(explore, uniform, greedy)

    def q_loss(self, learner, batch, policy, tables):
        """The next value maximises over the next state's candidates."""
        return policy.world.node_q_loss(learner, batch, tables)


METHOD = HDQN()
