"""The loop every trainer runs (grid world, houses, Scene Priors): step until the goal,
append a ``log.csv`` row every ``log_every`` and write a resumable checkpoint every
``checkpoint_every`` (both counted in the trainer's own unit: episodes or env steps), and on
Ctrl-C or SIGTERM finish the current step, write a checkpoint and return False.

A trainer subclasses ``TrainingLoop`` and provides ``step``, ``log_row``, ``write_log`` and
``save``, a ``config`` with ``log_every`` and ``checkpoint_every``, and the few hooks below.
"""

from __future__ import annotations

import time


class TrainingLoop:
    """``run()``: the loop, shared. Subclasses say what they count and what the bar shows."""

    unit = "step"
    """What ``done()`` counts, for the progress bar: ``ep`` or ``step``."""

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
