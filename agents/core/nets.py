"""What every network of both worlds uses: float32 tensors of numpy arrays, and building a
network with weights drawn from a seed."""

from __future__ import annotations

import numpy as np
import torch
from torch import nn


def as_tensor(x: np.ndarray) -> torch.Tensor:
    """float32 torch view of an array (copied only if not already contiguous float32)."""
    return torch.from_numpy(np.ascontiguousarray(x, dtype=np.float32))


def seeded_init(builder, seed: int, *args) -> nn.Module:
    """Build a network with weights drawn from ``seed`` without touching the global torch
    RNG state (it is forked and restored)."""
    with torch.random.fork_rng(devices=[]):
        torch.manual_seed(seed)
        return builder(*args)
