"""Training Scene Priors (``agents/baselines/scene_priors.py``), as the authors trained it: actor-critic,
reward +10 at the goal and -0.01 every other step, gamma 0.99, n-step returns over 30-step
rollouts cut at episode ends, entropy 0.01, gradients clipped to 40, RMSProp lr 1e-4 decayed
linearly to 5e-6, no curriculum, no pretraining. Their single worker becomes N episodes in
lockstep (as ``a3c``). The settings (``ScenePriorsConfig``), one run (``ScenePriorsRun``), its
``policy.pt`` (``save_policy``) and ``train``."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import torch

from objsearch import torchfile
from objsearch.configs import JsonConfig, require_at_least
from objsearch.errors import UserError
from objsearch.fileio import write_csv, write_json
from objsearch.house.categories import FIRST_OBJECT_ID
from objsearch.perception.model import pick_device
from objsearch.sim.camera import AGENT_CAMERA
from objsearch_agents.baselines.scene_priors_features import FeatureTables, feature_network
from objsearch_agents.baselines.scene_priors_graph import prior_graph
from objsearch_agents.baselines.scene_priors_net import ScenePriorsNet
from objsearch_agents.core.a2c import ActorCriticLearner
from objsearch_agents.core.nets import seeded_init
from objsearch_agents.core.training_loop import TrainingLoop, write_command
from objsearch_agents.house.checkpoint import CONFIG_FILE, LOG_FILE, POLICY_FILE, STATE_FILE
from objsearch_agents.house.policy import sample_actions
from objsearch_agents.house.tables import HISTORY

NAME = "scene_priors"
POLICY_KIND = "objsearch-scene-priors-policy"


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
    write_command(out, command)
    return run.start_or_resume(
        out / STATE_FILE,
        fresh,
        progress,
        "the state.pt of a scene_priors run",
        lambda: write_json(out / CONFIG_FILE, config.to_json()),
    )


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
