"""Progress of long work: a tqdm bar on a terminal, and in a log (nohup, CI, Slurm: stderr
is not a terminal) one plain line about every 30 seconds, e.g.
``random on gridworld: 600/1500 ep, 41.2 ep/s, ETA 00:21``."""

from __future__ import annotations

import sys

from tqdm import tqdm

LOG_INTERVAL_S = 30.0


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
