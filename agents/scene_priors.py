"""Scene Priors (Yang et al. 2018), as the HRL-GRG authors reimplemented it, in our houses.

The one baseline of the paper's AI2-THOR table that also uses relations: an actor-critic
whose input includes a graph convolution over a FIXED prior graph of category relations.
The whole method is this file, top to bottom; it reuses the houses' shared machinery
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
from functools import lru_cache
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from objsearch import digests, torchfile
from objsearch.configs import JsonConfig, require_at_least
from objsearch.errors import UserError
from objsearch.fileio import atomic_write, write_csv, write_json
from objsearch.house.categories import CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.perception.model import pick_device
from objsearch.sim.camera import AGENT_CAMERA, AGENT_CAMERA_NAME, check_camera
from objsearch_agents.a2c import ActorCriticLearner
from objsearch_agents.house.agent import HouseAgent
from objsearch_agents.house.checkpoint import CONFIG_FILE, LOG_FILE, POLICY_FILE, STATE_FILE
from objsearch_agents.house.nets import NUM_ACTIONS, glorot
from objsearch_agents.house.policy import sample_actions
from objsearch_agents.house.tables import HISTORY, NUM_OBJECTS
from objsearch_agents.nets import seeded_init
from objsearch_agents.rows import RowRandom
from objsearch_agents.training_loop import TrainingLoop

NAME = "scene_priors"
POLICY_KIND = "objsearch-scene-priors-policy"

# -- 1. the relation graph ------------------------------------------------------------------
GRAPH_SUITE = "house-gen-v2"
"""The suite whose TRAINING houses are the scene corpus (house-gen-2 houses)."""
RELATION_THRESHOLD = 0.5
"""A[i, j] = 1 when category j is in more than this fraction of the rooms that hold i."""


def object_node(category: str) -> int:
    """The graph node of an object category (its id less ``FIRST_OBJECT_ID``)."""
    return CATEGORY_IDS[category] - FIRST_OBJECT_ID


def room_counts(specs) -> np.ndarray:
    """int (R, NUM_OBJECTS): the objects of each category in every furnished room of ``specs``."""
    rows = []
    for spec in specs:
        counts = {room.id: np.zeros(NUM_OBJECTS, np.int64) for room in spec.rooms}
        for obj in spec.objects:
            counts[obj.room][object_node(obj.category)] += 1
        rows += [c for _, c in sorted(counts.items()) if c.any()]
    return np.stack(rows) if rows else np.zeros((0, NUM_OBJECTS), np.int64)


def relation_graph(specs, threshold: float = RELATION_THRESHOLD) -> np.ndarray:
    """uint8 (NUM_OBJECTS, NUM_OBJECTS) binary adjacency from the rooms of ``specs`` alone:
    A[i, j] = 1 when P(j in the room | i in the room) > ``threshold`` (j = i: a second
    instance of i). Asymmetric; a category in no room has no edges."""
    counts = room_counts(specs)
    has = (counts > 0).astype(np.int64)
    both = has.T @ has
    np.fill_diagonal(both, (counts >= 2).sum(axis=0))
    holding = has.sum(axis=0)
    p = both / np.maximum(holding, 1)[:, None]
    return (p > threshold).astype(np.uint8)


def normalized_adjacency(adjacency: np.ndarray) -> np.ndarray:
    """D^-1/2 A^T D^-1/2 with D the row sums of A, no self-loops added, 0 for a node with no
    out-edges (the authors' ``get_adjmat``, SAVN's ``normalize_adj``)."""
    a = np.asarray(adjacency, np.float64)
    rowsum = a.sum(axis=1)
    inv_sqrt = np.divide(1.0, np.sqrt(rowsum), out=np.zeros_like(rowsum), where=rowsum > 0)
    return (inv_sqrt[:, None] * a.T * inv_sqrt[None, :]).astype(np.float32)


def graph_refs(suite: str = GRAPH_SUITE):
    """The houses of the scene corpus: ``suite``'s training houses (spec-hash checked)."""
    from objsearch.sim.suites import load_suite_file, training_houses

    return training_houses(load_suite_file(suite))


@lru_cache(maxsize=2)
def prior_graph(suite: str = GRAPH_SUITE) -> np.ndarray:
    """The relation graph of ``suite``'s training houses (a few seconds: 40 specs generated)."""
    from objsearch.sim.world import World

    return relation_graph([World.load(ref).spec for ref in graph_refs(suite)])


# -- 2. the visual input: the perception network's features and class scores ----------------
FEATURE_GRID = 2  # the encoder's 8x8 output average-pooled to 2x2
FRAME_MEMO = 50_000  # frames whose features an agent remembers (about 200 MB): revisited poses cost nothing
TABLE_VERSION = "scene-priors-features-v1"


def feature_network(checkpoint: str | None = None):
    """The frozen perception network (``objsearch.perception``; default: the shipped one), on the CPU."""
    from objsearch.perception.inference import Predictor
    from objsearch.sim.camera import check_predictor_camera

    predictor = Predictor.from_checkpoint(checkpoint, device="cpu")
    check_predictor_camera(predictor, AGENT_CAMERA)
    return predictor


@torch.no_grad()
def frame_features(model, rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """uint8 (N, H, W, 3) -> (features float32 (N, F), class scores float32 (N, C)).

    Features: the encoder's output (stem ... layer4, ASPP; what DeepLabv3+ calls the
    encoder) average-pooled to ``FEATURE_GRID`` x ``FEATURE_GRID``. Scores: the per-pixel
    softmax over the category ids, averaged over the frame (the share of the frame the
    network gives each category)."""
    from objsearch.perception.model import rgb_to_tensor

    x = rgb_to_tensor(rgb)
    low = model.layer1(model.stem(x - model.mean))
    deep = model.aspp(model.layer4(model.layer3(model.layer2(low))))
    features = F.adaptive_avg_pool2d(deep, FEATURE_GRID).flatten(1)
    up = F.interpolate(deep, size=low.shape[-2:], mode="bilinear", align_corners=False)
    decoded = model.decoder(torch.cat([up, model.skip(low)], dim=1))
    logits = model.seg_head(decoded)  # (N, C * r * r, h, w): pixel shuffle's layout, class-major
    n, classes = len(x), model.config.num_classes
    scores = torch.softmax(logits.reshape(n, classes, -1), dim=1).mean(dim=2)
    return features.numpy().astype(np.float32), scores.numpy().astype(np.float32)


@dataclass(frozen=True, eq=False)
class FeatureTables:
    """``features`` (P, F) and ``scores`` (P, C) of every pose of one or more houses."""

    features: np.ndarray
    scores: np.ndarray

    @classmethod
    def of_cache(cls, cache, predictor, progress: bool = False) -> "FeatureTables":
        """The tables of one house's ``HouseCache`` (its RGB), stored in its folder as
        ``scene-priors-<network key>.npz``: the folder is keyed by the house and camera, the
        file by the network, and it holds ``TABLE_VERSION`` and the pose count, so a table
        never outlives what made it."""
        from tqdm import tqdm

        path = Path(cache.directory) / f"scene-priors-{predictor.key}.npz"
        n = len(cache.semantic)
        try:
            with np.load(path, allow_pickle=False) as data:
                if str(data["version"]) == TABLE_VERSION and len(data["features"]) == n:
                    return cls(data["features"], data["scores"])
        except (OSError, ValueError, KeyError):
            pass
        torch.set_num_threads(1)
        feats, scores = [], []
        for start in tqdm(range(0, n, 64), desc=f"scene features {Path(cache.directory).name}", disable=not progress):
            f, s = frame_features(predictor.model, np.asarray(cache.rgb[start : start + 64]))
            feats.append(f)
            scores.append(s)
        tables = cls(np.concatenate(feats), np.concatenate(scores))
        with atomic_write(path, "wb") as f:
            np.savez(f, version=np.array(TABLE_VERSION), features=tables.features, scores=tables.scores)
        return tables

    @classmethod
    def of_houses(cls, houses, predictor, cache_dir=None, progress: bool = False) -> "FeatureTables":
        """The tables of a ``TrainingHouses``, in its global pose ids."""
        from objsearch.sim.cache import HouseCache

        parts = [
            cls.of_cache(HouseCache.open(w, AGENT_CAMERA, cache_dir, progress), predictor, progress)
            for w in houses.worlds
        ]
        tables = cls(np.concatenate([t.features for t in parts]), np.concatenate([t.scores for t in parts]))
        if len(tables.features) != houses.tables.num_poses:
            raise RuntimeError("scene-priors tables do not cover the training houses' poses")
        return tables


# -- 3. the network ---------------------------------------------------------------------------
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


# -- 4. training --------------------------------------------------------------------------------
@dataclass(frozen=True)
class ScenePriorsConfig(JsonConfig):
    """The method's settings, written as ``config.json`` and into ``policy.pt``."""

    DESCRIPTION = "a scene_priors config"
    LEGACY_KEYS = {}

    suite: str = "house-gen-v2"
    """The suite whose training houses and seen targets the agent trains on."""
    seed: int = 0
    """Seeds the network, task sampling and action sampling."""
    steps: int = 2_000_000
    """Environment steps (summed over the parallel episodes)."""
    num_envs: int = 16
    """Episodes in lockstep (the authors' single worker; one forward pass for all)."""
    max_steps: int = 0
    """Steps per training episode; 0: the suite's own limit (``suite_max_steps``: 1000 in the
    Table 3 suites, ``rooms``' cap 200; its single rooms end at their type's limit, ``room_max_steps``)."""
    min_start_steps: int = 6
    """Episodes start this many to ``max_start_steps`` minimal steps from the target's goal poses
    (the suites' window; on ``rooms`` the authors' AI2-THOR code started from 1: ``--set min_start_steps=1``)."""
    max_start_steps: int = 40
    """The farthest start."""
    goal_reward: float = 10.0
    """Reward on reaching a goal pose."""
    step_reward: float = -0.01
    """Reward of every other step."""
    gamma: float = 0.99
    """Discount."""
    rollout: int = 30
    """Steps per update (the authors': every 30 steps and at the episode's end)."""
    lr: float = 1e-4
    """RMSProp learning rate at the start."""
    lr_end: float = 5e-6
    """Learning rate after ``lr_decay_steps`` (linear decay; the authors': over 100k episodes)."""
    lr_decay_steps: int = 10_000_000
    """Environment steps over which the learning rate falls from ``lr`` to ``lr_end``."""
    rmsprop_alpha: float = 0.99
    """RMSProp decay of the squared-gradient average (PyTorch's default, as the other house
    agents'; the grid world's 0.9 is TensorFlow 1's)."""
    rmsprop_eps: float = 1e-5
    """RMSProp epsilon."""
    max_grad_norm: float = 40.0
    """Gradients are clipped to this global norm."""
    entropy: float = 0.01
    """Entropy bonus of the actor-critic loss."""
    pool: str = "search"
    """Start pool (``house.episodes``): ``search`` (the suite's windows) or ``approach`` (a tiny task, for tests)."""
    curriculum_episodes: int = 1
    """Episode i starts among the nearest max(1, N * min((i + 10) / this, 1)) starts (1: none, the authors')."""
    checkpoint_every: int = 50_000
    """Write a resumable checkpoint every this many environment steps."""
    log_every: int = 20_000
    """Append a row to ``log.csv`` every this many environment steps."""
    device: str = "auto"
    """Where the network trains: ``auto`` (the GPU when there is one), ``cpu`` or ``cuda``. The
    GCN is most of the cost: an H200 trains about 100 times faster than one CPU thread
    (docs/scene_priors.md), but not bit for bit as the CPU does."""

    def __post_init__(self):
        if self.pool not in ("search", "approach"):
            raise UserError(f"pool must be search or approach, not {self.pool!r}")
        if self.min_start_steps > self.max_start_steps:
            raise UserError(
                f"min_start_steps={self.min_start_steps} is above max_start_steps={self.max_start_steps}: no episode "
                "could start; lower the first or raise the second"
            )
        require_at_least(
            self,
            (
                "steps",
                "num_envs",
                "min_start_steps",
                "max_start_steps",
                "rollout",
                "lr_decay_steps",
                "curriculum_episodes",
                "checkpoint_every",
                "log_every",
            ),
            1,
        )
        require_at_least(self, ("max_steps",), 0)

    @property
    def name(self) -> str:
        return NAME

    def learning_rate(self, env_steps: int) -> float:
        return max(self.lr_end, self.lr - (self.lr - self.lr_end) * env_steps / self.lr_decay_steps)


def suite_max_steps(suite: str) -> int:
    """A house suite's episode step limit (its file's ``max_steps``; the largest where it
    sets one per room type)."""
    from objsearch.sim.suites import load_suite_file

    limit = load_suite_file(suite).get("max_steps")
    if isinstance(limit, dict):
        limit = max(limit.values(), default=None)
    if not isinstance(limit, int) or limit < 1:
        raise UserError(f"suite {suite} records no step limit scene_priors can train with; pass --set max_steps=N")
    return limit


LOG_FIELDS = ("env_steps", "episodes", "updates", "lr", "success_rate", "mean_steps", "loss", "wall_s")


class ScenePriorsRun(TrainingLoop):
    """One training run: N lockstep episodes on the tables, A2C updates, its files."""

    def __init__(
        self,
        config: ScenePriorsConfig,
        out,
        houses,
        features: FeatureTables,
        perception_key: str,
        adjacency: np.ndarray,
    ):
        c = self.config = config
        self.out, self.houses, self.tables = Path(out), houses, features
        self.perception_key = perception_key
        self.device = pick_device(c.device)
        self.net = seeded_init(ScenePriorsNet, c.seed, adjacency, features.features.shape[1], features.scores.shape[1])
        self.net.to(self.device)
        self.features = torch.from_numpy(features.features).to(self.device)
        self.scores = torch.from_numpy(features.scores).to(self.device)
        self.learner = ActorCriticLearner(
            self.net, c.lr, c.rmsprop_alpha, c.rmsprop_eps, c.max_grad_norm, c.entropy, c.gamma
        )
        from objsearch_agents.house.episodes import EpisodeBatch

        self.batch = EpisodeBatch(houses, c.num_envs, c.max_steps)
        self.rng = np.random.default_rng([c.seed, 29])
        self.rollout: list = []
        self.counters = {"started": 0, "finished": 0, "env_steps": 0, "updates": 0, "wall_s": 0.0}
        self.window = {"success": 0, "episodes": 0, "steps": 0, "loss": 0.0, "losses": 0}
        self.rows: list[dict] = []
        self.interrupted = False

    def inputs(self, hist: np.ndarray, target: np.ndarray) -> tuple[torch.Tensor, ...]:
        """The network's input for histories ``hist`` (N, 4) and target categories ``target``, on its device."""
        hist = torch.from_numpy(np.asarray(hist)).to(self.device)
        return (
            self.features[hist],
            torch.from_numpy(np.asarray(target) - FIRST_OBJECT_ID).to(self.device),
            self.scores[hist[:, -1]],
        )

    def _start(self, env_ids: np.ndarray) -> None:
        ix = self.counters["started"] + np.arange(len(env_ids))
        self.counters["started"] += len(env_ids)
        pairs, starts = self.houses.sample(self.config.pool, ix, self.config.curriculum_episodes, self.rng)
        self.batch.start(env_ids, pairs, starts)

    def begin(self) -> None:
        self._start(np.arange(self.config.num_envs))

    def step(self) -> None:
        c, b = self.config, self.batch
        hist, target = b.hist.copy(), b.target.copy()
        with torch.no_grad():
            logits, _ = self.net(*self.inputs(hist, target))
        actions = sample_actions(logits.cpu(), self.rng)
        success, truncated = b.step(actions)
        over = success | truncated
        reward = np.where(success, c.goal_reward, c.step_reward).astype(np.float32)
        self.rollout.append((hist, target, actions, reward, over.astype(np.float32)))
        self.counters["env_steps"] += len(actions)
        done = np.flatnonzero(over)
        if len(done):
            w = self.window
            w["success"] += int(success[done].sum())
            w["episodes"] += len(done)
            w["steps"] += int(b.steps[done].sum())
            self.counters["finished"] += len(done)
            self._start(done)
        if len(self.rollout) == c.rollout:
            self.learn()

    def learn(self) -> None:
        """One A2C update on the rollout: n-step returns cut at episode ends, bootstrapped with V(s_T)."""
        hist, target, actions, rewards, dones = (np.stack(x) for x in zip(*self.rollout))
        self.rollout = []
        with torch.no_grad():
            _, bootstrap = self.net(*self.inputs(self.batch.hist, self.batch.target))
        returns = self.learner.returns(rewards, dones, bootstrap.cpu().numpy())
        for group in self.learner.optimizer.param_groups:
            group["lr"] = self.config.learning_rate(self.counters["env_steps"])
        loss = self.learner.update(
            self.inputs(hist.reshape(-1, HISTORY), target.reshape(-1)), actions.reshape(-1), returns.reshape(-1)
        )
        self.window["loss"] += loss
        self.window["losses"] += 1
        self.counters["updates"] += 1

    # -- files ------------------------------------------------------------------------------------
    def log_row(self) -> None:
        w, k = self.window, self.counters
        self.rows.append(
            {
                "env_steps": k["env_steps"],
                "episodes": k["finished"],
                "updates": k["updates"],
                "lr": f"{self.config.learning_rate(k['env_steps']):.3g}",
                "success_rate": round(w["success"] / max(w["episodes"], 1), 4),
                "mean_steps": round(w["steps"] / max(w["episodes"], 1), 2),
                "loss": round(w["loss"] / w["losses"], 6) if w["losses"] else "",
                "wall_s": round(k["wall_s"], 1),
            }
        )
        self.window = {"success": 0, "episodes": 0, "steps": 0, "loss": 0.0, "losses": 0}

    def state_dict(self) -> dict:
        return {
            "kind": "objsearch-scene-priors-train-state",
            "config": self.config.to_json(),
            "counters": dict(self.counters),
            "window": dict(self.window),
            "rows": list(self.rows),
            "rng": self.rng.bit_generator.state,
            "batch": self.batch.state_dict(),
            "rollout": [list(r) for r in self.rollout],
            "learner": self.learner.state_dict(),
        }

    def load_state_dict(self, s: dict) -> None:
        self.counters, self.window, self.rows = dict(s["counters"]), dict(s["window"]), list(s["rows"])
        self.rng.bit_generator.state = s["rng"]
        self.batch.load_state_dict(s["batch"])
        self.rollout = [tuple(np.asarray(x) for x in r) for r in s["rollout"]]
        self.learner.load_state_dict(s["learner"])

    def save(self) -> None:
        self.out.mkdir(parents=True, exist_ok=True)
        save_policy(self.net, self.config, self.perception_key, self.out)
        self.write_log()
        torchfile.save(self.out / STATE_FILE, self.state_dict())

    # -- the loop (training_loop.TrainingLoop.run) ----------------------------------------------
    def done(self) -> int:
        return self.counters["env_steps"]

    def goal(self) -> int:
        return self.config.steps

    def describe(self) -> str:
        return f"train {NAME}"

    def write_log(self) -> None:
        write_csv(self.out / LOG_FILE, LOG_FIELDS, self.rows)

    def postfix(self) -> dict:
        return {"sr": self.rows[-1]["success_rate"], "ep": self.counters["finished"]}

    def wall_seconds(self) -> float:
        return self.counters["wall_s"]

    def set_wall_seconds(self, seconds: float) -> None:
        self.counters["wall_s"] = seconds


def train(
    config: ScenePriorsConfig,
    out,
    houses=None,
    cache_dir=None,
    progress: bool = True,
    fresh: bool = False,
    command: str | None = None,
    predictor=None,
) -> ScenePriorsRun:
    """Train ``config`` into ``out``, resuming what is there (only ``steps`` may change)."""
    from objsearch_agents.house.train import suite_training_houses

    torch.set_num_threads(1)
    out = Path(out)
    if config.max_steps == 0:
        config = replace(config, max_steps=suite_max_steps(config.suite))
    if houses is None:
        houses = suite_training_houses(
            config.suite, "gt", cache_dir, progress, config.max_start_steps, config.min_start_steps
        )
    predictor = predictor or feature_network()
    features = FeatureTables.of_houses(houses, predictor, cache_dir, progress)
    run = ScenePriorsRun(config, out, houses, features, predictor.key, prior_graph())
    out.mkdir(parents=True, exist_ok=True)
    if command:
        with atomic_write(out / "command.txt") as f:
            f.write(command + "\n")
    if (out / STATE_FILE).exists() and not fresh:
        torchfile.resume(out / STATE_FILE, config, run.load_state_dict, "steps", "the state.pt of a scene_priors run")
    else:
        write_json(out / CONFIG_FILE, config.to_json())
        run.begin()
    run.interrupted = not run.run(progress=progress)
    return run


# -- 5. the checkpoint and the agent --------------------------------------------------------------
def save_policy(net: ScenePriorsNet, config: ScenePriorsConfig, perception_key: str, out: Path) -> None:
    """``policy.pt``: config, camera, the key of the perception network the features came from, weights."""
    torchfile.save(
        Path(out) / POLICY_FILE,
        {
            "kind": POLICY_KIND,
            "config": config.to_json(),
            "camera": AGENT_CAMERA.to_json(),
            "features": perception_key,
            "net": net.state_dict(),
        },
    )


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
