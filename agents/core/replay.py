"""A fixed-size replay memory of named numpy arrays (a ring buffer), sampled with an
explicit Generator. Its state (arrays, position, size) is saved for exact resume."""

from __future__ import annotations

import numpy as np


class ReplayBuffer:
    """Ring buffer of transitions; ``fields`` maps a name to (shape, dtype)."""

    def __init__(self, capacity: int, fields: dict[str, tuple[tuple[int, ...], type]]):
        self.capacity = int(capacity)
        self.data = {name: np.zeros((self.capacity, *shape), dtype=dtype) for name, (shape, dtype) in fields.items()}
        self.pos = 0
        self.size = 0

    def __len__(self) -> int:
        return self.size

    def add(self, **batch: np.ndarray) -> None:
        """Append a batch of transitions (every field with the same leading length)."""
        count = len(next(iter(batch.values())))
        if count == 0:
            return
        idx = (self.pos + np.arange(count)) % self.capacity
        for name, values in batch.items():
            self.data[name][idx] = values
        self.pos = int((self.pos + count) % self.capacity)
        self.size = int(min(self.size + count, self.capacity))

    def sample(self, batch_size: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
        idx = rng.integers(self.size, size=batch_size)
        return {name: values[idx] for name, values in self.data.items()}

    def state_dict(self) -> dict:
        return {"data": {k: v[: self.size].copy() for k, v in self.data.items()}, "pos": self.pos, "size": self.size}

    def load_state_dict(self, state: dict) -> None:
        self.pos, self.size = int(state["pos"]), int(state["size"])
        for k, v in state["data"].items():
            self.data[k][: self.size] = v
