"""One phase of house training (pretraining or the main phase): N episodes in lockstep on
observation tables (``episodes.EpisodeBatch``), one forward pass per level per step, and
the learners of the method (``objsearch_agents.methods``): the actor-critic's synchronous
A2C and the Q-network's Double DQN. ``house.train`` runs the phases; ``train_log`` keeps
the counters and ``log.csv``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from objsearch import torchfile
from objsearch.fileio import write_csv
from objsearch_agents.core.a2c import ActorCriticLearner
from objsearch_agents.core.double_dqn import Learner
from objsearch_agents.core.nets import as_tensor
from objsearch_agents.core.replay import ReplayBuffer
from objsearch_agents.core.training_loop import TrainingLoop, owed_updates
from objsearch_agents.house.checkpoint import LOG_FILE, STATE_FILE, save_policy
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.episodes import EpisodeBatch, TrainingHouses, object_node
from objsearch_agents.house.policy import HousePolicy
from objsearch_agents.house.tables import HISTORY
from objsearch_agents.house.train_log import LOG_FIELDS, Counters, Window, log_row
from objsearch_agents.house.world import RANDOM, low_input, node_category

REPLAY_FIELDS = {
    "hist": ((HISTORY,), np.int64),
    "target": ((), np.int64),
    "action": ((), np.int64),
    "reward": ((), np.float32),
    "next_hist": ((HISTORY,), np.int64),
    "done": ((), np.float32),
}
"""A Q-network's transitions, stored as pose ids (the observation is rebuilt from the tables)."""


class HouseTrainRun(TrainingLoop):
    """One training phase: its state, its loop, its files."""

    def __init__(self, config: HouseAgentConfig, out: Path, houses: TrainingHouses, pool: str = "search"):
        self.config = config
        self.out, self.houses, self.pool = Path(out), houses, pool
        self.tables = houses.tables
        self.rng = np.random.default_rng([config.seed, 11])
        self.policy = HousePolicy(config)
        self.method = self.policy.method
        self.batch = EpisodeBatch(houses, config.num_envs, config.max_steps)
        self.ac = None  # the actor-critic's learner: A3C, or a hierarchical low level with train_low
        if self.method.trains_actor_critic(config):
            self.ac = ActorCriticLearner(
                self.policy.ac,
                config.ac_lr,
                config.rmsprop_alpha,
                config.rmsprop_eps,
                config.max_grad_norm,
                config.entropy,
                config.gamma,
            )
        self.q = self.replay = None
        if self.policy.q is not None:
            self.q = Learner(self.policy.q, config)
            self.replay = ReplayBuffer(config.replay_size, REPLAY_FIELDS)
        self.rollout: list = []
        self.episode_ix = np.zeros(config.num_envs, np.int64)
        self.counters = Counters()
        self.window = Window()
        self.rows: list[dict] = []
        self.interrupted = False

    def _start_episodes(self, env_ids: np.ndarray) -> None:
        ix = self.counters.started + np.arange(len(env_ids))
        self.counters.started += len(env_ids)
        pairs, starts = self.houses.sample(self.pool, ix, self.config.curriculum_episodes, self.rng)
        self.episode_ix[env_ids] = ix
        self.batch.start(env_ids, pairs, starts)
        self.policy.begin_episodes(env_ids, self.batch.target[env_ids])

    def begin(self) -> None:
        self.policy.start(self.config.num_envs)
        self._start_episodes(np.arange(self.config.num_envs))

    # -- one batched step ----------------------------------------------------------------------
    def step(self) -> None:
        policy, batch, tables = self.policy, self.batch, self.tables
        hierarchical = self.method.hierarchical
        hist = batch.hist.copy()
        eps = self.epsilon(self.episode_ix)
        if hierarchical:
            policy.select_subgoals(tables, hist, eps, self.rng)
        chosen = policy.subgoal.copy() if hierarchical else None
        actions, inputs = policy.actions(tables, hist, eps, self.rng)
        success, truncated = batch.step(actions)
        over = success | truncated
        reward = success.astype(np.float32)
        if self.replay is not None:  # the Q-learning level's transition: its own choice, the extrinsic reward
            self.replay.add(
                hist=hist,
                target=batch.target.copy(),
                action=chosen if hierarchical else actions,
                reward=reward,
                next_hist=batch.hist.copy(),
                done=reward,
            )
        if hierarchical:
            ended = policy.advance(tables, batch.hist, over, count=True)
            if self.ac is not None:
                self._record_low(inputs, actions, chosen, success, ended)
        elif self.ac is not None:
            self.rollout.append((inputs, actions, reward, over.astype(np.float32), np.ones(len(actions), bool)))
        done = np.flatnonzero(over)
        if len(done):
            self.window.finish(success[done], batch.steps[done])
            self.counters.finished += len(done)
            self._start_episodes(done)
        if self.ac is not None and len(self.rollout) == self.config.rollout:
            self._learn_ac()
        self._learn_q(len(actions))
        self.counters.batched_steps += 1
        if policy.grg is not None and self.counters.batched_steps % self.config.plan_every == 0:
            policy.refresh_plans()

    @torch.no_grad()
    def _record_low(self, inputs, actions, chosen, success, ended) -> None:
        """A low-level step of every env toward the sub-goal it had (``chosen``): reward 1
        when reached (the target: at a goal pose), the option's end cuts the return, and an
        option that ended unreached is bootstrapped with V(s', sub-goal)."""
        policy = self.policy
        reward = (policy.reached | (success & (chosen == object_node(policy.target)))).astype(np.float32)
        cut = np.flatnonzero(ended & (reward == 0) & (chosen < RANDOM))
        if len(cut):
            low_in = low_input(self.tables, self.batch.hist[cut], node_category(chosen[cut]))
            _, value = policy.ac(*map(as_tensor, low_in))
            reward[cut] += np.float32(self.config.gamma) * value.numpy()
        self.rollout.append((inputs, actions, reward, ended.astype(np.float32), chosen < RANDOM))

    def _learn_ac(self) -> None:
        """One A2C update on the rollout's transitions (``valid`` ones: the back-up node's are not used)."""
        masks, depths, actions, rewards, dones, valid = zip(
            *[(i[0], i[1], a, r, d, v) for i, a, r, d, v in self.rollout]
        )
        self.rollout = []
        with torch.no_grad():
            low_in = low_input(self.tables, self.batch.hist, self.policy.acting_category())
            _, bootstrap = self.policy.ac(*map(as_tensor, low_in))
        returns = self.ac.returns(np.stack(rewards), np.stack(dones), bootstrap.numpy())
        keep = np.concatenate(valid)
        if not keep.any():
            return
        flat = lambda x: np.concatenate(x)[keep]
        loss = self.ac.update(
            (as_tensor(flat(masks)), as_tensor(flat(depths))), flat(actions), returns.reshape(-1)[keep]
        )
        self.window.loss_ac[0] += loss
        self.window.loss_ac[1] += 1

    def _learn_q(self, transitions: int) -> None:
        """Q-network updates owed for ``transitions`` more steps (one per ``update_every``),
        once the replay holds enough; the target network is copied every ``target_update``."""
        c, k = self.config, self.counters
        before = k.env_steps
        k.env_steps += transitions
        if self.q is None:
            return
        updates, k.credit = owed_updates(k.credit, transitions, c.update_every)
        if len(self.replay) < max(c.learning_starts, c.batch_size):
            return
        for _ in range(updates):
            batch = self.replay.sample(c.batch_size, self.rng)
            loss = self.method.q_loss(self.q, batch, self.policy, self.tables)
            self.window.loss_q[0] += self.q.step(loss)
            self.window.loss_q[1] += 1
            k.updates += 1
        if k.env_steps // c.target_update > before // c.target_update:
            self.q.sync_target()

    # -- log and files -------------------------------------------------------------------------
    def log_row(self) -> None:
        epsilon = float(self.epsilon(np.array([self.counters.started]))[0]) if self.q is not None else None
        grg_counts = int(self.policy.grg.counts.sum()) if self.policy.grg is not None else None
        self.rows.append(log_row(self.counters, self.window, epsilon, grg_counts))
        self.window = Window()

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
            "counters": self.counters.state_dict(),
            "window": self.window.state_dict(),
            "rows": list(self.rows),
            "arrays": arrays,
            "ac": self.ac.state_dict() if self.ac is not None else None,
            "q": self.q.state_dict() if self.q is not None else None,
            "low": self.policy.ac.state_dict() if self.policy.ac is not None else None,
            "explore": self.policy.explore.state_dict() if self.policy.explore is not None else None,
        }

    def load_state_dict(self, s: dict) -> None:
        self.counters, self.window, self.rows = Counters(**s["counters"]), Window(**s["window"]), list(s["rows"])
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
        self.write_log()
        torchfile.save(self.out / STATE_FILE, self.state_dict())

    # -- the loop (training_loop.TrainingLoop.run) ----------------------------------------------
    def done(self) -> int:
        return self.counters.env_steps

    def goal(self) -> int:
        return self.config.steps

    def describe(self) -> str:
        return f"train {self.config.name}" + (" (pretrain)" if self.pool == "approach" else "")

    def write_log(self) -> None:
        write_csv(self.out / LOG_FILE, LOG_FIELDS, self.rows)

    def postfix(self) -> dict:
        return {"sr": self.rows[-1]["success_rate"], "ep": self.counters.finished}

    def wall_seconds(self) -> float:
        return self.counters.wall_s

    def set_wall_seconds(self, seconds: float) -> None:
        self.counters.wall_s = seconds
