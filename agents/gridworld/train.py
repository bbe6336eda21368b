"""Training the grid-world agents on the batched grid world (``objsearch train``).

The paper's protocol (appendix A.2), run as ``num_envs`` parallel episodes with one
forward pass per level per step:

* Double DQN, RMSProp, batch 64, replay 10,000 per level, loss 0.5 * MSE, clip norm 40.
* Curriculum: episode i starts among the nearest max(1, N * min((i + 10) / 10000, 1)) start
  cells of the goal; maps uniform over the 100 training maps, goals over the 12 training
  goals. Episode numbers count episodes in the order they start.
* Exploration 1 -> 0.1 over 10,000 episodes (per episode, fixed at its start); the low
  level of the hierarchical agents explores with 0.1.
* The low level (and DQN) starts from a goal-reaching DQN pretrained on episodes that
  start where the goal is in view (``pretrain_episodes``, 10-step episodes).
* The high level stores one transition per primitive step with the extrinsic reward; the
  low level one per step of a real sub-goal with the intrinsic reward (1 and terminal on
  reaching it). Nothing is stored for the "random" sub-goal's steps at the low level.

Deviations forced by batching (documented in ``docs/gridworld_agents.md``, "Choices and deviations"):

* "An update every 10 steps" and "a target copy every 10,000 steps" count environment
  transitions summed over the parallel envs: a batched step of N envs earns N / 10 updates
  per level, so the number of updates per collected transition is the paper's.
* The GRG is re-planned once per batched step in which episodes start (the reference
  plans once per episode, with the graph of that moment: the same thing up to the few
  options that end within the step). The high level's relation weights at update time
  come from the current graph.

Files in the run directory (their format: ``gridworld.checkpoint``): ``config.json``,
``command.txt``, ``policy.pt`` (+ ``grg.npz``) the evaluable policy, ``state.pt`` everything
needed to resume (networks, optimisers, replay memories, env and option state, random
generator, counters, log rows), ``log.csv``. A run resumes from ``state.pt`` when restarted
with the same config (only ``episodes`` may change) and then gives the same result as an
uninterrupted run.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import torch

from objsearch import torchfile
from objsearch.fileio import write_csv
from objsearch.gridworld.batched import HALF, BatchedGridWorld, GridTables
from objsearch.gridworld.maps import GridMap
from objsearch.gridworld.tasks import SEEN_GOALS
from objsearch_agents.core.double_dqn import Learner
from objsearch_agents.core.replay import ReplayBuffer
from objsearch_agents.core.training_loop import TrainingLoop, owed_updates, write_command
from objsearch_agents.gridworld.checkpoint import CONFIG_FILE, LOG_FILE, STATE_FILE, load_policy_file, save_policy
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.gridworld.policy import GridPolicy, goal_input, goals_under_agent
from objsearch_agents.gridworld.world import flat_loss

LOG_FIELDS = (
    "episodes",
    "env_steps",
    "updates",
    "epsilon",
    "success_rate",
    "mean_steps",
    "loss_low",
    "loss_high",
    "grg_counts",
    "wall_s",
)


class StartSampler:
    """Start cells per (map, goal): sorted by distance to the goal (curriculum), or those
    with the goal in the 7x7 window (pretraining)."""

    def __init__(self, tables: GridTables, mode: str):
        self.mode = mode
        m, g, cells = tables.goal_dist.shape
        dist = tables.goal_dist.astype(np.int64)
        ok = dist > 0
        if mode == "visible":
            rows, cols = np.divmod(np.arange(cells), tables.width)
            grow, gcol = np.divmod(tables.goal_cells, tables.width)  # (M, G)
            near = (np.abs(rows[None, None] - grow[..., None]) <= HALF) & (
                np.abs(cols[None, None] - gcol[..., None]) <= HALF
            )
            ok &= near
        key = np.where(ok, dist, np.iinfo(np.int64).max)
        self.order = np.argsort(key, axis=2, kind="stable")  # nearest first, ties by cell index
        self.count = ok.sum(axis=2)

    def sample(self, maps: np.ndarray, goals: np.ndarray, episode_ix: np.ndarray, curriculum: int, rng) -> np.ndarray:
        n = self.count[maps, goals]
        if self.mode == "curriculum":
            frac = np.minimum((episode_ix + 10) / curriculum, 1.0)
            n = np.maximum(1, np.floor(n * frac).astype(np.int64))
        pick = (rng.random(len(maps)) * n).astype(np.int64)
        return self.order[maps, goals, pick]


class TrainRun(TrainingLoop):
    """One training run (one phase): its state, its loop, its files."""

    def __init__(self, config: GridAgentConfig, out: Path, maps: list[GridMap], goals=SEEN_GOALS):
        self.config, self.out = config, Path(out)
        c = config
        self.tables = GridTables.build(maps)
        self.goals = np.asarray(goals, dtype=np.int64)
        g = self.tables.num_goals
        self.rng = np.random.default_rng([c.seed, 7])
        self.policy = GridPolicy(c, num_goals=g)
        self.sampler = StartSampler(self.tables, c.starts)
        self.env = BatchedGridWorld(
            self.tables, c.num_envs, observation="all_goals", max_steps=c.max_steps, autoreset=False, rng=self.rng
        )
        self.low = Learner(self.policy.low, c)
        self.low_replay = ReplayBuffer(
            c.replay_size,
            {
                "obs": ((2, 7, 7), np.uint8),
                "action": ((), np.int64),
                "reward": ((), np.float32),
                "next_obs": ((2, 7, 7), np.uint8),
                "done": ((), np.float32),
            },
        )
        self.high = self.high_replay = None
        if self.policy.high is not None:
            self.high = Learner(self.policy.high, c)
            self.high_replay = ReplayBuffer(
                c.replay_size,
                {
                    "obs": ((1 + g, 7, 7), np.uint8),
                    "goal": ((), np.int64),
                    "subgoal": ((), np.int64),
                    "reward": ((), np.float32),
                    "next_obs": ((1 + g, 7, 7), np.uint8),
                    "done": ((), np.float32),
                },
            )
        self.episode_ix = np.zeros(c.num_envs, dtype=np.int64)
        self.counters = {"started": 0, "finished": 0, "env_steps": 0, "updates": 0, "credit": 0.0, "wall_s": 0.0}
        self.window = {"success": 0, "episodes": 0, "steps": 0, "loss_low": [0.0, 0], "loss_high": [0.0, 0]}
        self.rows: list[dict] = []
        self.obs = None

    # -- episodes (their exploration rate: TrainingLoop.epsilon) ---------------------------------
    def _start_episodes(self, env_ids: np.ndarray) -> None:
        k = len(env_ids)
        ix = self.counters["started"] + np.arange(k)
        self.counters["started"] += k
        maps = self.rng.integers(len(self.tables.names), size=k)
        goals = self.goals[self.rng.integers(len(self.goals), size=k)]
        starts = self.sampler.sample(maps, goals, ix, self.config.curriculum_episodes, self.rng)
        self.episode_ix[env_ids] = ix
        self.obs = self.env.reset(env_ids, maps, goals, starts)
        self.policy.refresh_plans()
        self.policy.begin_episodes(env_ids, goals)

    def begin(self) -> None:
        self.policy.start(self.config.num_envs)
        self._start_episodes(np.arange(self.config.num_envs))

    # -- one batched step ---------------------------------------------------------------------
    def step(self) -> None:
        c, p = self.config, self.policy
        images = self.obs["image"]
        eps = self.epsilon(self.episode_ix)
        if c.hierarchical:
            p.select_subgoals(images, eps, self.rng)
            subgoal = p.subgoal.copy()
            actions, low_in = p.actions(images, c.low_epsilon, self.rng)
        else:
            actions, low_in = p.actions(images, eps, self.rng)
        obs, reward, success, truncated, info = self.env.step(actions)
        nxt = obs["image"]
        over = success | truncated
        if c.hierarchical:
            real = np.flatnonzero(subgoal < p.random_node)
            reached = goals_under_agent(nxt)[real, subgoal[real]].astype(np.float32)
            self.low_replay.add(
                obs=low_in[real],
                action=actions[real],
                reward=reached,
                next_obs=goal_input(nxt[real], subgoal[real]),
                done=reached,
            )
            if self.high_replay is not None:
                self.high_replay.add(
                    obs=images,
                    goal=p.goal.copy(),
                    subgoal=subgoal,
                    reward=reward,
                    next_obs=nxt,
                    done=success.astype(np.float32),
                )
            p.advance(nxt, over, count=True)
        else:
            self.low_replay.add(
                obs=low_in,
                action=actions,
                reward=reward,
                next_obs=goal_input(nxt, p.goal),
                done=success.astype(np.float32),
            )
        self._learn(len(actions))
        self.obs = obs
        done = np.flatnonzero(over)
        if len(done):
            w = self.window
            w["success"] += int(success[done].sum())
            w["episodes"] += len(done)
            w["steps"] += int(info["steps"][done].sum())
            self.counters["finished"] += len(done)
            self._start_episodes(done)

    def _learn(self, transitions: int) -> None:
        c, k = self.config, self.counters
        before = k["env_steps"]
        k["env_steps"] += transitions
        updates, k["credit"] = owed_updates(k["credit"], transitions, c.update_every)
        for _ in range(updates):
            did = False
            if len(self.low_replay) >= max(c.learning_starts, c.batch_size):
                loss = self.low.step(flat_loss(self.low, self.low_replay.sample(c.batch_size, self.rng)))
                self.window["loss_low"][0] += loss
                self.window["loss_low"][1] += 1
                did = True
            if self.high_replay is not None and len(self.high_replay) >= max(c.learning_starts, c.batch_size):
                batch = self.high_replay.sample(c.batch_size, self.rng)
                loss = self.high.step(self.policy.method.q_loss(self.high, batch, self.policy, self.tables))
                self.window["loss_high"][0] += loss
                self.window["loss_high"][1] += 1
                did = True
            k["updates"] += int(did)
        if k["env_steps"] // c.target_update > before // c.target_update:
            self.low.sync_target()
            if self.high is not None:
                self.high.sync_target()

    # -- log and files --------------------------------------------------------------------------
    def log_row(self) -> None:
        w, k = self.window, self.counters
        mean = lambda pair: round(pair[0] / pair[1], 6) if pair[1] else ""
        self.rows.append(
            {
                "episodes": k["finished"],
                "env_steps": k["env_steps"],
                "updates": k["updates"],
                "epsilon": round(float(self.epsilon(np.array([k["started"]]))[0]), 4),
                "success_rate": round(w["success"] / max(w["episodes"], 1), 4),
                "mean_steps": round(w["steps"] / max(w["episodes"], 1), 2),
                "loss_low": mean(w["loss_low"]),
                "loss_high": mean(w["loss_high"]),
                "grg_counts": int(self.policy.grg.counts.sum()) if self.policy.grg is not None else "",
                "wall_s": round(k["wall_s"], 1),
            }
        )
        self.window = {"success": 0, "episodes": 0, "steps": 0, "loss_low": [0.0, 0], "loss_high": [0.0, 0]}

    def state_dict(self) -> dict:
        env = self.env
        return {
            "config": self.config.to_json(),
            "counters": dict(self.counters),
            "window": {k: (list(v) if isinstance(v, list) else v) for k, v in self.window.items()},
            "rows": list(self.rows),
            "rng": self.rng.bit_generator.state,
            "env": {k: getattr(env, k).copy() for k in ("map_idx", "goal", "cell", "steps", "min_steps")},
            "episode_ix": self.episode_ix.copy(),
            "obs": {k: v.copy() for k, v in self.obs.items()},
            "policy": self.policy.state_dict(),
            "grg": self.policy.grg.state_dict() if self.policy.grg is not None else None,
            "low": self.low.state_dict(),
            "low_replay": self.low_replay.state_dict(),
            "high": self.high.state_dict() if self.high is not None else None,
            "high_replay": self.high_replay.state_dict() if self.high_replay is not None else None,
        }

    def load_state_dict(self, s: dict) -> None:
        self.counters, self.window, self.rows = dict(s["counters"]), s["window"], list(s["rows"])
        self.rng.bit_generator.state = s["rng"]
        for k, v in s["env"].items():
            setattr(self.env, k, np.array(v))
        self.episode_ix, self.obs = np.array(s["episode_ix"]), s["obs"]
        self.low.load_state_dict(s["low"])
        self.low_replay.load_state_dict(s["low_replay"])
        if self.high is not None:
            self.high.load_state_dict(s["high"])
            self.high_replay.load_state_dict(s["high_replay"])
        if self.policy.grg is not None:
            self.policy.grg.counts[...] = s["grg"]["counts"]
        self.policy.refresh_plans()
        self.policy.load_state_dict(s["policy"])

    def write_log(self) -> None:
        """Rewrite ``log.csv`` with every row so far (after each row, not only at checkpoints)."""
        write_csv(self.out / LOG_FILE, LOG_FIELDS, self.rows)

    def save(self) -> None:
        self.out.mkdir(parents=True, exist_ok=True)
        save_policy(self.policy, self.out)
        self.write_log()
        torchfile.save(self.out / STATE_FILE, self.state_dict())

    # -- the loop (training_loop.TrainingLoop.run) ----------------------------------------------
    unit = "ep"
    budget = "episodes"

    def done(self) -> int:
        return self.counters["finished"]

    def goal(self) -> int:
        return self.config.episodes

    def describe(self) -> str:
        return f"train {self.config.method}"

    def postfix(self) -> dict:
        r = self.rows[-1]
        return {"sr": r["success_rate"], "eps": r["epsilon"], "loss": r["loss_low"]}

    def wall_seconds(self) -> float:
        return self.counters["wall_s"]

    def set_wall_seconds(self, seconds: float) -> None:
        self.counters["wall_s"] = seconds


def _run_phase(
    config: GridAgentConfig, out: Path, maps, progress: bool, fresh: bool, init_low: dict | None
) -> TrainRun:
    run = TrainRun(config, out, maps)

    def start() -> None:
        if init_low is not None:
            run.policy.low.load_state_dict(init_low)
            run.low.sync_target()
        out.mkdir(parents=True, exist_ok=True)
        config.save(out / CONFIG_FILE)

    return run.start_or_resume(out / STATE_FILE, fresh, progress, "the state.pt of a grid-world training run", start)


def train(
    config: GridAgentConfig,
    out: str | Path,
    maps: list[GridMap] | None = None,
    progress: bool = True,
    fresh: bool = False,
    command: str | None = None,
) -> TrainRun:
    """Train ``config`` into ``out`` (resuming what is there), pretraining the low level
    first into ``out/pretrain`` unless ``config.pretrained`` names one."""
    torch.set_num_threads(1)  # tiny networks: threads cost more than they give
    out = Path(out)
    if maps is None:
        from objsearch.gridworld.dataset import train_maps

        maps = list(train_maps().values())
    out.mkdir(parents=True, exist_ok=True)
    write_command(out, command)
    init_low = None
    if config.pretrained:
        init_low = load_policy_file(Path(config.pretrained))["low"]
    elif config.pretrain_episodes > 0:
        pre_config = replace(
            config,
            method="dqn",
            starts="visible",
            max_steps=config.option_steps,
            episodes=config.pretrain_episodes,
            eps_anneal_episodes=max(1, config.pretrain_episodes // 2),
            pretrain_episodes=0,
            pretrained="",
            checkpoint_every=min(config.checkpoint_every, config.pretrain_episodes),
        )
        pre = _run_phase(pre_config, out / "pretrain", maps, progress, fresh, None)
        if pre.interrupted:
            return pre
        init_low = pre.policy.low.state_dict()
    return _run_phase(config, out, maps, progress, fresh, init_low)
