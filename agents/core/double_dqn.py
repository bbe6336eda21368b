"""Double DQN (van Hasselt et al. 2016), written once for the Q-networks of both worlds.

One ``Learner`` per level: online and target networks, RMSProp, loss 0.5 * mean squared
TD error (``td_loss``), gradients clipped by global norm, hard target copies. The two
shapes of Double DQN loss the methods use are here, each world giving only its networks'
inputs (``gridworld.world``, ``house.world``):

* ``double_dqn_loss``: a network with one Q per output (DQN's actions, h-DQN's nodes); the
  next state's output chosen by the online network (among the allowed ones, h-DQN's
  candidates), its value read from the target network.
* ``candidate_double_dqn_loss``: a network that scores one candidate at a time (HRL-GRG's
  high level); the next state's best candidate by the online network, its value by the
  target network.
"""

from __future__ import annotations

import copy
from collections.abc import Callable

import numpy as np
import torch
from torch import nn

from objsearch_agents.core.nets import as_tensor


class Learner:
    """Online/target pair of one level and its optimiser (``config``: any config with
    ``lr``, ``rmsprop_alpha``, ``rmsprop_eps``, ``max_grad_norm`` and ``gamma``; the grid-world
    and house agents share it)."""

    def __init__(self, net: nn.Module, config):
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
    target = as_tensor(reward) + gamma * (1.0 - as_tensor(done)) * next_q
    return 0.5 * (target - q_taken).pow(2).mean()


def double_dqn_loss(learner: Learner, inputs: tuple, taken: np.ndarray, next_inputs: tuple, batch: dict, allowed=None):
    """Double DQN on a network with one Q per output: ``inputs`` and ``next_inputs`` are the
    network's arguments for the batch's states and next states, ``taken`` the outputs chosen;
    ``allowed`` (bool (B, outputs)), if given, restricts the next state's argmax."""
    q = learner.online(*inputs).gather(1, torch.from_numpy(taken)[:, None])[:, 0]
    with torch.no_grad():
        online = learner.online(*next_inputs)
        if allowed is not None:
            online = online.masked_fill(~torch.from_numpy(allowed), -torch.inf)
        next_q = learner.target(*next_inputs).gather(1, online.argmax(dim=1, keepdim=True))[:, 0]
    return td_loss(q, batch["reward"], batch["done"], next_q, learner.gamma)


def candidate_argmax(net, score: Callable, cand: np.ndarray) -> np.ndarray:
    """The best of each row's candidates (``cand``: bool (N, nodes)) by ``score(net, rows,
    nodes)`` (a (K,) tensor of the Q of those (row, node) pairs), one forward pass for all."""
    env_ix, node_ix = np.nonzero(cand)
    q = np.full(cand.shape, -np.inf, np.float32)
    q[env_ix, node_ix] = score(net, env_ix, node_ix).numpy()
    return q.argmax(axis=1)


def candidate_double_dqn_loss(
    learner: Learner, score: Callable, next_score: Callable, taken: np.ndarray, next_cand: np.ndarray, batch: dict
):
    """Double DQN on a network that scores one candidate at a time: ``score(net, rows,
    nodes)`` and ``next_score`` give the Q of (row, node) pairs in the batch's states and
    next states, ``taken`` the chosen nodes, ``next_cand`` (bool (B, nodes)) the next
    states' candidates."""
    rows = np.arange(len(taken))
    q = score(learner.online, rows, taken)
    with torch.no_grad():
        best = candidate_argmax(learner.online, next_score, next_cand)
        next_q = next_score(learner.target, rows, best)
    return td_loss(q, batch["reward"], batch["done"], next_q, learner.gamma)
