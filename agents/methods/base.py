"""What a method decides, as the policies and training loops of both worlds ask it.

A method sees a world through its adapter, ``policy.world`` (``house.world.HouseWorld``,
``gridworld.world.GridWorldAdapter``): the world builds the networks and computes their
Q-values and losses on its own observations (``obs``: the house's ``(tables, hist)``, the
grid world's 17-channel images), the method says which network, which node and when.
``policy.q`` is the network the method learns by Double DQN (None: none); ``policy.values``
and ``policy.successors`` the per-episode plans of the graph, if it has one."""

from __future__ import annotations

import numpy as np


class Method:
    """A method's decisions; subclasses override what differs. Defaults: flat, no Q-network."""

    name: str = ""
    hierarchical: bool = False
    """Chooses sub-goals (options) for a low level; flat methods act directly."""
    actor_critic: bool = True
    """Houses: has the actor-critic (A3C itself, or the hierarchical low level)."""

    def agent_name(self, config) -> str:
        """The agent name ``config`` trains (ablations add their suffixes)."""
        return self.name

    def trains_actor_critic(self, config) -> bool:
        """Houses: whether the main phase updates the actor-critic."""
        return False

    def q_network(self, config, world):
        """The network learned by Double DQN beside the low level (None: none)."""
        return None

    def graph(self, config, world):
        """The Goals Relational Graph counted from options (None: none)."""
        return None

    def acting_category(self, policy) -> np.ndarray:
        """Houses: the category the actor-critic is pointed at (hierarchical: the sub-goal's)."""
        return policy.world.node_category(policy.subgoal)

    def actions(self, policy, obs, epsilon, rng) -> tuple[np.ndarray, tuple | None]:
        """Houses: primitive actions and the actor-critic's inputs (default: sampled from the actor-critic)."""
        return policy.actor_critic_actions(*obs, rng)

    def choose_subgoals(self, policy, obs, targets, cand, explore, noise, rows) -> np.ndarray:
        """Hierarchical methods: a node per row among ``cand`` (bool (n, nodes)); ``explore``
        rows choose from ``noise`` (uniform draws, one per row and node); ``rows`` index the
        policy's per-episode state."""
        raise NotImplementedError

    def ends_options(self, policy, obs, subgoal) -> np.ndarray | None:
        """Options this method ends besides the shared rules (reached, out of steps, episode
        over), judged on the observation the step led to: bool (N,), or None."""
        return None

    def q_loss(self, learner, batch: dict, policy, tables):
        """The Double DQN loss of ``policy.q`` on a replay batch (``tables``: the world's, for houses)."""
        raise NotImplementedError


def gumbel(noise: np.ndarray) -> np.ndarray:
    """Gumbel draws from uniform ``noise``: argmax(values + gumbel) samples softmax(values)."""
    return -np.log(-np.log(np.clip(noise, 1e-12, 1 - 1e-12)))
