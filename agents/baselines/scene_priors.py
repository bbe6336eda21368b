"""Scene Priors (Yang et al. 2018), as the HRL-GRG authors reimplemented it, in our houses.

The one baseline of the paper's AI2-THOR table that also uses relations: an actor-critic
whose input includes a graph convolution over a FIXED prior graph of category relations.
The method is this file and four beside it, read in this order: the graph
(``scene_priors_graph``), the visual input (``scene_priors_features``), the network
(``scene_priors_net``), training and the checkpoint (``scene_priors_train``), then the agent
(here, which also gives every name of the four). It reuses the houses' shared machinery
(``house.episodes`` for training houses, tasks and lockstep episodes, ``a2c`` for the
learner, ``house.agent.HouseAgent`` for checkpoint lookup and the protocol) and adds
nothing to it. What the authors' code loads that cannot be had here is substituted, each
substitute written down in ``docs/scene_priors.md``:

1. **The relation graph** (``relation_graph``): SAVN's Visual Genome adjacency becomes
   co-occurrence in an annotated scene corpus, the specs of ``house-gen-v2``'s 40 training
   houses (never an evaluation house). Category j is related to i when j is in more than
   ``RELATION_THRESHOLD`` of the rooms that hold i (i to itself: a second instance); binary,
   asymmetric, normalised as the authors' ``get_adjmat``: D^-1/2 A^T D^-1/2, D the row sums,
   no added self-loops.
2. **The visual input** (``FeatureTables``): ImageNet ResNet-50 features become the frozen
   encoder of the shipped perception network (stem to ASPP, average-pooled to 2x2: 384
   values a frame), ImageNet's 1000 class scores its mean per-pixel softmax over the 69
   category ids. Both come from RGB only, so gt and predicted observations give the agent
   the same input. Computed once per pose per house, beside the observation cache.
3. **GloVe** becomes a learned 100-d embedding per object category, shared by the target
   and the graph's nodes as GloVe is.

The network (``ScenePriorsNet``): the last 4 frames' features -> FC512 ReLU; the target's
embedding -> FC512 ReLU; the current frame's scores -> FC512 (linear), shared by every node;
each node's input is [that, its own embedding -> FC512 (linear)]; three GCN layers A_hat H W
without bias (1024 ReLU, 1024 ReLU, 1 ReLU); the node outputs -> FC512 (linear); vision,
target and graph concatenated -> FC512 ReLU -> 6 action logits and a value.

Training (``ScenePriorsRun``), as the authors': actor-critic, reward +10 at the goal and
-0.01 every other step, gamma 0.99, n-step returns over 30-step rollouts cut at episode
ends, entropy 0.01, gradients clipped to 40, RMSProp lr 1e-4 decayed linearly to 5e-6, no
curriculum, no pretraining. Their single worker becomes N episodes in lockstep (as ``a3c``).
"""

from __future__ import annotations

import hashlib
import os
import sys
from collections import OrderedDict
from dataclasses import dataclass, replace

import numpy as np
import torch

from objsearch import digests, torchfile
from objsearch.errors import UserError
from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch.sim.camera import AGENT_CAMERA, AGENT_CAMERA_NAME, check_camera
from objsearch_agents.baselines.scene_priors_features import (
    FEATURE_GRID,
    TABLE_VERSION,
    FeatureTables,
    feature_network,
    frame_features,
)
from objsearch_agents.baselines.scene_priors_graph import (
    GRAPH_SUITE,
    RELATION_THRESHOLD,
    graph_refs,
    normalized_adjacency,
    object_node,
    prior_graph,
    relation_graph,
    room_counts,
)
from objsearch_agents.baselines.scene_priors_net import EMBED, GCN_HIDDEN, HIDDEN, ScenePriorsNet
from objsearch_agents.baselines.scene_priors_train import (
    LOG_FIELDS,
    NAME,
    POLICY_KIND,
    ScenePriorsConfig,
    ScenePriorsRun,
    save_policy,
    suite_max_steps,
    train,
)
from objsearch_agents.core.rows import RowRandom
from objsearch_agents.house.agent import HouseAgent
from objsearch_agents.house.checkpoint import POLICY_FILE
from objsearch_agents.house.policy import sample_actions
from objsearch_agents.house.tables import HISTORY

# the method's names, from its modules and this one (tests, docs and checkpoints' code name them here)
__all__ = [
    "EMBED",
    "FEATURE_GRID",
    "FRAME_MEMO",
    "GCN_HIDDEN",
    "GRAPH_SUITE",
    "HIDDEN",
    "LOG_FIELDS",
    "NAME",
    "POLICY_KIND",
    "RELATION_THRESHOLD",
    "TABLE_VERSION",
    "FeatureTables",
    "ScenePriorsAgent",
    "ScenePriorsConfig",
    "ScenePriorsNet",
    "ScenePriorsPolicy",
    "ScenePriorsRun",
    "feature_network",
    "frame_features",
    "graph_refs",
    "normalized_adjacency",
    "object_node",
    "prior_graph",
    "relation_graph",
    "room_counts",
    "save_policy",
    "suite_max_steps",
    "train",
]
FRAME_MEMO = 50_000  # frames whose features an agent remembers (about 200 MB): revisited poses cost nothing


@dataclass(frozen=True, eq=False)
class ScenePriorsPolicy:
    """What a ``policy.pt`` holds: the config, the network, and the key of the perception
    network whose features and scores it learned from."""

    config: ScenePriorsConfig
    net: ScenePriorsNet
    features_key: str


class ScenePriorsAgent(HouseAgent):
    """Scene Priors: an actor-critic with a GCN over a fixed prior graph of category relations."""

    config = ScenePriorsConfig()

    def load(self, path: str | os.PathLike) -> None:
        """Load ``policy.pt`` (or a run folder holding it) and the perception network its features came from."""
        path = torchfile.policy_path(path, POLICY_FILE)
        state = torchfile.load(path, "a policy.pt written by objsearch train --agent scene_priors")
        if not isinstance(state, dict) or state.get("kind") != POLICY_KIND:
            raise UserError(
                f"checkpoint {path} is not a scene_priors policy.pt; pass one written by objsearch train --agent scene_priors"
            )
        with torchfile.fitting(path, "a scene_priors policy.pt"):
            saved = ScenePriorsConfig.from_json(state["config"], f"checkpoint {path}")
            self._check_trained_for(saved, path)
            check_camera(
                state.get("camera"),
                AGENT_CAMERA,
                source=f"scene_priors checkpoint {path}",
                expected_name=AGENT_CAMERA_NAME,
                fix=f"retrain it (objsearch train --agent {NAME} --suite {saved.suite})",
            )
            weights = state["net"]
            net = ScenePriorsNet(
                weights["adjacency"].numpy(),
                weights["vision.weight"].shape[1] // HISTORY,
                weights["scores.weight"].shape[1],
            )
            net.load_state_dict(weights)
        self.predictor = feature_network()
        if self.predictor.key != state["features"]:
            raise UserError(
                f"checkpoint {path} learned from the features of perception network {state['features']}, but the "
                f"shipped network is {self.predictor.key}; retrain it (objsearch train --agent {NAME} --suite {saved.suite})"
            )
        self.policy = ScenePriorsPolicy(saved, net.eval(), state["features"])
        self._memo: OrderedDict[bytes, tuple[np.ndarray, np.ndarray]] = OrderedDict()  # see features()
        self.loaded_from = str(path)
        self.weights_sha256 = digests.of_files([path])
        self.trained_perception_key = None  # RGB only: the same input under gt and predicted observations

    def start_batch(self, num_slots: int) -> None:
        self._slots = int(num_slots)
        idle = np.random.default_rng(0)  # draws of an idle slot are thrown away
        self._rngs = [idle] * self._slots
        self._history: list[list | None] = [None] * self._slots
        self._graph: list = [None] * self._slots
        self._target = np.zeros(self._slots, np.int64)

    def reset_batch(self, tasks: dict) -> None:
        for i, task in tasks.items():
            self._rngs[i], self._history[i] = task.rng, None
            self._target[i] = int(task.goal) - FIRST_OBJECT_ID

    @torch.no_grad()
    def features(self, rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A frame's ``frame_features`` and the graph embedding of its class scores, computed
        one frame at a time (a slot's numbers do not depend on the batch it shares) and
        remembered by the frame's digest for the last ``FRAME_MEMO`` frames: episodes revisit
        poses, and a cached suite's frame of a pose is the same bytes each time."""
        memo = self._memo
        key = hashlib.blake2b(np.ascontiguousarray(rgb).tobytes(), digest_size=16).digest()
        if key in memo:
            memo.move_to_end(key)
            return memo[key]
        features, scores = frame_features(self.predictor.model, rgb[None])
        memo[key] = features[0], self.policy.net.graph_embedding(torch.from_numpy(scores))[0].numpy()
        if len(memo) > FRAME_MEMO:
            memo.popitem(last=False)
        return memo[key]

    @torch.no_grad()
    def act_batch(self, observations: dict) -> dict:
        busy = sorted(observations)
        for i in busy:
            obs = observations[i]
            if not isinstance(obs, dict) or "rgb" not in obs:
                raise TypeError("scene_priors needs the house env's observation (rgb, ..., target)")
            features, self._graph[i] = self.features(np.asarray(obs["rgb"]))
            self._history[i] = [features] * HISTORY if self._history[i] is None else self._history[i][1:] + [features]
        rows = [i if i in observations else busy[0] for i in range(self._slots)]
        logits, _ = self.policy.net.head(
            torch.from_numpy(np.stack([np.stack(self._history[i]) for i in rows])),
            torch.from_numpy(self._target[rows]),
            torch.from_numpy(np.stack([self._graph[i] for i in rows])),
        )
        actions = sample_actions(logits, RowRandom(self._rngs))
        return {i: int(actions[i]) for i in busy}

    @classmethod
    def train(
        cls,
        *,
        suite: str,
        out,
        episodes: int | None = None,
        steps: int | None = None,
        seed: int = 0,
        overrides: dict | None = None,
        fresh: bool = False,
        progress: bool = True,
        command: str | None = None,
    ) -> dict:
        """Train on a house suite's training houses (the ``objsearch train`` hook)."""
        if episodes is not None:
            raise UserError("scene_priors trains for a number of environment steps: pass --steps, not --episodes")
        config = replace(cls.config, seed=int(seed), suite=suite).with_overrides(dict(overrides or {}))
        if steps is not None:
            config = replace(config, steps=int(steps))
        run = train(config, out, progress=progress, fresh=fresh, command=command)
        k = run.counters
        print(f"{NAME}: {k['env_steps'] / max(k['wall_s'], 1e-9):.0f} env steps/s", file=sys.stderr)
        return {
            "out": str(out),
            "finished": k["finished"],
            "env_steps": k["env_steps"],
            "interrupted": run.interrupted,
            "wall_s": k["wall_s"],
        }
