"""Training the house agents on their suite's training houses (``objsearch train``).

N episodes run in lockstep on observation tables (``episodes.EpisodeBatch``); one forward
pass per level per step. The paper's protocol (appendix B.3), as the authors' code runs it,
with the deviations written in ``docs/house_agents.md``:

* The actor-critic (A3C, and the low level of the hierarchical methods) is first
  pretrained to approach a visible object: 50-step episodes from poses that see the
  category, reward 1 at its goal poses, every object category of the training houses.
* ``a3c`` then trains on the seen targets from the pretrained weights: synchronous A2C,
  n-step rollouts of 10 steps over all envs, entropy 0.01, reward 1 at a goal pose.
* ``dqn``, and the high levels of ``hdqn`` and ``hrl_grg``: Double DQN, replay of pose
  ids (the observation is rebuilt from the tables), batch 64, RMSProp, loss 0.5 * MSE, one
  transition per primitive step with the extrinsic reward; exploration 1 -> 0.1 over the
  first episodes (fixed per episode at its start).
* Hierarchical low levels start from the pretrained approach policy and stay frozen, or
  with ``train_low`` keep training as the authors' code does: the same A2C on the
  intrinsic reward (1 when the option's sub-goal is reached; the target's goal poses when
  the sub-goal is the target), returns cut at option ends and bootstrapped with V(s') when
  an option ends unreached; the back-up node's transitions are not used. With
  ``explorer``, the back-up node's options run another frozen actor-critic (the suite's A3C).
* Curriculum on the start pools (``episodes``); an episode is at most 1000 steps.

Files in the run directory (their format: ``house.checkpoint``): ``config.json``, ``command.txt``, ``policy.pt`` (+ ``grg.npz``)
the evaluable policy, ``state.pt`` everything to resume exactly, ``log.csv``. Rerunning
the same command resumes (only ``steps`` may change).
"""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np
import torch
from tqdm import tqdm

from objsearch import torchfile
from objsearch.fileio import atomic_write, write_csv, write_json
from objsearch.interrupt import stop_on_interrupt
from objsearch.sim.env import START_STEPS
from objsearch_agents.a2c import ActorCriticLearner
from objsearch_agents.dqn_learner import Learner, td_loss
from objsearch_agents.house.checkpoint import CONFIG_FILE, LOG_FILE, STATE_FILE, load_checkpoint_file, save_policy
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.episodes import EpisodeBatch, TrainingHouses, object_node
from objsearch_agents.house.policy import (
    RANDOM,
    HousePolicy,
    _t,
    candidate_inputs,
    candidates,
    category_input,
    low_input,
    node_category,
)
from objsearch_agents.house.tables import HISTORY
from objsearch_agents.replay import ReplayBuffer

LOG_FIELDS = (
    "env_steps",
    "episodes",
    "updates",
    "epsilon",
    "success_rate",
    "mean_steps",
    "loss_ac",
    "loss_q",
    "grg_counts",
    "wall_s",
)


# -- Q-learning targets ---------------------------------------------------------------------
def dqn_loss(learner: Learner, batch: dict, tables) -> torch.Tensor:
    """DQN over 6 actions: Double DQN on ``CategoryQ``."""
    return _category_loss(learner, batch, tables, None)


def hdqn_loss(learner: Learner, batch: dict, tables) -> torch.Tensor:
    """h-DQN's high level: the next value maximises over the next state's candidates."""
    return _category_loss(learner, batch, tables, candidates)


def _category_loss(learner, batch, tables, mask_fn) -> torch.Tensor:
    q = learner.online(*category_input(tables, batch["hist"], batch["target"]))
    q = q.gather(1, torch.from_numpy(batch["action"])[:, None])[:, 0]
    with torch.no_grad():
        nxt = category_input(tables, batch["next_hist"], batch["target"])
        online = learner.online(*nxt)
        if mask_fn is not None:
            online = online.masked_fill(
                ~torch.from_numpy(mask_fn(tables, batch["next_hist"], batch["target"])), -torch.inf
            )
        next_q = learner.target(*nxt).gather(1, online.argmax(dim=1, keepdim=True))[:, 0]
    return td_loss(q, batch["reward"], batch["done"], next_q, learner.gamma)


def grg_loss(learner: Learner, batch: dict, tables, policy: HousePolicy) -> torch.Tensor:
    """HRL-GRG's high level: one Q per (candidate mask x C(sg -> g), depth); the weights come
    from the current GRG's plans to each transition's target."""
    rows = np.arange(len(batch["action"]))
    values = policy.plan_values[object_node(batch["target"])]
    weights = policy.relation_weights(values)
    q = learner.online(*candidate_inputs(tables, batch["hist"], rows, batch["action"], weights))
    with torch.no_grad():
        best = policy.candidate_argmax(
            learner.online, tables, batch["next_hist"], candidates(tables, batch["next_hist"], batch["target"]), values
        )
        next_q = learner.target(*candidate_inputs(tables, batch["next_hist"], rows, best, weights))
    return td_loss(q, batch["reward"], batch["done"], next_q, learner.gamma)


class HouseTrainRun:
    """One training phase: its state, its loop, its files."""

    def __init__(self, config: HouseAgentConfig, out: Path, houses: TrainingHouses, pool: str = "search"):
        c = self.config = config
        self.out, self.houses, self.pool = Path(out), houses, pool
        self.tables = houses.tables
        self.rng = np.random.default_rng([c.seed, 11])
        self.policy = HousePolicy(c)
        self.batch = EpisodeBatch(houses, c.num_envs, c.max_steps)
        self.ac = None  # the actor-critic's learner: A3C, or a hierarchical low level with train_low
        if c.method == "a3c" or (c.hierarchical and c.train_low):
            self.ac = ActorCriticLearner(
                self.policy.ac, c.ac_lr, c.rmsprop_alpha, c.rmsprop_eps, c.max_grad_norm, c.entropy, c.gamma
            )
        self.q = self.replay = None
        if self.policy.q is not None:
            self.q = Learner(self.policy.q, c)
            self.replay = ReplayBuffer(
                c.replay_size,
                {
                    "hist": ((HISTORY,), np.int64),
                    "target": ((), np.int64),
                    "action": ((), np.int64),
                    "reward": ((), np.float32),
                    "next_hist": ((HISTORY,), np.int64),
                    "done": ((), np.float32),
                },
            )
        self.rollout: list = []
        self.episode_ix = np.zeros(c.num_envs, np.int64)
        self.counters = {
            "started": 0,
            "finished": 0,
            "env_steps": 0,
            "updates": 0,
            "credit": 0.0,
            "wall_s": 0.0,
            "batched_steps": 0,
        }
        self.window = self._empty_window()
        self.rows: list[dict] = []
        self.interrupted = False

    @staticmethod
    def _empty_window() -> dict:
        return {"success": 0, "episodes": 0, "steps": 0, "loss_ac": [0.0, 0], "loss_q": [0.0, 0]}

    def epsilon(self, episode_ix: np.ndarray) -> np.ndarray:
        c = self.config
        return np.maximum(c.eps_end, c.eps_start - (c.eps_start - c.eps_end) * episode_ix / c.eps_anneal_episodes)

    def _start_episodes(self, env_ids: np.ndarray) -> None:
        k = len(env_ids)
        ix = self.counters["started"] + np.arange(k)
        self.counters["started"] += k
        pairs, starts = self.houses.sample(self.pool, ix, self.config.curriculum_episodes, self.rng)
        self.episode_ix[env_ids] = ix
        self.batch.start(env_ids, pairs, starts)
        self.policy.begin_episodes(env_ids, self.batch.target[env_ids])

    def begin(self) -> None:
        self.policy.start(self.config.num_envs)
        self._start_episodes(np.arange(self.config.num_envs))

    # -- one batched step ----------------------------------------------------------------------
    def step(self) -> None:
        c, p, b, tables = self.config, self.policy, self.batch, self.tables
        hist = b.hist.copy()
        eps = self.epsilon(self.episode_ix)
        if c.hierarchical:
            p.select_subgoals(tables, hist, eps, self.rng)
        chosen = p.subgoal.copy() if c.hierarchical else None
        actions, inputs = p.actions(tables, hist, eps, self.rng)
        success, truncated = b.step(actions)
        over = success | truncated
        reward = success.astype(np.float32)
        if self.replay is not None:
            self.replay.add(
                hist=hist,
                target=b.target.copy(),
                action=chosen if c.hierarchical else actions,
                reward=reward,
                next_hist=b.hist.copy(),
                done=reward,
            )
        if c.hierarchical:
            ended = p.advance(tables, b.hist, over, count=True)
            if self.ac is not None:
                self._record_low(inputs, actions, chosen, success, ended)
        elif self.ac is not None:
            self.rollout.append((inputs, actions, reward, over.astype(np.float32), np.ones(len(actions), bool)))
        done = np.flatnonzero(over)
        if len(done):
            w = self.window
            w["success"] += int(success[done].sum())
            w["episodes"] += len(done)
            w["steps"] += int(b.steps[done].sum())
            self.counters["finished"] += len(done)
            self._start_episodes(done)
        if self.ac is not None and len(self.rollout) == c.rollout:
            self._learn_ac()
        self._learn_q(len(actions))
        k = self.counters
        k["batched_steps"] += 1
        if p.grg is not None and k["batched_steps"] % c.plan_every == 0:
            p.refresh_plans()

    @torch.no_grad()
    def _record_low(self, inputs, actions, chosen, success, ended) -> None:
        """A low-level step of every env toward the sub-goal it had (``chosen``): reward 1
        when reached (the target: at a goal pose), the option's end cuts the return, and an
        option that ended unreached is bootstrapped with V(s', sub-goal)."""
        p = self.policy
        reward = (p.reached | (success & (chosen == object_node(p.target)))).astype(np.float32)
        cut = np.flatnonzero(ended & (reward == 0) & (chosen < RANDOM))
        if len(cut):
            _, value = p.ac(*map(_t, low_input(self.tables, self.batch.hist[cut], node_category(chosen[cut]))))
            reward[cut] += np.float32(self.config.gamma) * value.numpy()
        self.rollout.append((inputs, actions, reward, ended.astype(np.float32), chosen < RANDOM))

    def _learn_ac(self) -> None:
        """One A2C update on the rollout's transitions (``valid`` ones: the back-up node's are not used)."""
        masks, depths, actions, rewards, dones, valid = zip(
            *[(i[0], i[1], a, r, d, v) for i, a, r, d, v in self.rollout]
        )
        self.rollout = []
        with torch.no_grad():
            _, bootstrap = self.policy.ac(
                *map(_t, low_input(self.tables, self.batch.hist, self.policy.acting_category()))
            )
        returns = self.ac.returns(np.stack(rewards), np.stack(dones), bootstrap.numpy())
        keep = np.concatenate(valid)
        if not keep.any():
            return
        flat = lambda x: np.concatenate(x)[keep]
        loss = self.ac.update((_t(flat(masks)), _t(flat(depths))), flat(actions), returns.reshape(-1)[keep])
        self.window["loss_ac"][0] += loss
        self.window["loss_ac"][1] += 1

    def _learn_q(self, transitions: int) -> None:
        c, k = self.config, self.counters
        before = k["env_steps"]
        k["env_steps"] += transitions
        if self.q is None:
            return
        k["credit"] += transitions / c.update_every
        updates = int(k["credit"])
        k["credit"] -= updates
        if len(self.replay) < max(c.learning_starts, c.batch_size):
            return
        for _ in range(updates):
            batch = self.replay.sample(c.batch_size, self.rng)
            if c.method == "dqn":
                loss = dqn_loss(self.q, batch, self.tables)
            elif c.method == "hdqn":
                loss = hdqn_loss(self.q, batch, self.tables)
            else:
                loss = grg_loss(self.q, batch, self.tables, self.policy)
            self.window["loss_q"][0] += self.q.step(loss)
            self.window["loss_q"][1] += 1
            k["updates"] += 1
        if k["env_steps"] // c.target_update > before // c.target_update:
            self.q.sync_target()

    # -- log and files -------------------------------------------------------------------------
    def log_row(self) -> None:
        w, k = self.window, self.counters
        mean = lambda pair: round(pair[0] / pair[1], 6) if pair[1] else ""
        self.rows.append(
            {
                "env_steps": k["env_steps"],
                "episodes": k["finished"],
                "updates": k["updates"],
                "epsilon": round(float(self.epsilon(np.array([k["started"]]))[0]), 4) if self.q is not None else "",
                "success_rate": round(w["success"] / max(w["episodes"], 1), 4),
                "mean_steps": round(w["steps"] / max(w["episodes"], 1), 2),
                "loss_ac": mean(w["loss_ac"]),
                "loss_q": mean(w["loss_q"]),
                "grg_counts": int(self.policy.grg.counts.sum()) if self.policy.grg is not None else "",
                "wall_s": round(k["wall_s"], 1),
            }
        )
        self.window = self._empty_window()

    def state_dict(self) -> dict:
        arrays = {
            "rng": self.rng.bit_generator.state,
            "batch": self.batch.state_dict(),
            "episode_ix": self.episode_ix.copy(),
            "policy": self.policy.state_dict(),
            "grg": self.policy.grg.counts.copy() if self.policy.grg is not None else None,
            "replay": self.replay.state_dict() if self.replay is not None else None,
            "rollout": [list(i) + [a, r, d, v] for i, a, r, d, v in self.rollout],
        }
        return {
            "kind": "objsearch-house-train-state",
            "config": self.config.to_json(),
            "counters": dict(self.counters),
            "window": {k: (list(v) if isinstance(v, list) else v) for k, v in self.window.items()},
            "rows": list(self.rows),
            "arrays": arrays,
            "ac": self.ac.state_dict() if self.ac is not None else None,
            "q": self.q.state_dict() if self.q is not None else None,
            "low": self.policy.ac.state_dict() if self.policy.ac is not None else None,
            "explore": self.policy.explore.state_dict() if self.policy.explore is not None else None,
        }

    def load_state_dict(self, s: dict) -> None:
        self.counters, self.window, self.rows = dict(s["counters"]), s["window"], list(s["rows"])
        a = s["arrays"]
        self.rng.bit_generator.state = a["rng"]
        self.batch.load_state_dict(a["batch"])
        self.episode_ix = np.array(a["episode_ix"])
        if self.policy.ac is not None:
            self.policy.ac.load_state_dict(s["low"])
        if self.policy.explore is not None:
            self.policy.explore.load_state_dict(s["explore"])
        if self.ac is not None:
            self.ac.load_state_dict(s["ac"])
        if self.q is not None:
            self.q.load_state_dict(s["q"])
            self.replay.load_state_dict(a["replay"])
        if self.policy.grg is not None:
            self.policy.grg.counts[...] = a["grg"]
        self.policy.load_state_dict(a["policy"])
        self.rollout = [((r[0], r[1]), r[2], r[3], r[4], r[5]) for r in a["rollout"]]

    def save(self) -> None:
        self.out.mkdir(parents=True, exist_ok=True)
        save_policy(self.policy, self.out, self.houses.perception_key)
        write_csv(self.out / LOG_FILE, LOG_FIELDS, self.rows)
        torchfile.save(self.out / STATE_FILE, self.state_dict())

    # -- the loop ----------------------------------------------------------------------------------
    def run(self, progress: bool = True) -> bool:
        """Train until ``config.steps`` env steps, checkpointing as it goes. Returns False if
        interrupted (Ctrl-C or SIGTERM: the current step finishes, then a checkpoint is written)."""
        c, k = self.config, self.counters
        with stop_on_interrupt() as stop:
            desc = f"train {c.name}" + (" (pretrain)" if self.pool == "approach" else "")
            bar = tqdm(
                total=c.steps,
                initial=min(k["env_steps"], c.steps),
                unit="step",
                unit_scale=True,
                desc=desc,
                disable=not progress or None,
                smoothing=0.05,
            )
            try:
                t0, wall0 = time.perf_counter(), k["wall_s"]
                while k["env_steps"] < c.steps and not stop.is_set():
                    before = k["env_steps"]
                    self.step()
                    k["wall_s"] = wall0 + time.perf_counter() - t0
                    bar.update(min(k["env_steps"], c.steps) - min(before, c.steps))
                    if k["env_steps"] // c.log_every > before // c.log_every:
                        self.log_row()
                        write_csv(self.out / LOG_FILE, LOG_FIELDS, self.rows)
                        bar.set_postfix(sr=self.rows[-1]["success_rate"], ep=k["finished"])
                    if k["env_steps"] // c.checkpoint_every > before // c.checkpoint_every:
                        self.save()
                self.save()
            finally:
                bar.close()
            return not stop.is_set()


def _run_phase(
    config: HouseAgentConfig,
    out: Path,
    houses: TrainingHouses,
    pool: str,
    progress: bool,
    fresh: bool,
    init_ac: dict | None,
) -> HouseTrainRun:
    run = HouseTrainRun(config, out, houses, pool)
    state_path = out / STATE_FILE
    if state_path.exists() and not fresh:
        torchfile.resume(state_path, config, run.load_state_dict, "steps", "the state.pt of a house training run")
    else:
        if init_ac is not None:
            run.policy.ac.load_state_dict(init_ac)
        if run.policy.explore is not None:
            run.policy.explore.load_state_dict(load_checkpoint_file(Path(config.explorer))["ac"])
        out.mkdir(parents=True, exist_ok=True)
        write_json(out / CONFIG_FILE, config.to_json())
        run.begin()
    run.interrupted = not run.run(progress=progress)
    return run


def train(
    config: HouseAgentConfig,
    out: str | Path,
    houses: TrainingHouses | None = None,
    progress: bool = True,
    fresh: bool = False,
    command: str | None = None,
    cache_dir: str | None = None,
) -> HouseTrainRun:
    """Train ``config`` into ``out`` (resuming what is there), pretraining the actor-critic
    first into ``out/pretrain`` unless ``config.pretrained`` names one (DQN needs none)."""
    torch.set_num_threads(1)  # small networks: threads cost more than they give
    out = Path(out)
    if houses is None:
        houses = suite_training_houses(
            config.suite, config.observation, cache_dir, progress, config.max_start_steps, config.min_start_steps
        )
    out.mkdir(parents=True, exist_ok=True)
    if command:
        with atomic_write(out / "command.txt") as f:
            f.write(command + "\n")
    init_ac = None
    if config.method != "dqn":
        if config.pretrained:
            init_ac = load_checkpoint_file(Path(config.pretrained))["ac"]
        elif config.pretrain_steps > 0:
            pre_config = replace(
                config,
                method="a3c",
                max_steps=config.option_steps,
                steps=config.pretrain_steps,
                pretrain_steps=0,
                pretrained="",
                explorer="",
                relation=True,
                termination=True,
                high_level=True,
            )
            pre = _run_phase(pre_config, out / "pretrain", houses, "approach", progress, fresh, None)
            if pre.interrupted:
                return pre
            init_ac = pre.policy.ac.state_dict()
    return _run_phase(config, out, houses, "search", progress, fresh, init_ac)


def suite_training_houses(
    suite_name: str,
    observation: str = "gt",
    cache_dir: str | None = None,
    progress: bool = True,
    max_start_steps: int = START_STEPS[1],
    min_start_steps: int = START_STEPS[0],
) -> TrainingHouses:
    """The training houses and seen targets of a house suite (``objsearch.sim.suites``), search
    episodes starting ``min_start_steps`` to ``max_start_steps`` steps from the goals, and
    ending at the suite's step limits of single rooms (``room_max_steps``) where it has them."""
    from objsearch.sim.suites import load_suite_file, training_houses, training_targets

    suite = load_suite_file(suite_name)
    predictor = None
    if observation == "predicted":
        from objsearch.perception.inference import Predictor, resolve_checkpoint

        predictor = Predictor.from_checkpoint(str(resolve_checkpoint(None)), device="cpu")
    return TrainingHouses(
        training_houses(suite),
        training_targets(suite),
        cache_dir,
        predictor,
        progress,
        max_start_steps,
        min_start_steps,
        suite.get("room_max_steps"),
    )
