"""Double DQN updates (van Hasselt et al. 2016), for the Q-networks of both worlds.

One ``Learner`` per level: online and target networks, RMSProp, loss 0.5 * mean squared
TD error (``td_loss``), gradients clipped by global norm, hard target copies; the grid-world
and house agents share them. The TD targets of the grid world's levels are small functions
here (``flat_loss``, ``hdqn_high_loss``, ``grg_high_loss``); the houses' are in ``house.world``.
"""

from __future__ import annotations

import copy

import numpy as np
import torch
from torch import nn

from objsearch_agents.gridworld_config import GridAgentConfig
from objsearch_agents.gridworld_inputs import candidate_inputs, candidates


def _f(x: np.ndarray) -> torch.Tensor:
    return torch.from_numpy(np.ascontiguousarray(x, dtype=np.float32))


class Learner:
    """Online/target pair of one level and its optimiser (``config``: any config with
    ``lr``, ``rmsprop_alpha``, ``rmsprop_eps``, ``max_grad_norm`` and ``gamma``; the grid-world
    and house agents share it)."""

    def __init__(self, net: nn.Module, config: GridAgentConfig):
        self.online = net
        self.target = copy.deepcopy(net).requires_grad_(False)
        self.optimizer = torch.optim.RMSprop(
            net.parameters(), lr=config.lr, alpha=config.rmsprop_alpha, eps=config.rmsprop_eps, foreach=True
        )  # foreach: the same numbers as the per-tensor loop, fewer calls
        self.max_grad_norm = config.max_grad_norm
        self.gamma = config.gamma

    def step(self, loss: torch.Tensor) -> float:
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        nn.utils.clip_grad_norm_(self.online.parameters(), self.max_grad_norm)
        self.optimizer.step()
        return float(loss.detach())

    def sync_target(self) -> None:
        self.target.load_state_dict(self.online.state_dict())

    def state_dict(self) -> dict:
        return {
            "online": self.online.state_dict(),
            "target": self.target.state_dict(),
            "optimizer": self.optimizer.state_dict(),
        }

    def load_state_dict(self, state: dict) -> None:
        self.online.load_state_dict(state["online"])
        self.target.load_state_dict(state["target"])
        self.optimizer.load_state_dict(state["optimizer"])


def td_loss(q_taken: torch.Tensor, reward, done, next_q: torch.Tensor, gamma: float) -> torch.Tensor:
    target = _f(reward) + gamma * (1.0 - _f(done)) * next_q
    return 0.5 * (target - q_taken).pow(2).mean()


def flat_loss(learner: Learner, batch: dict) -> torch.Tensor:
    """4-action Q-network on 2-channel inputs (DQN; the low level)."""
    q = learner.online(_f(batch["obs"])).gather(1, torch.from_numpy(batch["action"])[:, None])[:, 0]
    with torch.no_grad():
        nxt = _f(batch["next_obs"])
        a = learner.online(nxt).argmax(dim=1, keepdim=True)
        next_q = learner.target(nxt).gather(1, a)[:, 0]
    return td_loss(q, batch["reward"], batch["done"], next_q, learner.gamma)


def hdqn_high_loss(learner: Learner, batch: dict, num_goals: int) -> torch.Tensor:
    """h-DQN high level: 17-channel image + one-hot goal -> G+1 Q-values; the next value
    maximises over the candidates visible in the next observation."""
    onehot = _f(np.eye(num_goals)[batch["goal"]])
    q = learner.online(_f(batch["obs"]), onehot).gather(1, torch.from_numpy(batch["subgoal"])[:, None])[:, 0]
    with torch.no_grad():
        nxt = _f(batch["next_obs"])
        mask = torch.from_numpy(candidates(batch["next_obs"]))
        a = learner.online(nxt, onehot).masked_fill(~mask, -torch.inf).argmax(dim=1, keepdim=True)
        next_q = learner.target(nxt, onehot).gather(1, a)[:, 0]
    return td_loss(q, batch["reward"], batch["done"], next_q, learner.gamma)


def grg_high_loss(learner: Learner, batch: dict, weights_of_goal: np.ndarray) -> torch.Tensor:
    """HRL-GRG high level: one Q per (obstacles, candidate channel * weight). The weights
    are the relation weights toward each transition's goal, from the current GRG
    (``weights_of_goal``: (G, G+1), row = final goal)."""
    obs, nxt = batch["obs"], batch["next_obs"]
    weights = weights_of_goal[batch["goal"]]
    rows = np.arange(len(obs))
    q = learner.online(torch.from_numpy(candidate_inputs(obs, weights, rows, batch["subgoal"])))[:, 0]
    with torch.no_grad():
        cand = candidates(nxt)
        env_ix, node_ix = np.nonzero(cand)
        scores = np.full(cand.shape, -np.inf, dtype=np.float32)
        inputs = candidate_inputs(nxt, weights, env_ix, node_ix)
        scores[env_ix, node_ix] = learner.online(torch.from_numpy(inputs))[:, 0].numpy()
        best = scores.argmax(axis=1)
        next_q = learner.target(torch.from_numpy(candidate_inputs(nxt, weights, rows, best)))[:, 0]
    return td_loss(q, batch["reward"], batch["done"], next_q, learner.gamma)
