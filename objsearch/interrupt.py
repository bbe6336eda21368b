"""Long runs that stop cleanly on Ctrl-C: finish the current step, checkpoint, exit 130."""

from __future__ import annotations

import contextlib
import signal
import threading


@contextlib.contextmanager
def stop_on_interrupt():
    """Yield an Event that is set by SIGINT (Ctrl-C) instead of raising KeyboardInterrupt,
    so a training loop can finish its step and write a checkpoint. Only the main thread can
    catch signals; elsewhere the event is never set. The previous handler is restored."""
    stop = threading.Event()
    previous = None
    if threading.current_thread() is threading.main_thread():
        previous = signal.signal(signal.SIGINT, lambda *_: stop.set())
    try:
        yield stop
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
