"""The one configuration of the grid-world learning agents (DQN, h-DQN, HRL-GRG and its
ablations): the paper's protocol (appendix A.2, table 6) plus what the authors' code
settles (``docs/gridworld_agents.md``). It is written as ``config.json`` next to every
checkpoint, so a run can be rebuilt from the file alone."""

from __future__ import annotations

from dataclasses import dataclass

from objsearch.errors import UserError
from objsearch_agents.core.config import AgentConfig

METHODS = ("dqn", "hdqn", "hrl_grg")
STARTS = ("curriculum", "visible")


@dataclass(frozen=True)
class GridAgentConfig(AgentConfig):
    """Serialised, read and overridden (``--set``) through ``objsearch.configs.JsonConfig``;
    checked and named through ``core.config.AgentConfig``."""

    METHODS = METHODS

    DESCRIPTION = "a grid-world agent config"
    LEGACY_KEYS = {}  # no field has been renamed or removed since the first checkpoints

    method: str = "hrl_grg"
    """Which learner: ``dqn`` (flat), ``hdqn`` (17-output high level) or ``hrl_grg``."""
    relation: bool = True
    """hrl_grg: multiply the candidate channel by its plan value C(sg -> g) (False: the "-relation" ablation)."""
    termination: bool = True
    """hrl_grg: end an option when a later node of the plan from the sub-goal becomes visible (False: "-termination")."""
    high_level: bool = True
    """hrl_grg: choose sub-goals with the high-level network (False: "-high-level", best plan value)."""
    seed: int = 0
    """Seeds the network initialisation, the environments, exploration and replay sampling."""
    episodes: int = 100_000
    """Training episodes of the main phase (finished episodes, counted over all parallel envs)."""
    num_envs: int = 64
    """Episodes run in parallel by the batched grid world (one forward pass per step for all)."""
    max_steps: int = 100
    """Primitive steps per episode (N_max)."""
    option_steps: int = 10
    """Low-level steps per sub-goal at most (N_max^l); also the GRG's number of 'seen after k' categories."""
    gamma: float = 0.99
    """Discount of both levels' Q-learning."""
    grg_gamma: float = 0.99
    """Discount of the GRG's event values gamma^(k-1)."""
    lr: float = 1e-4
    """RMSProp learning rate of every network."""
    rmsprop_alpha: float = 0.9
    """RMSProp decay of the squared-gradient average (TensorFlow 1's default, as the reference)."""
    rmsprop_eps: float = 1e-5
    """RMSProp epsilon, added outside the square root (about TensorFlow's 1e-10 inside it)."""
    max_grad_norm: float = 40.0
    """Gradients are clipped to this global norm."""
    batch_size: int = 64
    """Transitions per gradient update."""
    replay_size: int = 10_000
    """Replay memory per level (transitions)."""
    update_every: int = 10
    """One gradient update per level every this many environment transitions (summed over the parallel envs)."""
    target_update: int = 10_000
    """Hard copy of the online into the target networks every this many environment transitions."""
    learning_starts: int = 1_000
    """Transitions a replay memory must hold before its network is updated."""
    eps_start: float = 1.0
    """Initial exploration rate of the acting level (high level; DQN's actions)."""
    eps_end: float = 0.1
    """Final exploration rate."""
    eps_anneal_episodes: int = 10_000
    """Episodes over which the exploration rate falls linearly from eps_start to eps_end."""
    low_epsilon: float = 0.1
    """Exploration rate of the low level of the hierarchical agents, throughout training."""
    eval_epsilon: float = 0.1
    """Exploration rate used at evaluation (both levels), as the authors evaluated; 0 = greedy."""
    curriculum_episodes: int = 10_000
    """Curriculum length: episode i starts among the nearest max(1, N * min((i + 10) / this, 1)) of the N start cells."""
    starts: str = "curriculum"
    """Start cells: ``curriculum`` (main phase) or ``visible`` (pretraining: the goal is in view at the start)."""
    pretrain_episodes: int = 20_000
    """Episodes of the low-level pretraining (goal-reaching DQN from starts where the goal is visible)."""
    pretrained: str = ""
    """A low-level ``policy.pt`` to start from; empty: pretrain in ``OUT/pretrain`` first (0 pretrain episodes: none)."""
    checkpoint_every: int = 5_000
    """Write a resumable checkpoint every this many finished episodes."""
    log_every: int = 1_000
    """Append a row to ``log.csv`` every this many finished episodes."""

    AT_LEAST_ONE = (
        "num_envs",
        "max_steps",
        "option_steps",
        "batch_size",
        "replay_size",
        "update_every",
        "target_update",
        "eps_anneal_episodes",
        "curriculum_episodes",
        "checkpoint_every",
        "log_every",
    )

    def check(self) -> None:
        if self.starts not in STARTS:
            raise UserError(f"starts must be one of {STARTS}, not {self.starts!r}")
