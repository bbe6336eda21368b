"""The grid-world Q-networks of HRL-GRG (paper appendix A.1, as the authors' code builds them).

Every network shares one convolutional trunk on a 7x7 window:

    1x1 conv -> 1 channel (ReLU) -> 3x3 conv, 50, same (ReLU) -> 2x2 max-pool
    -> 3x3 conv, 100 (ReLU) -> 2x2 max-pool -> flatten (100)

followed by FC 100 (ReLU) and a linear output. The pools round up (``ceil_mode``, as
TensorFlow's "SAME" pooling), so the 7x7 window gives 4x4 -> 2x2 -> 1x1 and no border row
or column of the window is dropped (floor pooling would ignore the last row and column of
the 7x7 map; a valid 3x3 conv on the 3x3 map would leave nothing for the second pool).

* ``low_level_net`` / DQN: 2 channels (obstacles, goal or sub-goal) -> 4 Q-values.
* ``hdqn_high_net``: 1 + G channels, the one-hot goal concatenated after the trunk -> G + 1
  Q-values (the last is the back-up "random" sub-goal).
* ``grg_high_net``: 2 channels (obstacles, relation-weighted candidate) -> 1 Q-value.

Initialisation follows TensorFlow 1's layers (Glorot-uniform weights, zero biases), except
that the first 1x1 convolution starts with non-negative weights: its single output channel
goes through a ReLU, and with PyTorch's default init (negative bias) or a Glorot draw of two
negative weights it is zero on every input, a dead network that never learns (seen with
seed 0). Non-negative weights keep obstacles and goals visible to the rest of the trunk.
"""

from __future__ import annotations

import torch
from torch import nn

TRUNK_FEATURES = 100
HIDDEN = 100


class ConvTrunk(nn.Module):
    def __init__(self, in_channels: int):
        super().__init__()
        self.layers = nn.Sequential(
            nn.Conv2d(in_channels, 1, kernel_size=1),
            nn.ReLU(),
            nn.Conv2d(1, 50, kernel_size=3, padding=1),
            nn.ReLU(),
            nn.MaxPool2d(2, ceil_mode=True),
            nn.Conv2d(50, TRUNK_FEATURES, kernel_size=3),
            nn.ReLU(),
            nn.MaxPool2d(2, ceil_mode=True),
            nn.Flatten(),
        )

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        conv1, relu1, conv50, relu50, pool1, conv100, relu100, pool2, flatten = self.layers
        # CPU max-pooling is ~10x faster on channels-last tensors (same values); converting
        # before the ReLU keeps its backward in one memory format (same values, faster).
        h = relu50(conv50(relu1(conv1(x))).contiguous(memory_format=torch.channels_last))
        return flatten(pool2(relu100(conv100(pool1(h)))))


class QNet(nn.Module):
    """Trunk -> [concat extra input] -> FC 100 (ReLU) -> ``outputs`` Q-values."""

    def __init__(self, in_channels: int, outputs: int, extra_inputs: int = 0):
        super().__init__()
        self.trunk = ConvTrunk(in_channels)
        self.head = nn.Sequential(
            nn.Linear(TRUNK_FEATURES + extra_inputs, HIDDEN), nn.ReLU(), nn.Linear(HIDDEN, outputs)
        )
        self.extra_inputs = extra_inputs
        for module in self.modules():
            if isinstance(module, (nn.Conv2d, nn.Linear)):
                nn.init.xavier_uniform_(module.weight)
                nn.init.zeros_(module.bias)
        first = self.trunk.layers[0]
        with torch.no_grad():
            first.weight.abs_()

    def forward(self, image: torch.Tensor, extra: torch.Tensor | None = None) -> torch.Tensor:
        h = self.trunk(image)
        if self.extra_inputs:
            h = torch.cat([h, extra], dim=1)
        return self.head(h)


def low_level_net() -> QNet:
    return QNet(2, 4)


def hdqn_high_net(num_goals: int) -> QNet:
    return QNet(1 + num_goals, num_goals + 1, extra_inputs=num_goals)


def grg_high_net() -> QNet:
    return QNet(2, 1)
