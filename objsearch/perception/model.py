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

With ``decoder_stride=4`` the low-level features, the decoder and the heads run at H/4
instead: layer1 takes the stride 2 (layer2 keeps the resolution), the ASPP output is
upsampled x2, and the heads make 16 x (classes + 1) channels, pixel-shuffled x4. With
``separable`` too, inference of 64 x 64 frames in batches of 64 is 4.6-4.9x faster on one CPU
thread (``benchmarks/bench_perception.py --baseline --set decoder_stride=4 --set separable=true``).

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
    decoder_stride: int = 2
    """Resolution of the low-level skip, the decoder and the heads, as input size over it: 2
    (the shipped network) or 4. At 4, layer1 has the stride 2 instead of layer2 (the skip comes
    from H/4), the ASPP output is upsampled x2, the heads are pixel-shuffled x4 (16 channels per
    class), and the segmentation head runs one frame at a time, in ``forward`` and
    ``predict_labels`` alike, so that ``predict_labels`` takes a frame's argmax while its
    logits are in the cache. Checkpoints without the field (the shipped one) have 2."""

    def __post_init__(self):
        object.__setattr__(self, "aspp_rates", tuple(int(r) for r in self.aspp_rates))
        if not isinstance(self.separable, bool):
            raise UserError(f"model config field separable must be true or false, got {self.separable!r}")
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if f.name not in ("aspp_rates", "separable") and (not isinstance(value, int) or value < 1):
                raise UserError(f"model config field {f.name} must be a positive integer, got {value!r}")
        if self.decoder_stride not in (2, 4):
            raise UserError(f"model config field decoder_stride must be 2 or 4, got {self.decoder_stride!r}")
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

    H and W must be multiples of 8 (output stride 8). Segmentation channel
    ``c * r * r + r * i + j`` of the heads (``r = config.decoder_stride``) is class ``c`` at
    pixel ``(r * y + i, r * x + j)`` (pixel shuffle's layout).
    """

    def __init__(self, config: ModelConfig = ModelConfig()):
        super().__init__()
        c = self.config = config
        self.register_buffer("mean", torch.tensor([0.5, 0.5, 0.5]).view(1, 3, 1, 1), persistent=False)
        self.stem = _conv_bn(3, c.stem, 3, stride=2)
        sep, r = c.separable, c.decoder_stride
        self.layer1 = ResidualBlock(c.stem, c.stem, stride=r // 2, separable=sep)  # the skip: at H/r
        self.layer2 = ResidualBlock(c.stem, c.mid, stride=4 // r, separable=sep)  # H/4 either way
        self.layer3 = ResidualBlock(c.mid, c.deep, stride=2, separable=sep)
        self.layer4 = ResidualBlock(c.deep, c.deep, dilation=2, separable=sep)
        self.aspp = ASPP(c.deep, c.aspp, c.aspp_rates, separable=sep)
        self.skip = _conv_bn(c.stem, c.skip, 1)
        self.decoder = nn.Sequential(
            _conv_bn(c.aspp + c.skip, c.decoder, separable=sep), _conv_bn(c.decoder, c.decoder, separable=sep)
        )
        self.seg_head = nn.Conv2d(c.decoder, r * r * c.num_classes, 1)  # r * r: the pixels of pixel shuffle
        self.depth_head = nn.Conv2d(c.decoder, r * r, 1)
        nn.init.constant_(self.depth_head.bias, 1.0)  # exp(1) ~ 2.7 m: a typical indoor depth

    def forward(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Class logits (N, C, H, W) and log depth (N, H, W) of an RGB batch (N, 3, H, W) in [0, 1].

        Raises ValueError if H or W is not a multiple of 8.
        """
        y = self._decoded(x)
        r = self.config.decoder_stride
        parts = self._seg_logits(y)
        seg = parts[0] if len(parts) == 1 else torch.cat(parts)
        return F.pixel_shuffle(seg, r), F.pixel_shuffle(self.depth_head(y), r)[:, 0]

    def predict_labels(self, x: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """Category ids (N, H, W) int64 and log depth (N, H, W): ``forward`` with the argmax
        taken before the pixel shuffle, on the same logits, so the ids equal
        ``forward(x)[0].argmax(1)`` exactly (ties too: both take the first maximal class).
        Rearranging 69 channels of logits was a fifth of the inference time; rearranging the
        ids costs nothing."""
        y = self._decoded(x)
        r = self.config.decoder_stride
        labels = []
        for seg in self._seg_logits(y):  # the logits of forward, in the same parts
            n, _, h, w = seg.shape
            # pixel shuffle's channel layout: channel c * r * r + r * i + j is class c at pixel (r * y + i, r * x + j)
            ids = _first_argmax(seg.reshape(n, -1, r * r * h * w)).view(n, r, r, h, w)
            labels.append(ids.permute(0, 3, 1, 4, 2).reshape(n, r * h, r * w))
        labels = labels[0] if len(labels) == 1 else torch.cat(labels)
        return labels, F.pixel_shuffle(self.depth_head(y), r)[:, 0]

    def _seg_logits(self, y: torch.Tensor) -> list[torch.Tensor]:
        """The segmentation head's output (before the pixel shuffle) on the decoder's features
        ``y``, in parts along the batch: one for the whole batch, or (``decoder_stride`` 4)
        one per frame, so that a frame's logits (1.1 MB at 64 x 64) stay in the cache for
        ``predict_labels``' argmax. ``forward`` concatenates the same parts, so both see the
        same numbers bit for bit."""
        if self.config.decoder_stride == 2 or len(y) < 2:
            return [self.seg_head(y)]
        return [self.seg_head(y[i : i + 1]) for i in range(len(y))]

    def _decoded(self, x: torch.Tensor) -> torch.Tensor:
        """The decoder's features (N, decoder, H/r, W/r), ``r = config.decoder_stride``, which both heads read."""
        h, w = x.shape[-2:]
        if h % 8 or w % 8:
            raise ValueError(f"input size {h}x{w} must be a multiple of 8")
        low = self.layer1(self.stem(x - self.mean))
        deep = self.aspp(self.layer4(self.layer3(self.layer2(low))))
        deep = F.interpolate(deep, size=low.shape[-2:], mode="bilinear", align_corners=False)
        return self.decoder(torch.cat([deep, self.skip(low)], dim=1))


def _first_argmax(scores: torch.Tensor) -> torch.Tensor:
    """``scores.argmax(dim=1)`` (int64) of finite (N, C, P) scores, the first maximal class at
    a tie: ``C - max over classes of (C - c where score c is maximal, else 0)``. Three
    vectorised passes (the maximum, the comparison, a maximum over bytes) instead of torch's
    argmax over a middle dimension, which does not vectorise, or a running maximum over the C
    classes (this function before): on one thread 1.4x faster than the running maximum on a
    batch of 64 frames' 64 x 64 logits, 6x on one frame's (which stay in the cache)."""
    c = scores.shape[1]
    rank = torch.arange(c, 0, -1, dtype=torch.uint8 if c < 256 else torch.int32, device=scores.device)
    is_max = scores >= scores.amax(dim=1, keepdim=True)
    return c - (is_max.to(rank.dtype) * rank.view(1, c, 1)).amax(dim=1).long()


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
