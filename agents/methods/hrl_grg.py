"""HRL-GRG (Ye et al., CVPR 2021): hierarchical reinforcement learning over a Goals
Relational Graph, and its three ablations as switches of the config. Both worlds run this
strategy: the grid world (goals in a 7x7 window, ``gridworld.world``) and the houses (object
categories in 10x10 maps, ``house.world``).

The parts, in the order an episode uses them:

1. **The graph** (``graph``). A ``GoalsRelationalGraph`` (``objsearch_agents.core.grg``) over
   the goal nodes and the back-up "random" node, counted from the options the low level
   runs: after an option toward sub-goal sg, every node first seen k steps into it counts
   "seen after k", every other node "not seen" (the policies count, ``advance``). Plans
   from every node to every goal, C(sg -> g), are refreshed as training goes and frozen
   per episode at its start.
2. **Choosing a sub-goal** (``choose_subgoals``). The candidates are the nodes in view plus
   "random". The high level scores each candidate on its own input, the candidate's channel
   (grid) or mask (houses) times its plan value C(sg -> g), beside the obstacles or depth
   (one Q per candidate); exploring, it samples softmax(C(sg -> g)) over the candidates.
3. **Ending an option** (``ends_options``): besides reaching the sub-goal, running out of
   steps or the episode's end, an option ends when a later node of the plan from its
   sub-goal to the goal comes into view.
4. **Learning** (``q_loss``): Double DQN on the candidate Q, the next state's best candidate
   chosen by the online network, its value read from the target network, both with the
   current graph's plan values to each transition's goal.

Ablations (the paper's Table 2), each one config switch:

* ``relation=False`` ("-relation"): the candidate's mask is not weighted by C(sg -> g);
* ``termination=False`` ("-termination"): no plan termination (part 3);
* ``high_level=False`` ("-high-level"): no network; the candidate with the best plan value.
"""

from __future__ import annotations

import numpy as np
import torch

from objsearch_agents.methods.base import Method, gumbel

ABLATIONS = ("relation", "termination", "high_level")


class HRLGRG(Method):
    name = "hrl_grg"
    hierarchical = True

    def agent_name(self, config) -> str:
        return self.name + "".join(f"_no_{switch}" for switch in ABLATIONS if not getattr(config, switch))

    def trains_actor_critic(self, config) -> bool:
        return config.train_low

    def q_network(self, config, world):
        return world.candidate_q_net(config.seed + 1) if config.high_level else None

    def graph(self, config, world):
        return world.graph(config)

    # -- 1. the relation: each candidate's weight --------------------------------------------
    @staticmethod
    def relation_weights(config, values: np.ndarray) -> np.ndarray:
        """The factor of each candidate's input: its plan value C(sg -> g) ("-relation": 1)."""
        return values if config.relation else np.ones_like(values)

    # -- 2. choosing a sub-goal --------------------------------------------------------------
    @torch.no_grad()
    def choose_subgoals(self, policy, obs, targets, cand, explore, noise, rows):
        values = policy.values[rows]
        if policy.q is not None:
            weights = self.relation_weights(policy.config, values)
            greedy = policy.world.candidate_argmax(policy.q, obs, cand, weights)
        else:  # "-high-level": the candidate with the best plan value
            greedy = np.where(cand, values, -1.0).argmax(axis=1)
        explored = np.where(cand, values + gumbel(noise), -np.inf).argmax(axis=1)  # softmax over plan values
        return np.where(explore, explored, greedy)

    # -- 3. plan termination -----------------------------------------------------------------
    def ends_options(self, policy, obs, subgoal):
        if not policy.config.termination:
            return None
        later = policy.successors[np.arange(len(subgoal)), subgoal]  # nodes after the sub-goal on its plan
        return (policy.world.visible_nodes(obs) & later).any(axis=1)

    # -- 4. the high level's loss --------------------------------------------------------------
    def q_loss(self, learner, batch, policy, tables):
        """The weights come from the current graph's plans to each transition's target."""
        values = policy.world.loss_plan_values(policy.plan_values, batch)
        weights = self.relation_weights(policy.config, values)
        return policy.world.candidate_q_loss(learner, batch, tables, weights)


METHOD = HRLGRG()
