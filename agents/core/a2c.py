"""Advantage actor-critic updates (the synchronous, batched form of A3C; Mnih et al. 2016).

The paper's A3C runs one worker thread (the authors' train.sh scripts all set
num_threads=1) and updates every 10 steps. Here N episodes run in lockstep and one update
uses all N x 10 transitions of a rollout: the same n-step returns and loss, one forward
pass for all envs, which is what makes it fast on a CPU.

Loss = 0.5 * MSE(value, return) - mean(log pi(a) * advantage) - beta * entropy, the
advantage held constant; gradients clipped by global norm; RMSProp.
"""

from __future__ import annotations

import numpy as np
import torch
from torch import nn


class ActorCriticLearner:
    """An actor-critic network (``forward(*inputs) -> (logits, value)``) and its optimiser."""

    def __init__(
        self, net: nn.Module, lr: float, alpha: float, eps: float, max_grad_norm: float, entropy: float, gamma: float
    ):
        self.net = net
        self.optimizer = torch.optim.RMSprop(
            net.parameters(), lr=lr, alpha=alpha, eps=eps, foreach=True
        )  # foreach: the same numbers as the per-tensor loop, fewer calls (as core.double_dqn.Learner)
        self.max_grad_norm, self.entropy, self.gamma = max_grad_norm, entropy, gamma

    def returns(self, rewards: np.ndarray, dones: np.ndarray, bootstrap: np.ndarray) -> np.ndarray:
        """n-step returns (T, N): R_t = r_t + gamma (1 - done_t) R_{t+1}, R_T = ``bootstrap``."""
        out = np.zeros(rewards.shape, np.float32)
        running = bootstrap.astype(np.float32)
        for t in range(len(rewards) - 1, -1, -1):
            running = rewards[t] + self.gamma * (1.0 - dones[t]) * running
            out[t] = running
        return out

    def update(self, inputs: tuple[torch.Tensor, ...], actions: np.ndarray, returns: np.ndarray) -> float:
        """One step on a batch: ``inputs`` flattened over (T, N), ``actions`` and ``returns`` (T*N,)."""
        logits, value = self.net(*inputs)
        ret = torch.from_numpy(returns.astype(np.float32)).to(value.device)
        logp = torch.log_softmax(logits, dim=1)
        taken = logp.gather(1, torch.from_numpy(actions.astype(np.int64)).to(logp.device)[:, None])[:, 0]
        advantage = (ret - value).detach()
        entropy = -(logp.exp() * logp).sum(dim=1).mean()
        loss = 0.5 * (ret - value).pow(2).mean() - (taken * advantage).mean() - self.entropy * entropy
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        nn.utils.clip_grad_norm_(self.net.parameters(), self.max_grad_norm)
        self.optimizer.step()
        return float(loss.detach())

    def state_dict(self) -> dict:
        return {"net": self.net.state_dict(), "optimizer": self.optimizer.state_dict()}

    def load_state_dict(self, state: dict) -> None:
        self.net.load_state_dict(state["net"])
        self.optimizer.load_state_dict(state["optimizer"])
