"""Long runs that stop cleanly on Ctrl-C (SIGINT) and on SIGTERM, the signal Slurm,
Kubernetes, ``timeout`` and Ray stop jobs with: finish the current step, save what was done,
say what was saved and how to resume, exit 130 (SIGINT) or 143 (SIGTERM).

Two ways in: a training loop checks ``stop_on_interrupt``'s flag between steps and writes a
checkpoint; everything else runs under ``sigterm_as_interrupt`` (the CLI installs it), where
SIGTERM raises ``Terminated``, a ``KeyboardInterrupt``, so that every clean-up written for
Ctrl-C (partial results flushed, temp files and folders removed, worker processes stopped)
runs for SIGTERM as well.
"""

from __future__ import annotations

import contextlib
import signal
import threading

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
DEFERRED_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)  # what signals_deferred holds back


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised where Ctrl-C raises ``KeyboardInterrupt`` (see ``sigterm_as_interrupt``)."""


_stopped_by: int | None = None  # the signal that set a stop_on_interrupt flag in this process


def exit_status(signum: int | None) -> int:
    """The shell's status for a run stopped by ``signum``: 128 + its number (130 for
    SIGINT, 143 for SIGTERM); 130 when unknown."""
    return 128 + int(signum if signum is not None else signal.SIGINT)


def interrupt_status(err: KeyboardInterrupt) -> int:
    """The exit status for an interrupt raised as ``err``: 143 for ``Terminated``, else 130."""
    return exit_status(signal.SIGTERM if isinstance(err, Terminated) else signal.SIGINT)


def stop_status() -> int:
    """The exit status for a run whose ``stop_on_interrupt`` flag was set: 143 if SIGTERM
    set it, else 130."""
    return exit_status(_stopped_by)


def interrupted_line(status: int, saved: str = "") -> str:
    """The one line an interrupted command ends with: the signal, what was ``saved`` and how
    to resume (``saved`` says it), and the exit status."""
    how = "by SIGTERM" if status == exit_status(signal.SIGTERM) else "(Ctrl-C)"
    return f"interrupted {how}{f': {saved}' if saved else ''} (exit {status})"


def _raise_terminated(signum, frame) -> None:
    raise Terminated()


@contextlib.contextmanager
def sigterm_as_interrupt():
    """While the block runs in the main thread, SIGTERM raises ``Terminated`` (a
    ``KeyboardInterrupt``) instead of killing the process at once. The previous handler is
    restored. Elsewhere than in the main thread it does nothing."""
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


@contextlib.contextmanager
def stop_on_interrupt():
    """Yield an Event that SIGINT (Ctrl-C) and SIGTERM set instead of raising, so a training
    loop can finish its step and write a checkpoint; ``stop_status()`` is then the status to
    exit with. Only the main thread can catch signals; elsewhere the event is never set. The
    previous handlers are restored."""
    stop = threading.Event()

    def on_signal(signum, frame) -> None:
        global _stopped_by
        if not stop.is_set():
            _stopped_by = signum
        stop.set()

    previous = {}
    if threading.current_thread() is threading.main_thread():
        previous = {signum: signal.signal(signum, on_signal) for signum in STOP_SIGNALS}
    try:
        yield stop
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


@contextlib.contextmanager
def signals_deferred():
    """While the block runs in the main thread, SIGINT, SIGTERM and SIGHUP wait: one that
    arrives is recorded, and delivered (each once) when the block has ended and the previous
    handlers are back, so that renames that belong together (``leaderboard add``'s entries and
    pages) all happen before the process stops. Keep the block short: Ctrl-C waits for it.
    Elsewhere than in the main thread it does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    pending: list[int] = []
    previous = {
        signum: signal.signal(signum, lambda signum, frame: pending.append(signum)) for signum in DEFERRED_SIGNALS
    }
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, signal.SIG_DFL if handler is None else handler)
        for signum in dict.fromkeys(pending):
            signal.raise_signal(signum)
