"""The House3D networks of HRL-GRG (paper appendix B.2, as the authors' code builds them).

Inputs are 4 frames of 10x10 maps, flattened to 400 values per stream:

* ``ActorCritic`` (A3C, and the low level of h-DQN and HRL-GRG): the target's (or
  sub-goal's) mask and the depth, FC 256 each (ReLU), concatenated, FC 256 ("embed", in
  the authors' code though not in the paper's text), then a policy branch FC 20 -> 6
  (softmax) and a value branch FC 20 -> 1.
* ``CandidateQ`` (HRL-GRG's high level): the candidate's mask times its plan value, and
  the depth; FC 256 each, concatenated, FC 256, a linear output of 1 (one Q per candidate).
* ``CategoryQ`` (DQN, and h-DQN's high level): every category's mask through a per-pixel
  linear map C -> 1 (no activation; a 1x1 convolution), FC 256; the depth, FC 256; both
  concatenated with the target's one-hot, FC 256, a linear output (6 actions for DQN, one Q
  per sub-goal node for h-DQN).

Glorot-uniform weights and zero biases, as TensorFlow 1's layers (the authors' code).
"""

from __future__ import annotations

import torch
from torch import nn
from torch.nn.functional import linear

from objsearch_agents.house.tables import HISTORY, SIZE

PIXELS = HISTORY * SIZE * SIZE  # 400
HIDDEN = 256
BRANCH = 20
NUM_ACTIONS = 6


def glorot(module: nn.Module) -> nn.Module:
    """Glorot-uniform weights and zero biases for every ``nn.Linear`` of ``module``."""
    for m in module.modules():
        if isinstance(m, nn.Linear):
            nn.init.xavier_uniform_(m.weight)
            if m.bias is not None:
                nn.init.zeros_(m.bias)
    return module


class TwoStream(nn.Module):
    """mask (N, 400), depth (N, 400) [, extra (N, E)] -> FC 256 (ReLU) of their concatenation."""

    def __init__(self, extra: int = 0):
        super().__init__()
        self.mask = nn.Linear(PIXELS, HIDDEN)
        self.depth = nn.Linear(PIXELS, HIDDEN)
        self.embed = nn.Linear(2 * HIDDEN + extra, HIDDEN)

    def forward(self, mask: torch.Tensor, depth: torch.Tensor, extra: torch.Tensor | None = None) -> torch.Tensor:
        # the layers' own computation (``nn.Linear.forward`` is ``linear``), without a module call
        # each: the networks are small, and every acting step and update runs them (no hooks are used)
        m, d, e = self.mask, self.depth, self.embed
        parts = [
            torch.relu(linear(mask.flatten(1), m.weight, m.bias)),
            torch.relu(linear(depth.flatten(1), d.weight, d.bias)),
        ]
        if extra is not None:
            parts.append(extra)
        return torch.relu(linear(torch.cat(parts, dim=1), e.weight, e.bias))


def head(branch: nn.Sequential, h: torch.Tensor) -> torch.Tensor:
    """``branch(h)`` of a Linear, ReLU, Linear branch, without the module calls."""
    first, _, last = branch
    return linear(torch.relu(linear(h, first.weight, first.bias)), last.weight, last.bias)


class ActorCritic(nn.Module):
    """(mask, depth) -> (action logits (N, 6), value (N,))."""

    def __init__(self):
        super().__init__()
        self.body = TwoStream()
        self.policy = nn.Sequential(nn.Linear(HIDDEN, BRANCH), nn.ReLU(), nn.Linear(BRANCH, NUM_ACTIONS))
        self.value = nn.Sequential(nn.Linear(HIDDEN, BRANCH), nn.ReLU(), nn.Linear(BRANCH, 1))
        glorot(self)

    def forward(self, mask: torch.Tensor, depth: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        h = self.body.forward(mask, depth)
        return head(self.policy, h), head(self.value, h)[:, 0]


class CandidateQ(nn.Module):
    """(weighted candidate mask, depth) -> Q (N,)."""

    def __init__(self):
        super().__init__()
        self.body = TwoStream()
        self.out = nn.Linear(HIDDEN, 1)
        glorot(self)

    def forward(self, mask: torch.Tensor, depth: torch.Tensor) -> torch.Tensor:
        return linear(self.body.forward(mask, depth), self.out.weight, self.out.bias)[:, 0]


class CategoryQ(nn.Module):
    """(categories in view (N, 4, M), their masks (N, 4, M, 10, 10), depth (N, 4, 10, 10),
    target one-hot (N, C)) -> Q (N, outputs). The per-pixel linear map over all C masks is
    computed over the M categories in view only (the others' masks are zero): the same
    value, a fraction of the work."""

    def __init__(self, num_categories: int, outputs: int):
        super().__init__()
        self.pixel = nn.Linear(num_categories, 1)  # the per-pixel C -> 1 map
        self.body = TwoStream(extra=num_categories)
        self.out = nn.Linear(HIDDEN, outputs)
        glorot(self)

    def forward(
        self, categories: torch.Tensor, masks: torch.Tensor, depth: torch.Tensor, target: torch.Tensor
    ) -> torch.Tensor:
        w = self.pixel.weight[0][categories]  # (N, 4, M)
        seg = (masks * w[..., None, None]).sum(dim=2) + self.pixel.bias  # (N, 4, 10, 10)
        return linear(self.body.forward(seg, depth, target), self.out.weight, self.out.bias)
