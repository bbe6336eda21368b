"""The one configuration of the house agents (A3C, DQN, h-DQN, HRL-GRG and its ablations):
the paper's protocol (appendix B.3, table 9) plus the facts of the authors' code, with the
deviations of ``docs/house_agents.md``. Written as ``config.json`` beside every checkpoint."""

from __future__ import annotations

from dataclasses import dataclass

from objsearch.errors import UserError
from objsearch_agents.core.config import AgentConfig
from objsearch_agents.methods import METHODS


@dataclass(frozen=True)
class HouseAgentConfig(AgentConfig):
    """Serialised, read and overridden (``--set``) through ``objsearch.configs.JsonConfig``;
    checked and named through ``core.config.AgentConfig``."""

    DESCRIPTION = "a house agent config"
    LEGACY_KEYS = {}  # no field has been renamed or removed (files from before ``explorer`` lack it: its default)

    method: str = "hrl_grg"
    """``a3c`` (actor-critic on the target), ``dqn``, ``hdqn`` (DQN over sub-goals, A3C low level) or ``hrl_grg``."""
    relation: bool = True
    """hrl_grg: weight the candidate's mask by its plan value C(sg -> g) (False: the "-relation" ablation)."""
    termination: bool = True
    """hrl_grg: end an option when a later node of its plan comes into view (False: "-termination")."""
    high_level: bool = True
    """hrl_grg: choose sub-goals with the network (False: "-high-level", the best plan value)."""
    suite: str = "house-single"
    """The suite whose training houses and seen targets the agent trains on."""
    observation: str = "gt"
    """``gt`` or ``predicted`` (the shipped perception network's segmentation and depth)."""
    seed: int = 0
    """Seeds the networks, task sampling, exploration and replay sampling."""
    steps: int = 10_000_000
    """Environment steps of the main phase (summed over the parallel envs)."""
    num_envs: int = 32
    """Episodes run in parallel (one forward pass per level per step for all)."""
    max_steps: int = 1000
    """Primitive steps per episode (N_max)."""
    option_steps: int = 50
    """Low-level steps per sub-goal at most (N_max^l); also the GRG's number of 'seen after k' categories."""
    gamma: float = 0.99
    """Discount of every learner."""
    grg_gamma: float = 0.99
    """Discount of the GRG's event values gamma^(k-1)."""
    lr: float = 1e-4
    """RMSProp learning rate of the Q-networks."""
    ac_lr: float = 5e-4
    """RMSProp learning rate of the actor-critics (batched A2C: one update per rollout of all envs)."""
    rmsprop_alpha: float = 0.99
    """RMSProp decay of the squared-gradient average (PyTorch's default, and A3C's; the grid
    world's 0.9 is TensorFlow 1's)."""
    rmsprop_eps: float = 1e-5
    """RMSProp epsilon."""
    max_grad_norm: float = 40.0
    """Gradients are clipped to this global norm."""
    entropy: float = 0.01
    """Entropy bonus of the actor-critic loss (beta)."""
    rollout: int = 10
    """Actor-critic update interval: n-step rollouts of this many steps (A3C_update)."""
    batch_size: int = 64
    """Transitions per Q-network update."""
    replay_size: int = 10_000
    """Replay memory of a Q-network (transitions, stored as pose ids)."""
    update_every: int = 100
    """One Q-network update every this many environment transitions (summed over the envs; main_update)."""
    target_update: int = 100_000
    """Hard copy of online into target Q-networks every this many environment transitions."""
    learning_starts: int = 1_000
    """Transitions a replay memory must hold before its network is updated."""
    eps_start: float = 1.0
    """Initial exploration rate of the Q-learning level."""
    eps_end: float = 0.1
    """Final exploration rate (also used at evaluation, as the authors evaluated)."""
    eps_anneal_episodes: int = 10_000
    """Episodes over which exploration falls linearly from eps_start to eps_end."""
    curriculum_episodes: int = 10_000
    """Episode i starts among the nearest max(1, N * min((i + 10) / this, 1)) start poses."""
    min_start_steps: int = 6
    """Search episodes start this many to ``max_start_steps`` minimal steps from the target's
    goal poses (the suites' window, ``START_STEPS``; ``rooms``, whose episodes start 1 step away
    and more, trains from 1 as the authors' AI2-THOR code did)."""
    max_start_steps: int = 40
    """The farthest search start (the authors' House3D DQN trained from starts under 20)."""
    pretrain_steps: int = 4_000_000
    """Environment steps of the approach pretraining of the actor-critic (0: none)."""
    pretrained: str = ""
    """A ``policy.pt`` whose actor-critic starts this run (empty: pretrain in ``OUT/pretrain``)."""
    explorer: str = ""
    """Hierarchical methods: a ``policy.pt`` whose actor-critic runs the back-up node's options,
    e.g. the suite's trained ``a3c``, which learned to move through the training houses with
    the target out of view (empty: the low level on depth alone, as the authors' code)."""
    explorer_target: bool = False
    """With ``explorer``: point the explorer at the episode's target (the A3C's own input: the
    target's mask and depth), so the back-up node searches for the target, approaching it
    once in view (False: the back-up node's empty mask)."""
    train_low: bool = False
    """Hierarchical methods: keep training the low level (A2C, ``ac_lr``) on the intrinsic reward, 1 on
    reaching the option's sub-goal, as the authors' code does (False: the pretrained approach policy, frozen)."""
    plan_every: int = 10
    """hrl_grg: re-plan the GRG every this many batched steps (the reference: once per episode)."""
    checkpoint_every: int = 500_000
    """Write a resumable checkpoint every this many environment steps."""
    log_every: int = 100_000
    """Append a row to ``log.csv`` every this many environment steps."""

    METHODS = METHODS
    AT_LEAST_ONE = (
        "num_envs",
        "max_steps",
        "option_steps",
        "batch_size",
        "replay_size",
        "update_every",
        "target_update",
        "rollout",
        "eps_anneal_episodes",
        "curriculum_episodes",
        "min_start_steps",
        "max_start_steps",
        "plan_every",
        "checkpoint_every",
        "log_every",
    )

    def check(self) -> None:
        if self.observation not in ("gt", "predicted"):
            raise UserError(f"observation must be gt or predicted, not {self.observation!r}")
        for flag in ("explorer", "explorer_target", "train_low"):
            if getattr(self, flag) and not self.hierarchical:
                raise UserError(
                    f"{flag} applies to the hierarchical methods (hdqn, hrl_grg), not {self.method}; drop it"
                )
        if self.explorer_target and not self.explorer:
            raise UserError(
                "explorer_target=true needs an explorer (--set explorer=PATH/policy.pt); drop it or add one"
            )
        if self.min_start_steps > self.max_start_steps:
            raise UserError(
                f"min_start_steps={self.min_start_steps} is above max_start_steps={self.max_start_steps}: no search "
                "episode could start; lower the first or raise the second"
            )

    @property
    def name(self) -> str:
        """The agent name this config trains (``hrl_grg_no_relation`` for an ablation,
        ``hrl_grg_explorer``/``hdqn_explorer`` with an ``explorer``: our extension, not the paper's method)."""
        return super().name + ("_explorer" if self.explorer else "")
