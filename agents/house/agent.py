"""The house agents behind the evaluation protocol, and their ``train`` hook.

``HouseAgent`` wraps ``HousePolicy`` with N = 1. It is built for a suite
(``for_suite(suite, checkpoint)``): with no checkpoint it loads the one shipped for that
(suite, agent) pair in ``agents/checkpoints/<suite>/<agent>/``, and a missing pair is an
error that names the training command. That folder is the agent's training run of seed 0;
its ``seed<N>/`` folders hold runs of the same recipe with ``--seed N``
(``training_runs``: the harness evaluates them all). ``act(obs)`` turns the env's 64x64 frame into the
same 10x10 tables training used (``ObservationTables.from_frames``), keeps the last 4,
ends or continues the current option, picks a sub-goal if needed and an action.
Evaluation explores as the authors evaluated: actor-critics sample from their policy,
Q-learning levels take a random choice with probability ``eps_end`` (0.1).
"""

from __future__ import annotations

import csv
import json
import os
import re
import sys
from pathlib import Path

import numpy as np

from objsearch import digests
from objsearch.errors import UserError
from objsearch.eval.agent import CHECKPOINTS_ENV, OneSlotBatch, TrainingRun
from objsearch_agents.core.rows import RowRandom
from objsearch_agents.house.checkpoint import CONFIG_FILE, LOG_FILE, POLICY_FILE, load_policy
from objsearch_agents.house.config import HouseAgentConfig
from objsearch_agents.house.tables import HISTORY, ObservationTables

CHECKPOINTS = Path(__file__).resolve().parent.parent / "checkpoints"
ROOT = CHECKPOINTS.parent.parent  # the checkout: shipped configs name their inputs from here


# generator version -> the suite whose checkpoints were trained for unseen houses of that generator
# (its training houses, evaluated on other houses of the generator)
GENERALISATION_SUITES = {
    "house-gen-1": "house-gen",
    "house-gen-2": "house-gen-v2",
    "house-gen-3": "house-large",
    "house-gen-4": "house-large-v2",
}


def checkpoint_root() -> Path:
    """Where agents find their training runs: ``$OBJSEARCH_CHECKPOINTS`` (``CHECKPOINTS_ENV``)
    if set, else the shipped ``CHECKPOINTS``."""
    return Path(os.environ.get(CHECKPOINTS_ENV) or CHECKPOINTS)


def checkpoint_source() -> str:
    """Where agents look for their runs, as messages say it: ``shipped``, or ``in
    $OBJSEARCH_CHECKPOINTS (PATH)`` (with ``, no such folder`` when it is not one)."""
    root = os.environ.get(CHECKPOINTS_ENV)
    if not root:
        return "shipped"
    missing = "" if Path(root).is_dir() else ", no such folder"
    return f"in ${CHECKPOINTS_ENV} ({root}{missing})"


def default_checkpoint(suite: str, name: str) -> Path | None:
    """The seed-0 run of agent ``name`` for ``suite`` (its ``policy.pt``), if there is one."""
    path = checkpoint_root() / suite / name / POLICY_FILE
    return path if path.exists() else None


def suite_generator(suite: str) -> str | None:
    """The one generator version of a suite's evaluation houses (None if they mix several)."""
    from objsearch.sim.suites import load_suite_file, suite_generators

    generators = suite_generators(load_suite_file(suite))
    return generators.pop() if len(generators) == 1 else None


def generalisation_checkpoint(suite: str, name: str) -> tuple[Path | None, str | None]:
    """For a suite with no checkpoint of its own (a user's suite file): the shipped checkpoint
    trained for unseen houses of the suite's generator, and that generator."""
    generator = suite_generator(suite)
    trained_on = GENERALISATION_SUITES.get(generator)
    return (default_checkpoint(trained_on, name) if trained_on else None), generator


def training_cost(run: Path) -> tuple[int | None, float | None]:
    """(environment steps, seconds) that made the run folder ``run``: its own training (with
    its ``pretrain/``) plus that of the checkpoints it starts from (``pretrained``,
    ``explorer`` and its pretraining); None where a log is missing. The inputs are those its
    ``command.txt`` names with ``--set``, where a shipped run's command names where they are
    committed, else those of its ``config.json``, where they were when it trained."""
    config = json.loads((run / CONFIG_FILE).read_text())
    command = run / "command.txt"
    if command.exists():
        config.update(re.findall(r"--set (pretrained|explorer)=(\S+)", command.read_text()))
    folders = {run, run / "pretrain"}
    for key in ("pretrained", "explorer"):
        if config.get(key):
            start = Path(config[key])
            start = (start if start.is_absolute() else ROOT / start).parent
            folders |= {start, start / "pretrain"} if key == "explorer" else {start}
    steps, seconds = 0, 0.0
    for folder in {f.resolve() for f in folders}:
        log = folder / LOG_FILE
        if not log.exists():
            if folder.name == "pretrain" and not folder.exists():
                continue  # no pretraining of its own
            return None, None
        with log.open() as f:
            last = list(csv.DictReader(f))[-1]
        steps, seconds = steps + int(last["env_steps"]), seconds + float(last["wall_s"])
    return steps, round(seconds, 1)


def run_folders(agent_folder: Path) -> list[Path]:
    """The training runs shipped in ``agent_folder``: itself, then its ``seed<N>/`` by N."""
    seeds = [f for f in agent_folder.glob("seed*") if f.name[4:].isdigit() and (f / POLICY_FILE).exists()]
    return [agent_folder, *sorted(seeds, key=lambda f: int(f.name[4:]))]


class HouseAgent(OneSlotBatch):
    """A house agent from a ``HouseAgentConfig`` (subclasses set ``config``)."""

    config = HouseAgentConfig()
    explorer = False
    """The method with the back-up node's explorer (``HouseAgentConfig.explorer``): our
    extension, named ``<method>_explorer``; it trains with the suite's ``a3c`` as explorer,
    pointed at the target, unless ``--set explorer=...`` says otherwise."""

    @classmethod
    def worlds(cls) -> tuple[str, ...]:
        return ("house",)

    @classmethod
    def protocols(cls) -> tuple[str, ...]:
        """The paper's only: the learned agents have no STOP action (ObjectNav suites need one)."""
        return ("paper",)

    @classmethod
    def agent_name(cls) -> str:
        """The name this agent is registered, trained and shipped under."""
        return cls.config.name + ("_explorer" if cls.explorer else "")

    def __init__(self, suite: str = "house-single", checkpoint: str | os.PathLike | None = None):
        import torch

        torch.set_num_threads(1)  # batch-1 forwards of small networks: extra threads only contend
        self.suite = suite
        self.loaded_from: str | None = None
        name = self.agent_name()
        path = checkpoint if checkpoint is not None else default_checkpoint(suite, name)
        if path is None:
            path, generator = generalisation_checkpoint(suite, name)
            if path is None:
                run = f"runs/{Path(suite).stem}/{name}-seed0"
                raise UserError(
                    f"no {name} checkpoint is {checkpoint_source()} for suite {suite} (houses of generator {generator or 'several'}: "
                    f"checkpoints for unseen houses exist for {', '.join(GENERALISATION_SUITES)}); train one with "
                    f"`objsearch train --agent {name} --suite {suite}` (it writes {run}) and pass --checkpoint {run}"
                )
            print(
                f"{name}: suite {suite} has houses of generator {generator}; using the checkpoint trained on "
                f"{GENERALISATION_SUITES[generator]}'s training houses for unseen ones ({path})",
                file=sys.stderr,
            )
        self.load(path)

    @classmethod
    def for_suite(cls, suite: str, checkpoint: str | os.PathLike | None = None) -> "HouseAgent":
        return cls(suite, checkpoint)

    @classmethod
    def training_runs(cls, suite: str) -> list[TrainingRun]:
        """The shipped training runs for ``suite`` (those made for its generator's unseen
        houses when the suite has none of its own), each with its seed and cost."""
        name = cls.agent_name()
        path = default_checkpoint(suite, name) or generalisation_checkpoint(suite, name)[0]
        if path is None:
            return []
        runs = []
        for folder in run_folders(path.parent):
            seed = json.loads((folder / CONFIG_FILE).read_text())["seed"]
            runs.append(TrainingRun(int(seed), str(folder), *training_cost(folder)))
        return runs

    # -- checkpoints ------------------------------------------------------------------------
    def load(self, path: str | os.PathLike) -> None:
        """Load ``policy.pt`` (or a run directory holding it) and ``grg.npz`` beside it."""
        self.policy, files = load_policy(path, self._check_trained_for)
        self.loaded_from = str(files[0])
        self.weights_sha256 = digests.of_files(files)
        # the harness refuses predictions of another network than the one this policy learned from
        self.trained_perception_key = self.policy.perception_key

    def _check_trained_for(self, saved: HouseAgentConfig, path: Path) -> None:
        """Refuse a checkpoint trained as another agent, or on another suite than this one's
        unless it was trained for unseen houses of this suite's generator (``GENERALISATION_SUITES``);
        warn when this suite holds houses that checkpoint trained on. (The camera, and the
        perception network of predicted observations, are checked where they are paired.)"""
        if saved.name != self.agent_name():
            raise UserError(
                f"checkpoint {path} was trained as {saved.name}, not {self.agent_name()}; pick --agent {saved.name}"
            )
        if saved.suite == self.suite:
            return
        generator = suite_generator(self.suite)
        if GENERALISATION_SUITES.get(generator) != saved.suite:
            made_for = next((g for g, s in GENERALISATION_SUITES.items() if s == saved.suite), None)
            what = f"for unseen houses of generator {made_for}" if made_for else "for that suite's houses only"
            raise UserError(
                f"checkpoint {path} was trained on suite {saved.suite} ({what}), but suite {self.suite} has houses of "
                f"generator {generator or 'several'}; pass a checkpoint trained on {self.suite} or for its generator "
                f"({GENERALISATION_SUITES.get(generator, 'none is shipped')})"
            )
        from objsearch.sim.suites import load_suite_file

        trained = {info.get("spec_sha256") for info in load_suite_file(saved.suite)["training_houses"].values()}
        seen = sorted(
            h for h, info in load_suite_file(self.suite)["houses"].items() if info.get("spec_sha256") in trained
        )
        if seen:
            print(
                f"warning: {len(seen)} house(s) of suite {self.suite} ({', '.join(seen[:3])}{', ...' if len(seen) > 3 else ''}) "
                f"are training houses of {path}: results on them are not held out",
                file=sys.stderr,
            )

    # -- the protocol (one episode, or N in lockstep: the same code, OneSlotBatch) -----------
    def start_batch(self, num_slots: int) -> None:
        self._slots = int(num_slots)
        self.policy.start(self._slots)
        idle = np.random.default_rng(0)  # draws of an idle slot are thrown away
        self._rngs = [idle] * self._slots
        self._frames: list[list | None] = [None] * self._slots
        self.epsilon = np.full(self._slots, self.policy.config.eps_end)

    def reset_batch(self, tasks: dict) -> None:
        slots = np.array(sorted(tasks), dtype=np.int64)
        self.policy.begin_episodes(slots, np.array([int(tasks[i].goal) for i in slots], np.int64))
        for i in slots:
            self._rngs[i], self._frames[i] = tasks[i].rng, None

    def act_batch(self, observations: dict) -> dict:
        busy = sorted(observations)
        for i in busy:
            obs = observations[i]
            if not isinstance(obs, dict) or not {"semantic", "depth"} <= set(obs):
                raise TypeError("a house agent needs the house env's observation (semantic, depth, target)")
            frame = ObservationTables.from_frames(np.asarray(obs["semantic"])[None], np.asarray(obs["depth"])[None])
            # the last 4 frames, oldest first; an episode's first frame fills the history
            self._frames[i] = [frame] * HISTORY if self._frames[i] is None else self._frames[i][1:] + [frame]
        rows = [self._frames[i] if i in observations else self._frames[busy[0]] for i in range(self._slots)]
        tables = ObservationTables.concat([f for row in rows for f in row])
        hist = np.arange(self._slots * HISTORY).reshape(self._slots, HISTORY)
        rng = RowRandom(self._rngs)
        p = self.policy
        p.advance(tables, hist, np.zeros(self._slots, bool), count=False)  # no-op for slots on their first step
        if p.config.hierarchical:
            p.select_subgoals(tables, hist, self.epsilon, rng)
        actions, _ = p.actions(tables, hist, self.epsilon, rng)
        return {i: int(actions[i]) for i in busy}

    # -- training -----------------------------------------------------------------------------
    @classmethod
    def train(
        cls,
        *,
        suite: str,
        out: str | os.PathLike,
        episodes: int | None = None,
        steps: int | None = None,
        seed: int = 0,
        overrides: dict[str, str] | None = None,
        fresh: bool = False,
        progress: bool = True,
        command: str | None = None,
    ) -> dict:
        """Train this agent on a house suite's training houses (the ``objsearch train`` hook)."""
        from dataclasses import replace

        if episodes is not None:
            raise UserError("house agents train for a number of environment steps: pass --steps, not --episodes")

        from objsearch_agents.house.train import train

        overrides = dict(overrides or {})
        if cls.explorer and "explorer" not in overrides:  # the shipped recipe: the suite's A3C, pointed at the target
            explorer = default_checkpoint(suite, "a3c")
            if explorer is None:
                raise UserError(
                    f"{cls.agent_name()} runs a trained a3c in its back-up node and none is {checkpoint_source()} for suite "
                    f"{suite}: "
                    "train one (objsearch train --agent a3c) and pass --set explorer=PATH/policy.pt"
                )
            overrides = {"explorer": os.path.relpath(explorer, ROOT), "explorer_target": "true", **overrides}
        config = replace(cls.config, seed=int(seed), suite=suite).with_overrides(overrides)
        if steps is not None:
            config = replace(config, steps=int(steps))
        if config.name != cls.agent_name():
            raise UserError(
                f"these settings train {config.name}, not {cls.agent_name()} (an explorer in the back-up node is our "
                f"extension of the paper's method, with its own name): pass --agent {config.name}"
            )
        run = train(config, out, progress=progress, fresh=fresh, command=command)
        return {
            "out": str(out),
            "finished": run.counters.finished,
            "env_steps": run.counters.env_steps,
            "interrupted": run.interrupted,
            "wall_s": run.counters.wall_s,
        }
