"""The loop every trainer runs (grid world, houses, Scene Priors): step until the goal,
append a ``log.csv`` row every ``log_every`` and write a resumable checkpoint every
``checkpoint_every`` (both counted in the trainer's own unit: episodes or env steps), and on
Ctrl-C or SIGTERM finish the current step, write a checkpoint and return False.

A trainer subclasses ``TrainingLoop`` and provides ``step``, ``log_row``, ``write_log`` and
``save``, a ``config`` with ``log_every`` and ``checkpoint_every``, and the few hooks below.
What every trainer does the same way is here too: starting a run or resuming it from its
``state.pt`` (``start_or_resume``), its ``command.txt`` (``write_command``), and for the
Q-learning trainers the exploration schedule (``epsilon``) and the updates owed per
transitions (``owed_updates``).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from objsearch import torchfile
from objsearch.fileio import atomic_write


class TrainingLoop:
    """``run()``: the loop, shared. Subclasses say what they count and what the bar shows."""

    unit = "step"
    """What ``done()`` counts, for the progress bar: ``ep`` or ``step``."""
    budget = "steps"
    """The config field ``goal()`` reads: the one field a resumed run may change."""

    def done(self) -> int:
        """Progress towards ``goal()``: episodes finished or env steps taken."""
        raise NotImplementedError

    def goal(self) -> int:
        """Where training ends, in ``done()``'s unit."""
        raise NotImplementedError

    def describe(self) -> str:
        """The progress bar's label."""
        raise NotImplementedError

    def postfix(self) -> dict:
        """What the bar shows after each ``log.csv`` row (from the last row)."""
        raise NotImplementedError

    def wall_seconds(self) -> float:
        """Training time so far (it survives resuming)."""
        raise NotImplementedError

    def set_wall_seconds(self, seconds: float) -> None:
        raise NotImplementedError

    def start_or_resume(self, state: Path, fresh: bool, progress: bool, what: str, start: Callable[[], None]):
        """Resume from the training state ``state`` (``what`` it is, for errors) unless
        ``fresh`` or it is missing, else ``start()`` a new run (initial weights, ``config.json``)
        and ``begin()``; then ``run``. Returns self, ``interrupted`` telling whether it was stopped."""
        if state.exists() and not fresh:
            torchfile.resume(state, self.config, self.load_state_dict, self.budget, what)
        else:
            start()
            self.begin()
        self.interrupted = not self.run(progress=progress)
        return self

    def epsilon(self, episode_ix: np.ndarray) -> np.ndarray:
        """The Q-learning level's exploration rate of episodes ``episode_ix`` (fixed per episode at
        its start): ``eps_start`` falling linearly to ``eps_end`` over ``eps_anneal_episodes``."""
        c = self.config
        return np.maximum(c.eps_end, c.eps_start - (c.eps_start - c.eps_end) * episode_ix / c.eps_anneal_episodes)

    def run(self, progress: bool = True) -> bool:
        """Train until ``goal()``, checkpointing as it goes. Returns False if interrupted (Ctrl-C
        or SIGTERM: the current step finishes, then a checkpoint is written)."""
        from tqdm import tqdm

        from objsearch.interrupt import stop_on_interrupt

        c, goal = self.config, self.goal()
        with stop_on_interrupt() as stop:
            bar = tqdm(
                total=goal,
                initial=min(self.done(), goal),
                unit=self.unit,
                unit_scale=self.unit == "step",
                desc=self.describe(),
                disable=not progress or None,
                smoothing=0.05,
            )
            try:
                t0, wall0 = time.perf_counter(), self.wall_seconds()
                while self.done() < goal and not stop.is_set():
                    before = self.done()
                    self.step()
                    self.set_wall_seconds(wall0 + time.perf_counter() - t0)
                    after = self.done()
                    bar.update(min(after, goal) - min(before, goal))
                    if after // c.log_every > before // c.log_every:
                        self.log_row()
                        self.write_log()
                        bar.set_postfix(**self.postfix())
                    if after // c.checkpoint_every > before // c.checkpoint_every:
                        self.save()
                self.save()
            finally:
                bar.close()
            return not stop.is_set()


def owed_updates(credit: float, transitions: int, every: int) -> tuple[int, float]:
    """(updates, credit left) after ``transitions`` more environment transitions at one update
    every ``every`` of them (summed over the parallel envs; the fraction carries over)."""
    credit += transitions / every
    updates = int(credit)
    return updates, credit - updates


def write_command(out: Path, command: str | None) -> None:
    """The run folder's ``command.txt``: the command that trained it (none given: nothing)."""
    if command:
        with atomic_write(Path(out) / "command.txt") as f:
            f.write(command + "\n")
