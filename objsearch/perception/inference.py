"""Running a trained network: checkpoints, the ``Predictor`` the house env's predicted mode
uses, and evaluation on a split of frames.

A checkpoint (``model.pt``) holds ``version``, ``model_config``, ``settings`` (the render
settings of its training frames), ``categories`` (the category table version) and
``state_dict``. A predictor's ``key`` hashes all of it, weights included, so a predicted
observation cache never outlives the network that filled it.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import torch

from objsearch import torchfile
from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_TABLE_VERSION
from objsearch.perception.metrics import Evaluation
from objsearch.perception.model import MODEL_VERSION, ModelConfig, SegDepthNet, depth_from_log, pick_device, rgb_to_tensor

BATCH = 64
SHIPPED_CHECKPOINT = Path(__file__).with_name("checkpoint") / "model.pt"
"""The network shipped with the package (``objsearch/perception/checkpoint/README.md`` says how it was made)."""


def resolve_checkpoint(path: str | Path | None = None) -> Path:
    """``path``, or the shipped checkpoint when it is None."""
    if path is not None:
        return Path(path)
    if not SHIPPED_CHECKPOINT.is_file():
        raise UserError(f"no shipped perception checkpoint at {SHIPPED_CHECKPOINT}; pass one (objsearch perception train writes RUN/model.pt)")
    return SHIPPED_CHECKPOINT


def save_checkpoint(path: str | Path, model: SegDepthNet, settings: dict) -> None:
    """Write the evaluable network atomically (weights on the CPU)."""
    state = {"version": MODEL_VERSION, "model_config": model.config.to_json(), "settings": dict(settings),
             "categories": CATEGORY_TABLE_VERSION,
             "state_dict": {k: v.detach().cpu() for k, v in model.state_dict().items()}}
    torchfile.save(path, state)


def load_checkpoint(path: str | Path) -> dict:
    state = torchfile.load(path, "a perception model.pt written by objsearch perception train")
    if not isinstance(state, dict) or state.get("version") != MODEL_VERSION:
        raise UserError(f"{path} is not a {MODEL_VERSION} checkpoint (objsearch perception train writes RUN/model.pt)")
    if state.get("categories") != CATEGORY_TABLE_VERSION:
        raise UserError(f"{path} was trained on category table {state.get('categories')}, this is {CATEGORY_TABLE_VERSION}; retrain")
    return state


def checkpoint_key(state: dict) -> str:
    """sha256 (16 hex digits) of a checkpoint's metadata and weights."""
    h = hashlib.sha256(json.dumps({k: state[k] for k in ("version", "model_config", "settings", "categories")},
                                  sort_keys=True).encode())
    for name, tensor in sorted(state["state_dict"].items()):
        h.update(name.encode())
        h.update(tensor.detach().cpu().contiguous().numpy().tobytes())
    return h.hexdigest()[:16]


class Predictor:
    """Segmentation and depth from RGB with a trained network (``objsearch.sim.cache.Predictor``).

    Args:
        model: the network (its weights are not changed; it is put in eval mode).
        settings: render settings (dict) of the frames it was trained on; depth is clamped
            to their [znear, zfar].
        key: identity of the network and weights (``checkpoint_key``).
        device: ``auto``, ``cpu``, ``cuda`` or a torch device.
    """

    def __init__(self, model: SegDepthNet, settings: dict, key: str, device="auto"):
        self.device = device if isinstance(device, torch.device) else pick_device(device)
        self.model = model.to(self.device).eval()
        self.settings, self.key = dict(settings), key

    @classmethod
    def from_checkpoint(cls, path: str | Path | None = None, device="auto") -> "Predictor":
        """The network of ``path`` (default: the shipped checkpoint)."""
        state = load_checkpoint(resolve_checkpoint(path))
        model = SegDepthNet(ModelConfig.from_json(state["model_config"]))
        model.load_state_dict(state["state_dict"])
        return cls(model, state["settings"], checkpoint_key(state), device)

    @torch.no_grad()
    def predict(self, rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """uint8 (N, H, W, 3) -> (semantic uint8 (N, H, W) category ids, depth float32 (N, H, W) metres).

        Frames are run in batches of 64 (eval mode: no frame influences another). The
        CPU kernels may round differently for another batch size or memory layout, so a
        frame predicted alone can differ from the same frame in a batch by a float ulp
        (depth by 1 mm after rounding, a rare label flip at a near tie).
        """
        rgb = np.asarray(rgb)
        if rgb.ndim != 4 or rgb.shape[-1] != 3 or rgb.dtype != np.uint8:
            raise ValueError(f"expected uint8 RGB frames of shape (N, H, W, 3), got {rgb.dtype} {rgb.shape}")
        semantic = np.empty(rgb.shape[:3], np.uint8)
        depth = np.empty(rgb.shape[:3], np.float32)
        for start in range(0, len(rgb), BATCH):
            logits, log_depth = self.model(rgb_to_tensor(rgb[start : start + BATCH], self.device))
            stop = start + len(logits)
            semantic[start:stop] = logits.argmax(dim=1).to(torch.uint8).cpu().numpy()
            depth[start:stop] = depth_from_log(log_depth, self.settings["znear"], self.settings["zfar"]).cpu().numpy()
        return semantic, depth


def evaluate(predictor: Predictor, frames, zfar: float | None = None, progress: bool = False) -> dict:
    """Metrics (``objsearch.perception.metrics``) of the predictor on a ``FrameSet``."""
    from tqdm import tqdm

    evaluation = Evaluation(zfar if zfar is not None else predictor.settings["zfar"])
    for start in tqdm(range(0, len(frames), BATCH), desc="eval", unit="batch", disable=not progress or None):
        sl = slice(start, start + BATCH)
        semantic, depth = predictor.predict(frames.rgb[sl])
        evaluation.update(frames.semantic[sl], semantic, frames.depth[sl], depth)
    return evaluation.result()
