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

This module is the recipe: pretraining, then the main phase, each a ``train_run.HouseTrainRun``
(the lockstep loop and the learners; each method's decisions and loss: ``objsearch_agents.methods``).
Files in the run directory (their format: ``house.checkpoint``): ``config.json``, ``command.txt``, ``policy.pt`` (+ ``grg.npz``)
the evaluable policy, ``state.pt`` everything to resume exactly, ``log.csv``. Rerunning
the same command resumes (only ``steps`` may change).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import torch

from objsearch.fileio import write_json
from objsearch.sim.house_task import START_STEPS
from objsearch_agents.core.training_loop import write_command
from objsearch_agents.house.checkpoint import CONFIG_FILE, STATE_FILE, load_checkpoint_file
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.episodes import TrainingHouses
from objsearch_agents.house.train_run import HouseTrainRun
from objsearch_agents.methods import method_of

__all__ = ["HouseTrainRun", "suite_training_houses", "train"]


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

    def start() -> None:
        if init_ac is not None:
            run.policy.ac.load_state_dict(init_ac)
        if run.policy.explore is not None:
            run.policy.explore.load_state_dict(load_checkpoint_file(Path(config.explorer))["ac"])
        out.mkdir(parents=True, exist_ok=True)
        write_json(out / CONFIG_FILE, config.to_json())

    return run.start_or_resume(out / STATE_FILE, fresh, progress, "the state.pt of a house training run", start)


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
    write_command(out, command)
    init_ac = None
    if method_of(config.method).actor_critic:  # pretrain it (all but DQN)
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
                explorer_target=False,
                train_low=False,
                relation=True,
                termination=True,
                high_level=True,
            )  # the approach policy is an A3C of its own: none of the hierarchy's switches
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
