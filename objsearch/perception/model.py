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
    separable: bool = False
    """Every 3x3 convolution after the stem as a depthwise-separable one (depthwise 3x3, batch
    norm, 1x1), as DeepLabv3+'s Xception does: about a fifth of the multiply-adds. Checkpoints
    without the field (the shipped one) are plain convolutions."""

    def __post_init__(self):
        object.__setattr__(self, "aspp_rates", tuple(int(r) for r in self.aspp_rates))
        if not isinstance(self.separable, bool):
            raise UserError(f"model config field separable must be true or false, got {self.separable!r}")
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.name not in ("aspp_rates", "separable") and (not isinstance(value, int) or value < 1):
                raise UserError(f"model config field {f.name} must be a positive integer, got {value!r}")
        if self.num_classes != NUM_CLASSES:
            raise UserError(f"num_classes={self.num_classes} does not match the category table ({NUM_CLASSES} ids)")


def _conv(cin: int, cout: int, k: int, stride: int = 1, dilation: int = 1, separable: bool = False) -> nn.Module:
    """A k x k convolution without bias, or (``separable``, k > 1) a depthwise k x k one, batch
    norm and a 1x1 one."""
    pad = dilation * (k - 1) // 2
    if not separable or k == 1:
        return nn.Conv2d(cin, cout, k, stride, pad, dilation=dilation, bias=False)
    return nn.Sequential(
        nn.Conv2d(cin, cin, k, stride, pad, dilation=dilation, groups=cin, bias=False),
        nn.BatchNorm2d(cin),
        nn.Conv2d(cin, cout, 1, bias=False),
    )


def _conv_bn(
    cin: int, cout: int, k: int = 3, stride: int = 1, dilation: int = 1, separable: bool = False
) -> nn.Sequential:
    return nn.Sequential(_conv(cin, cout, k, stride, dilation, separable), nn.BatchNorm2d(cout), nn.ReLU(inplace=True))


class ResidualBlock(nn.Module):
    """Two 3x3 convolutions with a shortcut (1x1 projection when the shape changes)."""

    def __init__(self, cin: int, cout: int, stride: int = 1, dilation: int = 1, separable: bool = False):
        super().__init__()
        self.conv1 = _conv(cin, cout, 3, stride, dilation, separable)
        self.bn1 = nn.BatchNorm2d(cout)
        self.conv2 = _conv(cout, cout, 3, 1, dilation, separable)
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

    def __init__(self, cin: int, cout: int, rates: tuple[int, ...], separable: bool = False):
        super().__init__()
        self.branches = nn.ModuleList(
            [_conv_bn(cin, cout, 1)] + [_conv_bn(cin, cout, 3, dilation=r, separable=separable) for r in rates]
        )
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
        sep = c.separable
        self.layer1 = ResidualBlock(c.stem, c.stem, separable=sep)
        self.layer2 = ResidualBlock(c.stem, c.mid, stride=2, separable=sep)
        self.layer3 = ResidualBlock(c.mid, c.deep, stride=2, separable=sep)
        self.layer4 = ResidualBlock(c.deep, c.deep, dilation=2, separable=sep)
        self.aspp = ASPP(c.deep, c.aspp, c.aspp_rates, separable=sep)
        self.skip = _conv_bn(c.stem, c.skip, 1)
        self.decoder = nn.Sequential(
            _conv_bn(c.aspp + c.skip, c.decoder, separable=sep), _conv_bn(c.decoder, c.decoder, separable=sep)
        )
        self.seg_head = nn.Conv2d(c.decoder, 4 * c.num_classes, 1)  # 4 = the 2 x 2 pixels of pixel shuffle
        self.depth_head = nn.Conv2d(c.decoder, 4, 1)
        nn.init.constant_(self.depth_head.bias, 1.0)  # exp(1) ~ 2.7 m: a typical indoor depth

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Class logits (N, C, H, W) and log depth (N, H, W) of an RGB batch (N, 3, H, W) in [0, 1].

        Raises ValueError if H or W is not a multiple of 8.
        """
        y = self._decoded(x)
        return F.pixel_shuffle(self.seg_head(y), 2), F.pixel_shuffle(self.depth_head(y), 2)[:, 0]

    def predict_labels(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Category ids (N, H, W) int64 and log depth (N, H, W): ``forward`` with the argmax
        taken before the pixel shuffle, on the same logits, so the ids equal
        ``forward(x)[0].argmax(1)`` exactly (ties too: both take the first maximal class).
        Rearranging 69 channels of logits was a fifth of the inference time; rearranging the
        ids costs nothing."""
        y = self._decoded(x)
        seg = self.seg_head(y)
        n, _, h, w = seg.shape
        # pixel shuffle's channel layout: channel c * 4 + 2 * i + j is class c at pixel (2y + i, 2x + j)
        labels = _first_argmax(seg.view(n, -1, 4 * h * w)).view(n, 2, 2, h, w)
        return labels.permute(0, 3, 1, 4, 2).reshape(n, 2 * h, 2 * w), F.pixel_shuffle(self.depth_head(y), 2)[:, 0]

    def _decoded(self, x: torch.Tensor) -> torch.Tensor:
        """The decoder's features (N, decoder, H/2, W/2), which both heads read."""
        h, w = x.shape[-2:]
        if h % 8 or w % 8:
            raise ValueError(f"input size {h}x{w} must be a multiple of 8")
        low = self.layer1(self.stem(x - self.mean))
        deep = self.aspp(self.layer4(self.layer3(self.layer2(low))))
        deep = F.interpolate(deep, size=low.shape[-2:], mode="bilinear", align_corners=False)
        return self.decoder(torch.cat([deep, self.skip(low)], dim=1))


def _first_argmax(scores: torch.Tensor) -> torch.Tensor:
    """``scores.argmax(dim=1)`` of finite (N, C, P) scores (the first maximal class at a tie),
    as a running maximum over the C classes: on these shapes 1.7x faster than torch's
    reduction over a middle dimension."""
    best, labels = scores[:, 0].clone(), scores.new_zeros((scores.shape[0], scores.shape[2]), dtype=torch.long)
    for c in range(1, scores.shape[1]):
        better = scores[:, c] > best
        best = torch.where(better, scores[:, c], best)
        labels[better] = c
    return labels


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
