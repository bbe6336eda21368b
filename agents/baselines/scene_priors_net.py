"""Scene Priors' network (``agents/baselines/scene_priors.py``): the last 4 frames' features -> FC512 ReLU;
the target's embedding -> FC512 ReLU; the current frame's scores -> FC512 (linear), shared by
every node; each node's input is [that, its own embedding -> FC512 (linear)]; three GCN layers
A_hat H W without bias (1024 ReLU, 1024 ReLU, 1 ReLU); the node outputs -> FC512 (linear);
vision, target and graph concatenated -> FC512 ReLU -> 6 action logits and a value. GloVe
(substitute 3 of ``docs/scene_priors.md``) becomes a learned 100-d embedding per object
category, shared by the target and the graph's nodes as GloVe is."""

from __future__ import annotations

import numpy as np
import torch
from torch import nn

from objsearch_agents.baselines.scene_priors_graph import normalized_adjacency
from objsearch_agents.house.nets import NUM_ACTIONS, glorot
from objsearch_agents.house.tables import HISTORY

EMBED = 100  # GloVe's 100 dimensions (the authors' glove_map100d)
HIDDEN = 512
GCN_HIDDEN = 1024


class ScenePriorsNet(nn.Module):
    """(features (N, 4, F), target node (N,), scores (N, C)) -> (logits (N, 6), value (N,)).

    ``adjacency``: the binary relation graph (nodes x nodes); stored in the weights, so a
    checkpoint carries the graph it learned with."""

    def __init__(self, adjacency: np.ndarray, feature_dim: int, num_scores: int):
        super().__init__()
        nodes = len(adjacency)
        self.register_buffer("adjacency", torch.as_tensor(np.asarray(adjacency), dtype=torch.float32))
        a_hat = torch.from_numpy(normalized_adjacency(np.asarray(adjacency)))
        # Nodes whose row and column of A_hat are zero (no edges at all) output exactly 0 and
        # touch no other node: the layers run over the others only (the same values).
        active = torch.nonzero((a_hat != 0).any(dim=0) | (a_hat != 0).any(dim=1))[:, 0]
        self.register_buffer("a_hat", a_hat[active][:, active], persistent=False)
        self.register_buffer("active", active, persistent=False)
        self.embedding = nn.Parameter(torch.randn(nodes, EMBED))  # GloVe's place: learned
        self.vision = nn.Linear(HISTORY * feature_dim, HIDDEN)
        self.target = nn.Linear(EMBED, HIDDEN)
        self.scores = nn.Linear(num_scores, HIDDEN)
        self.node = nn.Linear(EMBED, HIDDEN)
        self.gcn = nn.ModuleList(
            [
                nn.Linear(2 * HIDDEN, GCN_HIDDEN, bias=False),
                nn.Linear(GCN_HIDDEN, GCN_HIDDEN, bias=False),
                nn.Linear(GCN_HIDDEN, 1, bias=False),
            ]
        )
        self.graph = nn.Linear(nodes, HIDDEN)
        self.joint = nn.Linear(3 * HIDDEN, HIDDEN)
        self.policy = nn.Linear(HIDDEN, NUM_ACTIONS)
        self.value = nn.Linear(HIDDEN, 1)
        glorot(self)

    def graph_embedding(self, scores: torch.Tensor) -> torch.Tensor:
        """The GCN over the prior graph: (N, C) scores -> (N, 512)."""
        a = self.a_hat
        shared = self.scores(scores)  # (N, 512): every node's first half
        own = self.node(self.embedding[self.active])  # (n, 512): each node's second half
        w0 = self.gcn[0].weight
        # Layer 1, A [1 shared, own] W0 = (A 1)(shared W0a) + (A own) W0b: exact, without
        # building the (N, n, 1024) input.
        h = a.sum(dim=1)[None, :, None] * (shared @ w0[:, :HIDDEN].T)[:, None, :] + (a @ own @ w0[:, HIDDEN:].T)[None]
        h = torch.relu(h)
        h = torch.relu(self.gcn[1](a @ h))
        h = torch.relu(self.gcn[2](a @ h))[..., 0]  # (N, n)
        return h @ self.graph.weight[:, self.active].T + self.graph.bias

    def forward(
        self, features: torch.Tensor, target: torch.Tensor, scores: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        return self.head(features, target, self.graph_embedding(scores))

    def head(
        self, features: torch.Tensor, target: torch.Tensor, graph: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """``forward`` given the graph embedding (N, 512) of the last frame's scores: what the
        agent remembers per frame, since the GCN is almost all of the network's work."""
        v = torch.relu(self.vision(features.flatten(1)))
        t = torch.relu(self.target(self.embedding[target]))
        j = torch.relu(self.joint(torch.cat([v, t, graph], dim=1)))
        return self.policy(j), self.value(j)[:, 0]
