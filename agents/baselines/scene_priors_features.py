"""Scene Priors' visual input (``agents/baselines/scene_priors.py``, substitute 2 of ``docs/scene_priors.md``):
ImageNet ResNet-50 features become the frozen encoder of the shipped perception network (stem
to ASPP, average-pooled to 2x2: 384 values a frame), ImageNet's 1000 class scores its mean
per-pixel softmax over the 69 category ids. Both come from RGB only, so gt and predicted
observations give the agent the same input. Computed once per pose per house, beside the
observation cache (``FeatureTables``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F

from objsearch.fileio import atomic_write
from objsearch.sim.camera import AGENT_CAMERA

FEATURE_GRID = 2  # the encoder's 8x8 output average-pooled to 2x2
TABLE_VERSION = "scene-priors-features-v1"


def feature_network(checkpoint: str | None = None):
    """The frozen perception network (``objsearch.perception``; default: the shipped one), on the CPU."""
    from objsearch.perception.inference import Predictor
    from objsearch.sim.camera import check_predictor_camera

    predictor = Predictor.from_checkpoint(checkpoint, device="cpu")
    check_predictor_camera(predictor, AGENT_CAMERA)
    return predictor


@torch.no_grad()
def frame_features(model, rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """uint8 (N, H, W, 3) -> (features float32 (N, F), class scores float32 (N, C)).

    Features: the encoder's output (stem ... layer4, ASPP; what DeepLabv3+ calls the
    encoder) average-pooled to ``FEATURE_GRID`` x ``FEATURE_GRID``. Scores: the per-pixel
    softmax over the category ids, averaged over the frame (the share of the frame the
    network gives each category)."""
    from objsearch.perception.model import rgb_to_tensor

    x = rgb_to_tensor(rgb)
    low = model.layer1(model.stem(x - model.mean))
    deep = model.aspp(model.layer4(model.layer3(model.layer2(low))))
    features = F.adaptive_avg_pool2d(deep, FEATURE_GRID).flatten(1)
    up = F.interpolate(deep, size=low.shape[-2:], mode="bilinear", align_corners=False)
    decoded = model.decoder(torch.cat([up, model.skip(low)], dim=1))
    logits = model.seg_head(decoded)  # (N, C * r * r, h, w): pixel shuffle's layout, class-major
    n, classes = len(x), model.config.num_classes
    scores = torch.softmax(logits.reshape(n, classes, -1), dim=1).mean(dim=2)
    return features.numpy().astype(np.float32), scores.numpy().astype(np.float32)


@dataclass(frozen=True, eq=False)
class FeatureTables:
    """``features`` (P, F) and ``scores`` (P, C) of every pose of one or more houses."""

    features: np.ndarray
    scores: np.ndarray

    @classmethod
    def of_cache(cls, cache, predictor, progress: bool = False) -> "FeatureTables":
        """The tables of one house's ``HouseCache`` (its RGB), stored in its folder as
        ``scene-priors-<network key>.npz``: the folder is keyed by the house and camera, the
        file by the network, and it holds ``TABLE_VERSION`` and the pose count, so a table
        never outlives what made it."""
        from tqdm import tqdm

        path = Path(cache.directory) / f"scene-priors-{predictor.key}.npz"
        n = len(cache.semantic)
        try:
            with np.load(path, allow_pickle=False) as data:
                if str(data["version"]) == TABLE_VERSION and len(data["features"]) == n:
                    return cls(data["features"], data["scores"])
        except (OSError, ValueError, KeyError):
            pass
        torch.set_num_threads(1)
        feats, scores = [], []
        for start in tqdm(range(0, n, 64), desc=f"scene features {Path(cache.directory).name}", disable=not progress):
            f, s = frame_features(predictor.model, np.asarray(cache.rgb[start : start + 64]))
            feats.append(f)
            scores.append(s)
        tables = cls(np.concatenate(feats), np.concatenate(scores))
        with atomic_write(path, "wb") as f:
            np.savez(f, version=np.array(TABLE_VERSION), features=tables.features, scores=tables.scores)
        return tables

    @classmethod
    def of_houses(cls, houses, predictor, cache_dir=None, progress: bool = False) -> "FeatureTables":
        """The tables of a ``TrainingHouses``, in its global pose ids."""
        from objsearch.sim.cache import HouseCache

        parts = [
            cls.of_cache(HouseCache.open(w, AGENT_CAMERA, cache_dir, progress), predictor, progress)
            for w in houses.worlds
        ]
        tables = cls(np.concatenate([t.features for t in parts]), np.concatenate([t.scores for t in parts]))
        if len(tables.features) != houses.tables.num_poses:
            raise RuntimeError("scene-priors tables do not cover the training houses' poses")
        return tables
