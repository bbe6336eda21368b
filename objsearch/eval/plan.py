"""An evaluation resolved once: ``resolve(config) -> EvalPlan``, which the executors play.

``resolve`` is the one place where an evaluation's config meets the registries: it builds the
suite (``objsearch.eval.suites``) and checks the splits, resolves the agent's class
(``objsearch.eval.registry``) and refuses an agent of another world or protocol, lists the
training runs it plays (``objsearch.eval.runs``) and each run's checkpoint, builds each play's
agent once to refuse it before the first episode (``check_perception``) and to read what the
results record of it (its weights' digest, the checkpoint it loaded), and lists the units
(split, seed, episode) and the units that get pictures. The executors (``executors``,
``worker``, ``lockstep``) only play the plan: each process builds the suite's envs and each
play's agent from it, and a process started for the evaluation rebuilds the suite from the
plan's config (``EvalPlan.open_suite``) without looking anything else up again.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from objsearch.errors import UserError
from objsearch.eval.agent import CHECKPOINTS_ENV, TrainingRun, build_agent
from objsearch.eval.config import EvalConfig, Unit
from objsearch.eval.registry import check_supports, resolve_agent
from objsearch.eval.runs import check_run_choice, listed_runs, run_config
from objsearch.eval.suites import REGISTERED, check_splits, make_suite, register_suite


@dataclass(frozen=True)
class AgentFactory:
    """Builds one play's agent, in any process, as ``make_agent`` would: the class's
    ``for_suite(suite, checkpoint)``, else ``cls()`` and ``load(checkpoint)``.

    Attributes:
        spec: the agent as the config names it (a registered name, ``module:Class`` or
            ``file.py:Class``).
        suite: the suite's name (what ``for_suite`` is given).
        checkpoint: what ``for_suite``/``load`` is given (the run's, the one given, or None).
        folder: where ``spec``'s module or relative file is also looked for.
        cls: the class ``spec`` resolved to in the process that resolved the plan; not pickled
            (a file agent's class cannot be unpickled elsewhere): a worker process resolves
            ``spec`` once, on its first build.
    """

    spec: str
    suite: str
    checkpoint: str | None
    folder: str
    cls: type | None = field(default=None, compare=False, repr=False)

    def __call__(self):
        """A new agent, with its checkpoint loaded."""
        if self.cls is None:  # in a worker process: the class, once
            object.__setattr__(self, "cls", resolve_agent(self.spec, self.folder))
        return build_agent(self.cls, self.spec, self.checkpoint, self.suite)

    def __getstate__(self) -> dict:
        return {**self.__dict__, "cls": None}


@dataclass(frozen=True)
class Play:
    """One agent played over the plan's units: the evaluation's only play, or one of an
    agent's several training runs.

    Attributes:
        config: its settings (with its ``training_run`` where it plays one of several, and its
            agent's ``weights_sha256``): the header of its partial-results file, and the
            results' ``config`` when it is the only play.
        agent: builds its agent; None when the evaluation was given an agent object
            (``EvalPlan.agent``).
        run: the training run it plays, as the agent lists it (None: the agent lists none,
            a checkpoint was given, or an agent object plays).
        loaded: the checkpoint its agent loads, as chosen (by the agent or its training run)
            or given; None when not known.
        partial: its partial-results file (with an output file), else None.
        video_dir: where its videos go (the first play's only), else None.
    """

    config: EvalConfig
    agent: AgentFactory | None
    run: TrainingRun | None = None
    loaded: str | None = None
    partial: str | None = None
    video_dir: str | None = None


@dataclass(frozen=True)
class EvalPlan:
    """An evaluation, resolved: what to play, with what, and what the results record.

    Attributes:
        config: the config with the suite's splits and full options filled in (what the
            results record as ``config`` when there are several plays).
        plays: one play per training run played (one when there is one run, none listed, a
            checkpoint was given, or an agent object plays).
        units: every (split, seed, episode_id) each play plays, in report order.
        video_units: the units that get pictures (with a play's ``video_dir``; None: every unit).
        registered_suites: the suites ``register_suite`` added in the resolving process, which
            a worker process registers again before it rebuilds the suite.
        suite: the suite, built in the resolving process; None in a worker process (or a plan
            made by ``resolve_play``): ``open_suite`` builds it there.
        agent: the agent object the evaluation plays in this process, if it was given one.
    """

    config: EvalConfig
    plays: tuple[Play, ...]
    units: tuple[Unit, ...]
    video_units: frozenset[Unit] | None = None
    registered_suites: tuple[tuple[str, str], ...] = ()
    suite: Any = field(default=None, compare=False, repr=False)
    agent: Any = field(default=None, compare=False, repr=False)

    @property
    def several(self) -> bool:
        """Whether the agent's several training runs are played (records tagged by run)."""
        return len(self.plays) > 1

    @property
    def recorded(self) -> EvalConfig:
        """The config the results record: the plan's with several plays, else the play's."""
        return self.config if self.several else self.plays[0].config

    @property
    def runs(self) -> list[tuple[TrainingRun, EvalConfig]]:
        """(training run, its play's config) of every play of a listed training run (``build_results``)."""
        return [(play.run, play.config) for play in self.plays if play.run is not None]

    @property
    def loaded(self) -> list[str | None]:
        """The checkpoint each play loads (``build_results``)."""
        return [play.loaded for play in self.plays]

    def open_suite(self):
        """The suite to play: the plan's own, or in a worker process one rebuilt from the
        config (the resolving process's registered suites registered first)."""
        if self.suite is not None:
            return self.suite
        for name, target in self.registered_suites:
            register_suite(name, target)
        return make_suite(self.config.suite, **self.config.suite_config)

    def portable(self) -> EvalPlan:
        """The plan as a worker process (local or a Ray actor) gets it: without the objects of
        this process (the suite, an agent object) and without the units (they come in chunks)."""
        return replace(self, suite=None, agent=None, units=())


def plan_units(suite, splits: list[str], seeds: tuple[int, ...], episodes: int | None = None) -> list[Unit]:
    """Every (split, seed, episode_id), in report order; with ``episodes``, only the first
    that many episodes of each split (``--episodes``)."""
    return [
        (split, seed, ep.episode_id) for split in splits for seed in seeds for ep in suite.episodes(split)[:episodes]
    ]


def video_units_of(suite, splits: list[str], seeds: tuple[int, ...], episodes: int) -> list[Unit]:
    """The units that get a video: the first ``episodes`` episodes (by id) of each split,
    with the first seed."""
    return [
        (split, seeds[0], ep.episode_id)
        for split in splits
        for ep in sorted(suite.episodes(split), key=lambda ep: ep.episode_id)[:episodes]
    ]


def check_perception(agent, suite) -> None:
    """Refuse an agent trained on one perception network's predictions (its
    ``trained_perception_key``) evaluated on another's: its numbers would measure neither."""
    trained = getattr(agent, "trained_perception_key", None)
    predictor = getattr(suite, "predictor", None)
    if trained and predictor is not None and predictor.key != trained:
        raise UserError(
            f"the agent's checkpoint {getattr(agent, 'loaded_from', '')} was trained on the predictions of "
            f"perception network {trained}, not those of {predictor.key} ({suite.perception}); pass --perception "
            "with the network it was trained on, or evaluate a checkpoint trained on this one"
        )


def _agent_class(config: EvalConfig, folder: str, runs: bool = True) -> tuple[type, list[TrainingRun]]:
    """The agent class of ``config`` (refused on a suite of another world or protocol) and,
    with ``runs``, the training runs it plays (``objsearch.eval.runs``; none with a checkpoint):
    resolved once."""
    check_run_choice(config)
    cls = resolve_agent(config.agent, folder)
    check_supports(config.agent, cls, config.suite)
    return cls, (listed_runs(config, cls) if runs and config.checkpoint is None else [])


def _checkpoints_used(plays: list[Play]) -> str | None:
    """The folder ``$OBJSEARCH_CHECKPOINTS`` names (absolute), if a play's agent loaded its
    weights from under it; else None (a training-free agent, or the shipped weights)."""
    if not os.environ.get(CHECKPOINTS_ENV):
        return None
    root = Path(os.environ[CHECKPOINTS_ENV]).resolve()
    loaded = [Path(p.loaded).resolve() for p in plays if p.loaded]
    return str(root) if any(path.is_relative_to(root) for path in loaded) else None


def resolve(
    config: EvalConfig,
    folder: str | None = None,
    agent=None,
    out: str | os.PathLike | None = None,
    video_dir: str | None = None,
    video_episodes: int = 2,
) -> EvalPlan:
    """Turn ``config`` into the plan that ``objsearch.eval.runner.evaluate`` plays.

    In order, each refusal a ``UserError`` before any episode: the suite (built once) and its
    splits; ``--video`` on a suite without videos; the agent's class, its world and protocol;
    its training runs (``config.training_run`` picks one; ``config.checkpoint`` plays that
    one alone); each play's agent, built once to refuse one trained on another perception
    network's predictions and to read its ``weights_sha256`` and ``loaded_from``.

    Args:
        config: the evaluation's config.
        folder: where the agent's module or relative file is also looked for (default: the
            current folder).
        agent: an agent object to play instead of building ``config.agent`` (which then only
            names it); played as it is (no training runs, no checkpoint).
        out: the results file, whose partial-results files the plays get.
        video_dir: where the first play's videos go; ``video_episodes``: how many episodes of
            each split (first seed) get one.
    """
    folder = os.path.abspath(folder or os.getcwd())
    suite = make_suite(config.suite, **config.suite_config)
    splits = check_splits(suite, list(config.splits))
    if video_dir and not hasattr(suite, "write_video"):
        raise UserError(f"--video is not available for suite {config.suite!r} (house suites have it)")
    # replace, not a new EvalConfig: every other field (and any field added later) is kept
    config = replace(config, splits=tuple(splits), suite_config=suite.config())
    cls, runs = _agent_class(config, folder) if agent is None else (None, [])
    several = len(runs) > 1
    configs = [run_config(config, run) for run in runs] if several else [config]
    listed = runs if len(runs) == len(configs) else [None] * len(configs)  # each play's run, as the agent lists it
    plays = []
    for i, (play, run) in enumerate(zip(configs, listed)):
        factory = None
        if agent is None:  # a play that names its training run (by seed) loads that run's checkpoint
            checkpoint = play.checkpoint if play.training_run is None else run.checkpoint
            factory = AgentFactory(config.agent, config.suite, checkpoint, folder, cls)
        built = agent if agent is not None else factory()  # once, to refuse it now and read what it loaded
        check_perception(built, suite)
        loaded = None
        if agent is None:  # as chosen (by the agent, or its training run) or given
            loaded = getattr(built, "loaded_from", None) or (run.checkpoint if run else None) or play.checkpoint
        partial = None
        if out:
            partial = f"{out}.run{play.training_run}.partial.jsonl" if several else f"{out}.partial.jsonl"
        weights = getattr(built, "weights_sha256", None)
        del built
        video = video_dir if i == 0 else None  # one run's pictures: the first's
        plays.append(Play(replace(play, weights_sha256=weights), factory, run, loaded, partial, video))
    found = _checkpoints_used(plays) if agent is None and config.checkpoint is None else None
    if found:  # the agent chose weights under $OBJSEARCH_CHECKPOINTS: recorded, so a replay loads the same
        config = replace(config, checkpoints=found)
        plays = [replace(p, config=replace(p.config, checkpoints=found)) for p in plays]
    units = plan_units(suite, splits, config.seeds, config.episodes)
    videos = frozenset(video_units_of(suite, splits, config.seeds, video_episodes)) if video_dir else None
    return EvalPlan(config, tuple(plays), tuple(units), videos, tuple(REGISTERED.items()), suite, agent)


def resolve_play(
    config: EvalConfig,
    units: list[Unit],
    folder: str | None = None,
    agent=None,
    video_dir: str | None = None,
    video_units=None,
) -> EvalPlan:
    """The plan that plays ``config`` as it is (one play, its ``training_run`` or
    ``checkpoint`` if it names one) over ``units``: a replay of recorded episodes
    (``objsearch leaderboard verify``). Only the agent is resolved here; the suite is built by
    the process that plays (``EvalPlan.open_suite``). ``video_units``: the units that get
    pictures in ``video_dir`` (None: every unit)."""
    folder = os.path.abspath(folder or os.getcwd())
    factory = None
    if agent is None:
        cls, runs = _agent_class(config, folder, runs=config.training_run is not None)
        checkpoint = config.checkpoint if config.training_run is None else runs[0].checkpoint
        factory = AgentFactory(config.agent, config.suite, checkpoint, folder, cls)
    videos = None if video_units is None else frozenset(map(tuple, video_units))
    play = Play(config, factory, video_dir=video_dir)
    return EvalPlan(config, (play,), tuple(units), videos, tuple(REGISTERED.items()), agent=agent)
