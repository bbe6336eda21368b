"""Running a trained network: checkpoints, the ``Predictor`` the house env's predicted mode
uses, and evaluation on a split of frames.

A checkpoint (``model.pt``) holds ``version``, ``model_config``, ``settings`` (the camera
of its training frames: ``RenderSettings.to_json()``), ``categories`` (the category table
version) and ``state_dict``. A predictor's ``key`` hashes all of it, weights included, so a
predicted observation cache never outlives the network that filled it.

In memory the camera is a ``RenderSettings`` (``Predictor.settings``); a network meets
frames of another camera only through ``objsearch.sim.camera.check_predictor_camera``.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import fields
from pathlib import Path

import numpy as np
import torch

from objsearch import torchfile
from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_TABLE_VERSION
from objsearch.perception.metrics import Evaluation
from objsearch.perception.model import (
    MODEL_VERSION,
    ModelConfig,
    SegDepthNet,
    depth_from_log,
    pick_device,
    rgb_to_tensor,
)
from objsearch.sim.camera import AGENT_CAMERA, AGENT_CAMERA_NAME, PERCEPTION_FIX, RenderSettings, check_camera

BATCH = 64
SHIPPED_CHECKPOINT = Path(__file__).with_name("checkpoint") / "model.pt"
"""The network shipped with the package (``objsearch/perception/checkpoint/README.md`` says how it was made)."""


def resolve_checkpoint(path: str | Path | None = None) -> Path:
    """``path``, or the shipped checkpoint when it is None."""
    if path is not None:
        return Path(path)
    if not SHIPPED_CHECKPOINT.is_file():
        raise UserError(
            f"no shipped perception checkpoint at {SHIPPED_CHECKPOINT}; pass one (objsearch perception train writes RUN/model.pt)"
        )
    return SHIPPED_CHECKPOINT


def _require_settings(settings) -> RenderSettings:
    if not isinstance(settings, RenderSettings):
        raise TypeError(
            f"settings must be a RenderSettings (objsearch.sim.camera), not {type(settings).__name__}; "
            "RenderSettings.from_json(d) reads a dict"
        )
    return settings


def save_checkpoint(path: str | Path, model: SegDepthNet, settings: RenderSettings) -> None:
    """Write the evaluable network atomically (weights on the CPU); ``settings``: the camera of its training frames."""
    state = {
        "version": MODEL_VERSION,
        "model_config": model.config.to_json(),
        "settings": _require_settings(settings).to_json(),
        "categories": CATEGORY_TABLE_VERSION,
        "state_dict": {k: v.detach().cpu() for k, v in model.state_dict().items()},
    }
    torchfile.save(path, state)


def load_checkpoint(path: str | Path) -> dict:
    """A checkpoint's contents, as stored (``settings`` a dict: ``checkpoint_settings`` reads it)."""
    state = torchfile.load(path, "a perception model.pt written by objsearch perception train")
    if not isinstance(state, dict) or state.get("version") != MODEL_VERSION:
        raise UserError(f"{path} is not a {MODEL_VERSION} checkpoint (objsearch perception train writes RUN/model.pt)")
    if state.get("categories") != CATEGORY_TABLE_VERSION:
        raise UserError(
            f"{path} was trained on category table {state.get('categories')}, this is {CATEGORY_TABLE_VERSION}; retrain"
        )
    return state


def checkpoint_settings(state: dict, path: str | Path) -> RenderSettings:
    """The camera of a loaded checkpoint's training frames."""
    settings, names = state.get("settings"), [f.name for f in fields(RenderSettings)]
    try:
        if not isinstance(settings, dict):
            raise ValueError(f"expected a dict, got {type(settings).__name__}")
        # Complete records only: from_json would fill a missing field with today's default,
        # which need not be the camera the network was trained on.
        missing = [name for name in names if name not in settings]
        if missing:
            raise ValueError(f"missing camera fields {', '.join(missing)}")
        return RenderSettings.from_json(settings, source=f"the settings of checkpoint {path}")
    except (UserError, TypeError, ValueError) as err:
        raise UserError(
            f"{path} records no readable camera settings ({err}); retrain it with objsearch perception train"
        ) from None


def check_checkpoint_camera(
    path: str | Path | None = None, expected: RenderSettings = AGENT_CAMERA, expected_name: str = AGENT_CAMERA_NAME
) -> RenderSettings:
    """Load the checkpoint ``path`` (default: the shipped one) and check that it was trained
    on frames of ``expected`` (``objsearch.sim.camera.check_camera``), without building the
    network: what a command runs before it renders anything.

    Raises:
        UserError: the file is not a readable checkpoint.
        CameraMismatchError: it was trained on another camera.
    """
    path = resolve_checkpoint(path)
    settings = checkpoint_settings(load_checkpoint(path), path)
    return check_camera(
        settings, expected, source=f"perception checkpoint {path}", expected_name=expected_name, fix=PERCEPTION_FIX
    )


def checkpoint_key(state: dict) -> str:
    """sha256 (16 hex digits) of a checkpoint's metadata and weights."""
    h = hashlib.sha256(
        json.dumps(
            {k: state[k] for k in ("version", "model_config", "settings", "categories")}, sort_keys=True
        ).encode()
    )
    for name, tensor in sorted(state["state_dict"].items()):
        h.update(name.encode())
        h.update(tensor.detach().cpu().contiguous().numpy().tobytes())
    return h.hexdigest()[:16]


class Predictor:
    """Segmentation and depth from RGB with a trained network (``objsearch.sim.cache.Predictor``).

    Args:
        model: the network (its weights are not changed; it is put in eval mode).
        settings: the camera (``RenderSettings``) of the frames it was trained on; depth is
            clamped to its [znear, zfar]. Whoever shows it frames checks that they come from
            this camera (``objsearch.sim.camera.check_predictor_camera``).
        key: identity of the network and weights (``checkpoint_key``).
        device: ``auto``, ``cpu``, ``cuda`` or a torch device.
        checkpoint: where it was loaded from (error messages name it), if anywhere.
    """

    def __init__(
        self, model: SegDepthNet, settings: RenderSettings, key: str, device="auto", checkpoint: str | None = None
    ):
        self.device = device if isinstance(device, torch.device) else pick_device(device)
        self.model = model.to(self.device).eval()
        self.settings, self.key = _require_settings(settings), key
        self.checkpoint = None if checkpoint is None else str(checkpoint)

    @classmethod
    def from_checkpoint(cls, path: str | Path | None = None, device="auto") -> "Predictor":
        """The network of ``path`` (default: the shipped checkpoint)."""
        path = resolve_checkpoint(path)
        state = load_checkpoint(path)
        model = SegDepthNet(
            ModelConfig.from_json(state["model_config"], source=f"the model_config of checkpoint {path}")
        )
        model.load_state_dict(state["state_dict"])
        return cls(model, checkpoint_settings(state, path), checkpoint_key(state), device, checkpoint=str(path))

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
            labels, log_depth = self.model.predict_labels(rgb_to_tensor(rgb[start : start + BATCH], self.device))
            stop = start + len(labels)
            semantic[start:stop] = labels.to(torch.uint8).cpu().numpy()
            depth[start:stop] = depth_from_log(log_depth, self.settings.znear, self.settings.zfar).cpu().numpy()
        return semantic, depth


def evaluate(predictor: Predictor, frames, zfar: float | None = None, progress: bool = False) -> dict:
    """Metrics (``objsearch.perception.metrics``) of the predictor on a ``FrameSet``."""
    from tqdm import tqdm

    evaluation = Evaluation(zfar if zfar is not None else predictor.settings.zfar)
    for start in tqdm(range(0, len(frames), BATCH), desc="eval", unit="batch", disable=not progress or None):
        sl = slice(start, start + BATCH)
        semantic, depth = predictor.predict(frames.rgb[sl])
        evaluation.update(frames.semantic[sl], semantic, frames.depth[sl], depth)
    return evaluation.result()
