"""A DeepLabv3+-style encoder-decoder sized for a 2-core CPU: RGB in, segmentation and depth out.

Layout (input H x W, default 64 x 64; channel widths from ``ModelConfig``)::

    stem     conv3x3 s2                        H/2   (low-level features: the decoder's skip)
    layer1   residual block                    H/2
    layer2   residual block s2                 H/4
    layer3   residual block s2                 H/8   (output stride 8)
    layer4   residual block, dilation 2        H/8
    ASPP     1x1 + 3x3 at rates (2, 4, 6) + image pooling, concatenated, 1x1 projection
    decoder  upsample x4, concat 1x1-projected layer1 features, two 3x3 convs   H/2
    heads    1x1 conv to 4 x (classes + 1) channels at H/2, rearranged by pixel shuffle into
             full-resolution segmentation logits (one channel per category id) and log
             depth (a learned x2 upsampling: cheaper to train than bilinear upsampling of 69
             channels, and sharper for objects a few pixels wide)

Channel ``i`` of the segmentation logits is category id ``i`` of
``objsearch.house.categories.CATEGORY_IDS`` (background 0, structure classes, objects from
``FIRST_OBJECT_ID``); ids that the table reserves but does not use keep a channel that
training never targets. The depth head predicts log metres; ``depth_from_log`` turns it
into metres clamped to the camera's range.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import torch
import torch.nn.functional as F
from torch import nn

from objsearch.configs import JsonConfig
from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_IDS

#: One segmentation channel per category id, 0..max id (structure classes and background included).
NUM_CLASSES = max(CATEGORY_IDS.values()) + 1
MODEL_VERSION = "seg-depth-v1"


@dataclass(frozen=True)
class ModelConfig(JsonConfig):
    """Widths of the network. Stored in every checkpoint (``objsearch.configs.JsonConfig``)."""

    DESCRIPTION = "a perception model config"
    LEGACY_KEYS = {}  # no field has been renamed or removed since the shipped checkpoint

    stem: int = 32
    """Channels of the stem and layer1 (stride 2)."""
    mid: int = 64
    """Channels of layer2 (stride 4)."""
    deep: int = 128
    """Channels of layer3 and layer4 (stride 8)."""
    aspp: int = 96
    """Channels of each ASPP branch and of its projection."""
    aspp_rates: tuple[int, ...] = (2, 4, 6)
    """Dilation rates of the ASPP 3x3 branches (at output stride 8)."""
    skip: int = 32
    """Channels the low-level (stride 2) features are projected to before the decoder."""
    decoder: int = 64
    """Channels of the decoder's 3x3 convolutions."""
    num_classes: int = NUM_CLASSES
    """Segmentation channels: one per category id."""

    def __post_init__(self):
        object.__setattr__(self, "aspp_rates", tuple(int(r) for r in self.aspp_rates))
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.name != "aspp_rates" and (not isinstance(value, int) or value < 1):
                raise UserError(f"model config field {f.name} must be a positive integer, got {value!r}")
        if self.num_classes != NUM_CLASSES:
            raise UserError(f"num_classes={self.num_classes} does not match the category table ({NUM_CLASSES} ids)")


def _conv_bn(cin: int, cout: int, k: int = 3, stride: int = 1, dilation: int = 1) -> nn.Sequential:
    pad = dilation * (k - 1) // 2
    return nn.Sequential(
        nn.Conv2d(cin, cout, k, stride, pad, dilation=dilation, bias=False), nn.BatchNorm2d(cout), nn.ReLU(inplace=True)
    )


class ResidualBlock(nn.Module):
    """Two 3x3 convolutions with a shortcut (1x1 projection when the shape changes)."""

    def __init__(self, cin: int, cout: int, stride: int = 1, dilation: int = 1):
        super().__init__()
        self.conv1 = nn.Conv2d(cin, cout, 3, stride, dilation, dilation=dilation, bias=False)
        self.bn1 = nn.BatchNorm2d(cout)
        self.conv2 = nn.Conv2d(cout, cout, 3, 1, dilation, dilation=dilation, bias=False)
        self.bn2 = nn.BatchNorm2d(cout)
        self.shortcut = nn.Identity()
        if stride != 1 or cin != cout:
            self.shortcut = nn.Sequential(nn.Conv2d(cin, cout, 1, stride, bias=False), nn.BatchNorm2d(cout))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """relu(conv-bn-relu-conv-bn(x) + shortcut(x))."""
        y = F.relu(self.bn1(self.conv1(x)), inplace=True)
        return F.relu(self.bn2(self.conv2(y)) + self.shortcut(x), inplace=True)


class ASPP(nn.Module):
    """Atrous spatial pyramid pooling: parallel 1x1, dilated 3x3 and image-pooling branches."""

    def __init__(self, cin: int, cout: int, rates: tuple[int, ...]):
        super().__init__()
        self.branches = nn.ModuleList([_conv_bn(cin, cout, 1)] + [_conv_bn(cin, cout, 3, dilation=r) for r in rates])
        self.pool = nn.Sequential(nn.AdaptiveAvgPool2d(1), nn.Conv2d(cin, cout, 1, bias=False), nn.ReLU(inplace=True))
        self.project = _conv_bn(cout * (len(rates) + 2), cout, 1)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """The concatenated atrous branches and image pooling of ``x``, projected."""
        outs = [branch(x) for branch in self.branches]
        outs.append(self.pool(x).expand(-1, -1, x.shape[2], x.shape[3]))
        return self.project(torch.cat(outs, dim=1))


class SegDepthNet(nn.Module):
    """RGB (N, 3, H, W) float in [0, 1] -> (logits (N, C, H, W), log depth (N, H, W)).

    H and W must be multiples of 8 (output stride 8).
    """

    def __init__(self, config: ModelConfig = ModelConfig()):
        super().__init__()
        c = self.config = config
        self.register_buffer("mean", torch.tensor([0.5, 0.5, 0.5]).view(1, 3, 1, 1), persistent=False)
        self.stem = _conv_bn(3, c.stem, 3, stride=2)
        self.layer1 = ResidualBlock(c.stem, c.stem)
        self.layer2 = ResidualBlock(c.stem, c.mid, stride=2)
        self.layer3 = ResidualBlock(c.mid, c.deep, stride=2)
        self.layer4 = ResidualBlock(c.deep, c.deep, dilation=2)
        self.aspp = ASPP(c.deep, c.aspp, c.aspp_rates)
        self.skip = _conv_bn(c.stem, c.skip, 1)
        self.decoder = nn.Sequential(_conv_bn(c.aspp + c.skip, c.decoder), _conv_bn(c.decoder, c.decoder))
        self.seg_head = nn.Conv2d(c.decoder, 4 * c.num_classes, 1)  # 4 = the 2 x 2 pixels of pixel shuffle
        self.depth_head = nn.Conv2d(c.decoder, 4, 1)
        nn.init.constant_(self.depth_head.bias, 1.0)  # exp(1) ~ 2.7 m: a typical indoor depth

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Class logits (N, C, H, W) and log depth (N, H, W) of an RGB batch (N, 3, H, W) in [0, 1].

        Raises ValueError if H or W is not a multiple of 8.
        """
        h, w = x.shape[-2:]
        if h % 8 or w % 8:
            raise ValueError(f"input size {h}x{w} must be a multiple of 8")
        low = self.layer1(self.stem(x - self.mean))
        deep = self.aspp(self.layer4(self.layer3(self.layer2(low))))
        deep = F.interpolate(deep, size=low.shape[-2:], mode="bilinear", align_corners=False)
        y = self.decoder(torch.cat([deep, self.skip(low)], dim=1))
        logits = F.pixel_shuffle(self.seg_head(y), 2)
        log_depth = F.pixel_shuffle(self.depth_head(y), 2)[:, 0]
        return logits, log_depth


def rgb_to_tensor(rgb, device: torch.device | str = "cpu") -> torch.Tensor:
    """uint8 (N, H, W, 3) numpy or tensor -> float (N, 3, H, W) in [0, 1] on ``device``."""
    t = (
        rgb if isinstance(rgb, torch.Tensor) else torch.from_numpy(np.array(rgb, dtype=np.uint8))
    )  # a copy: memmaps are read-only
    t = t.to(device)
    return t.permute(0, 3, 1, 2).float().div_(255.0)


def depth_from_log(log_depth: torch.Tensor, znear: float, zfar: float) -> torch.Tensor:
    """Metres from the depth head's log depth, clamped to [znear, zfar]."""
    return log_depth.clamp(min=float(torch.log(torch.tensor(znear))), max=float(torch.log(torch.tensor(zfar)))).exp()


def pick_device(name: str = "auto") -> torch.device:
    """``auto``: the GPU when one is present, else the CPU; or a torch device name."""
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    try:
        return torch.device(name)
    except RuntimeError as err:
        raise UserError(f"unknown device {name!r} ({err}); use auto, cpu or cuda") from None


def count_parameters(model: nn.Module) -> int:
    """Number of parameters (elements) of ``model``."""
    return sum(p.numel() for p in model.parameters())
