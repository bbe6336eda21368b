"""What the stages of every generator version share: the seed's split and size class, the
house id, the wall dimensions, and ``StageFailure``.

A generator's ``build_spec(seed, size_class, split, attempt)`` (``objsearch.house.generators``)
draws its stages from ``numpy.random.default_rng([seed, attempt, SPLITS[split], ...])``; the
size class is drawn once per seed (``size_class_for``) so that resampling keeps it. These
values are part of every generator's output: changing one changes the houses of every version.
"""

from __future__ import annotations

import numpy as np

#: The generator splits (a split's index seeds its houses); ``test`` houses use the test mesh variants.
SPLITS = {"train": 0, "test": 1}
#: Size classes: the number of rooms (both generators) and, for ``house-gen-1``, the side of the footprint.
SIZE_CLASSES = {
    "small": {"side": (6.0, 9.0), "rooms": (3, 4)},
    "medium": {"side": (8.0, 12.0), "rooms": (4, 6)},
    "large": {"side": (11.0, 16.0), "rooms": (6, 9)},
}
#: Size classes of ``house-gen-3`` (its size knob): ``rooms-N`` is exactly N rooms (4-14), ``xlarge``
#: 9-14 rooms drawn per house. Apart from ``SIZE_CLASSES``, whose draw (``size_class_for``) they leave alone.
ROOM_COUNT_CLASSES = {**{f"rooms-{n}": (n, n) for n in range(4, 15)}, "xlarge": (9, 14)}
SIZE_STREAM = 7919
WALL_HEIGHT = 2.7
WALL_THICKNESS = 0.12


class StageFailure(Exception):
    """A stage could not satisfy its rules with this rng; the house is resampled."""


def house_id(seed: int, split: str = "train") -> str:
    """The id of the house of ``seed`` in ``split``: ``train_000042``."""
    return f"{split}_{seed:06d}"


def size_class_for(seed: int) -> str:
    """The size class drawn for ``seed`` when none is given."""
    names = sorted(SIZE_CLASSES)
    return names[int(np.random.default_rng([seed, SIZE_STREAM]).integers(len(names)))]
