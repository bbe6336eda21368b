"""One process's share of an evaluation: one play of an ``EvalPlan`` (``objsearch.eval.plan``),
its suite's envs and its agent, built once, then fed (split, seed, episode_id) units; each is
played alone (``objsearch.eval.episode``) or ``batch`` at a time in lockstep
(``objsearch.eval.lockstep``). Nothing is looked up here: the plan says what to play."""

from __future__ import annotations

import copy

from objsearch.eval.config import Unit
from objsearch.eval.episode import run_episode
from objsearch.eval.lockstep import EnvSlots, play_lockstep
from objsearch.eval.plan import EvalPlan


class Worker:
    """The suite's env and one play's agent of ``plan``: built once per process (or Ray
    actor), then fed units.

    ``play``: the index of the play in ``plan.plays``. The suite is the plan's own in the
    process that resolved it, else rebuilt from the plan's config (``EvalPlan.open_suite``);
    the agent is the plan's agent object if it was given one, else the play's
    (``Play.agent``). With the play's ``video_dir``, the pictures of each unit in
    ``plan.video_units`` (None: every unit) are written there by the suite's
    ``write_video(directory, record, episode, trajectory)``; those units are played one by
    one, first. With ``batch`` > 1, the others are played ``batch`` at a time in lockstep
    (``objsearch.eval.lockstep``): in the suite's own slots if it has them (``make_slots``),
    else one env per slot; an agent object without the batched protocol is copied for each
    slot past the first, a built one built again."""

    def __init__(self, plan: EvalPlan, play: int = 0, batch: int = 1):
        chosen = plan.plays[play]
        self.batch, self.make_agent = int(batch), chosen.agent
        self.video_dir, self.video_units = chosen.video_dir, plan.video_units
        self.step_time_limit = chosen.config.step_time_limit
        self.suite = plan.open_suite()
        self.env = self.suite.make_env()
        self.given = plan.agent is not None
        self.agent = plan.agent if self.given else self.make_agent()
        self.episodes: dict = {}
        self._slots = None

    def episode(self, split: str, episode_id: int):
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
            self.agent, self.env, self.suite.name, split, episode, seed, self.step_time_limit, trajectory
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
        another = (lambda: copy.deepcopy(self.agent)) if self.given else self.make_agent
        make = lambda: next(built, None) or another()  # noqa: E731
        yield from play_lockstep(units, self.slots(), make, self.episode, self.suite.name, self.step_time_limit)

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
