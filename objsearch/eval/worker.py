"""One process's share of an evaluation: an agent, a suite and its envs, built once, then
fed (split, seed, episode_id) units; each is played alone (``objsearch.eval.episode``) or
``batch`` at a time in lockstep (``objsearch.eval.lockstep``)."""

from __future__ import annotations

import copy
from typing import Iterable

from objsearch.eval.config import EvalConfig, Unit
from objsearch.eval.episode import run_episode
from objsearch.eval.lockstep import EnvSlots, play_lockstep
from objsearch.eval.runs import agent_of
from objsearch.eval.suites import Episode, make_suite, register_suite


class Worker:
    """An agent, a suite and its env: built once per process (or Ray actor), then fed units.

    ``folder``: the folder the evaluation started in, where a ``module:Class`` or relative
    ``file.py:Class`` agent is also looked for (default: the current folder). With
    ``video_dir``, the pictures of each unit in ``video_units`` (None: every unit) are
    written there by the suite's ``write_video(directory, record, episode, trajectory)``;
    those units are played one by one, first. With ``batch`` > 1, the others are played ``batch`` at a time in
    lockstep (``objsearch.eval.lockstep``): in the suite's own slots if it has them
    (``make_slots``), else one env per slot. ``agent``: an agent object to play instead of
    building ``config.agent`` (``objsearch.evaluate``); an unbatched one is copied for each
    lockstep slot past the first. ``suites``: the suites ``register_suite`` added in the
    process that started the evaluation (a worker process registers them again)."""

    def __init__(
        self,
        config: EvalConfig,
        video_dir: str | None = None,
        batch: int = 1,
        folder: str | None = None,
        video_units: Iterable[Unit] | None = None,
        agent=None,
        suites: dict[str, str] | None = None,
    ):
        for name, target in (suites or {}).items():
            register_suite(name, target)
        self.config, self.video_dir, self.batch, self.folder = config, video_dir, int(batch), folder
        self.video_units = None if video_units is None else frozenset(map(tuple, video_units))
        self.suite = make_suite(config.suite, **config.suite_config)
        self.env = self.suite.make_env()
        self.given = agent is not None
        self.agent = agent if self.given else agent_of(config, folder)
        self.episodes: dict[str, list[Episode]] = {}
        self._slots = None

    def episode(self, split: str, episode_id: int) -> Episode:
        """The suite's episode ``episode_id`` of ``split`` (each split's list is read once)."""
        if split not in self.episodes:
            self.episodes[split] = self.suite.episodes(split)
        return self.episodes[split][episode_id]

    def run(self, split: str, seed: int, episode_id: int) -> dict:
        """Play one unit alone and return its record (writing its pictures if it gets a video)."""
        episode = self.episode(split, episode_id)
        video = self.wants_video((split, seed, episode_id))
        trajectory = [] if video else None
        record = run_episode(
            self.agent, self.env, self.suite.name, split, episode, seed, self.config.step_time_limit, trajectory
        )
        if video:
            self.suite.write_video(self.video_dir, record, episode, trajectory)
        return record

    def wants_video(self, unit: Unit) -> bool:
        """Whether ``unit`` gets pictures."""
        return bool(self.video_dir) and (self.video_units is None or unit in self.video_units)

    def play(self, units: list[Unit]):
        """Records of ``units`` as they finish: the video units one by one, then the others
        in lockstep if ``batch`` > 1, else one by one."""
        yield from (self.run(*unit) for unit in units if self.wants_video(unit))
        units = [unit for unit in units if not self.wants_video(unit)]
        if self.batch <= 1:
            yield from (self.run(*unit) for unit in units)
            return
        if not units:
            return
        built = iter([self.agent])
        c = self.config
        another = (lambda: copy.deepcopy(self.agent)) if self.given else (lambda: agent_of(c, self.folder))
        make = lambda: next(built, None) or another()
        yield from play_lockstep(units, self.slots(), make, self.episode, self.suite.name, c.step_time_limit)

    def slots(self):
        """The ``batch`` lockstep slots, built once: the suite's own (``make_slots(n)``, the
        grid world's one ``BatchedGridWorld``) if it has them, else one env per slot."""
        if self._slots is None:
            make_slots = getattr(self.suite, "make_slots", None)
            if make_slots is not None:
                self._slots = make_slots(self.batch)
            else:
                self._slots = EnvSlots([self.env] + [self.suite.make_env() for _ in range(self.batch - 1)])
        return self._slots

    def run_chunk(self, units: list[Unit]) -> list[dict]:
        """The records of ``units``, all at once (what a pool process or Ray actor returns)."""
        return list(self.play(units))
