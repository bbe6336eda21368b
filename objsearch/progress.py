"""Progress of long work: a tqdm bar on a terminal, and in a log (nohup, CI, Slurm: stderr
is not a terminal) one plain line about every 30 seconds, e.g.
``random on gridworld: 600/1500 ep, 41.2 ep/s, ETA 00:21``. Work with no count to show says
it is under way when it takes longer than a moment (``stage``)."""

from __future__ import annotations

import contextlib
import sys
import threading
import time

from tqdm import tqdm

LOG_INTERVAL_S = 30.0
STAGE_DELAY_S = 5.0  # quicker work says nothing: a quick error stays one line


class _Lines:
    """A file for tqdm that writes each status it draws as one line (tqdm redraws its status
    in place with carriage returns, which a log keeps as one endless line)."""

    def __init__(self, stream):
        self.stream = stream

    def write(self, text: str) -> None:
        line = text.replace("\r", "").rstrip()
        if line:
            self.stream.write(line + "\n")

    def flush(self) -> None:
        self.stream.flush()


def progress_bar(total: int, desc: str, unit: str, enabled: bool = True, initial: int = 0, **options) -> tqdm:
    """A tqdm bar over ``total`` ``unit``s on stderr (``options`` go to tqdm). Where stderr is
    not a terminal, a line at the start, about every ``LOG_INTERVAL_S`` seconds and at the end:
    done / total, rate and ETA. ``enabled`` False: nothing (``--quiet``)."""
    stream = sys.stderr
    if not enabled:
        return tqdm(total=total, initial=initial, disable=True)
    if stream.isatty():
        return tqdm(total=total, initial=initial, desc=desc, unit=unit, file=stream, **options)
    options.pop("smoothing", None)
    return tqdm(
        total=total,
        initial=initial,
        desc=desc,
        unit=unit,
        file=_Lines(stream),
        mininterval=LOG_INTERVAL_S,
        maxinterval=LOG_INTERVAL_S * 10,
        smoothing=0,  # the rate over the whole run: a steadier ETA than the last interval's
        bar_format="{desc}: {n_fmt}/{total_fmt} {unit}, {rate_fmt}, ETA {remaining}",
        disable=False,
        **options,
    )


@contextlib.contextmanager
def stage(what: str, delay: float | None = None):
    """Say on stderr that ``what`` is under way once it has taken ``delay`` seconds (None:
    ``STAGE_DELAY_S``) and then every ``LOG_INTERVAL_S``, and when it is done how long it took;
    work done sooner says nothing."""
    stream, start, said = sys.stderr, time.monotonic(), threading.Event()
    stop = threading.Event()

    def say() -> None:
        wait = STAGE_DELAY_S if delay is None else delay
        while not stop.wait(wait):
            took = time.monotonic() - start
            stream.write(f"{what} ... ({took:.0f} s)\n" if said.is_set() else f"{what} ...\n")
            stream.flush()
            said.set()
            wait = LOG_INTERVAL_S

    thread = threading.Thread(target=say, daemon=True)
    thread.start()
    ok = False
    try:
        yield
        ok = True
    finally:
        stop.set()
        thread.join()
        if ok and said.is_set():
            stream.write(f"{what}: done in {time.monotonic() - start:.0f} s\n")
            stream.flush()
