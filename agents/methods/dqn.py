"""DQN (paper sec. 4.1): Double DQN over the primitive actions, epsilon-greedy. Flat: no
options, no graph.

* Grid world: the Q-network on (obstacles, final-goal channel) is the low-level network,
  initialised from the pretrained goal-reaching low level (``q_network``: none beside it).
* Houses: ``CategoryQ`` on every category's mask, the depth and the target's one-hot,
  trained from scratch; no actor-critic.
"""

from __future__ import annotations

import numpy as np

from objsearch_agents.methods.base import Method


class DQN(Method):
    name = "dqn"
    actor_critic = False

    def q_network(self, config, world):
        return world.action_q_net(config.seed + 1)

    def actions(self, policy, obs, epsilon, rng):
        q = policy.world.action_q(policy.q, obs, policy.target)
        n, num_actions = q.shape
        explore = rng.random(n) < epsilon
        return np.where(explore, rng.integers(num_actions, size=n), q.argmax(axis=1)), None

    def q_loss(self, learner, batch, policy, tables):
        return policy.world.action_q_loss(learner, batch, tables)


METHOD = DQN()
