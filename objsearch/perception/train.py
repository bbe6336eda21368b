"""Training the perception network: ``objsearch perception train``.

A run folder holds ``config.json`` (the ``TrainConfig``), ``model.pt`` (the evaluable
network, ``objsearch.perception.inference``), ``state.pt`` (network, optimizer, step and
log: what resuming needs) and ``log.csv`` (one row every ``log_every`` steps: mean losses,
learning rate, wall time, and validation mIoU / AbsRel where evaluated).

Loss: class-weighted cross-entropy over every category id + ``depth_weight`` x L1 of log
depth over pixels that hit something. AdamW with linear warm-up and poly decay.

Reproducible: the weights are initialised from ``torch.Generator`` seeded by ``seed``;
epoch e visits the frames in the order ``default_rng([seed, e]).permutation``; the
augmentation of step s draws from a ``torch.Generator`` seeded by (seed, s). So a resumed
run continues exactly as an uninterrupted one would (on the same device and threads).
Re-running the same command resumes from ``state.pt``; Ctrl-C (or SIGTERM) finishes the current
step, writes a checkpoint and exits with 130 (143).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F

from objsearch import torchfile
from objsearch.errors import UserError
from objsearch.fileio import write_csv
from objsearch.interrupt import stop_on_interrupt
from objsearch.perception.config import TrainConfig
from objsearch.perception.dataset import load_split, read_manifest
from objsearch.perception.inference import (
    Predictor,
    checkpoint_settings,
    evaluate,
    load_checkpoint,
    save_checkpoint,
)
from objsearch.perception.model import NUM_CLASSES, ModelConfig, SegDepthNet, pick_device
from objsearch.sim.camera import RenderSettings, check_camera

CONFIG_FILE, MODEL_FILE, STATE_FILE, LOG_FILE = "config.json", "model.pt", "state.pt", "log.csv"
LOG_FIELDS = [
    "step",
    "epoch",
    "lr",
    "loss",
    "seg_loss",
    "depth_loss",
    "wall_s",
    "val_miou",
    "val_absrel",
    "val_pixel_acc",
]


def init_weights(model: SegDepthNet, generator: torch.Generator) -> None:
    """Kaiming-normal convolutions, drawn from ``generator`` (not the global torch RNG)."""
    for name, module in model.named_modules():
        if isinstance(module, torch.nn.Conv2d):
            if module is model.seg_head or module is model.depth_head:  # heads start near uniform / exp(1) m
                torch.nn.init.normal_(module.weight, std=0.01, generator=generator)
            else:
                torch.nn.init.kaiming_normal_(module.weight, mode="fan_out", nonlinearity="relu", generator=generator)
            if module.bias is not None:
                torch.nn.init.constant_(module.bias, 1.0 if module is model.depth_head else 0.0)


def start_from(model: SegDepthNet, path: str, settings: RenderSettings) -> None:
    """Load the weights of the perception checkpoint ``path`` (``TrainConfig.init``) into
    ``model``; ``UserError`` if its network or its training frames' camera differ."""
    state = load_checkpoint(path)
    saved = ModelConfig.from_json(state["model_config"], source=f"the model_config of checkpoint {path}")
    if saved != model.config:
        changed = [k for k, v in model.config.to_json().items() if saved.to_json().get(k) != v]
        raise UserError(
            f"init={path} is a network with other {', '.join(changed)} than this run's model; "
            "drop the --set model.* overrides that differ, or start without init"
        )
    check_camera(
        checkpoint_settings(state, path),
        settings,
        source=f"init={path}",
        expected_name="the camera of this run's dataset",
        fix="start without init, or from a checkpoint trained on frames of this camera",
    )
    model.load_state_dict(state["state_dict"])


def class_weights(class_pixels, kind: str) -> torch.Tensor:
    """Cross-entropy weights from training pixel counts per class (``enet``: 1 / ln(1.02 + p))."""
    counts = np.asarray(class_pixels, np.float64)
    if kind == "none":
        return torch.ones(NUM_CLASSES)
    p = counts / max(counts.sum(), 1.0)
    return torch.tensor(1.0 / np.log(1.02 + p), dtype=torch.float32)


def augment(rgb: torch.Tensor, semantic: torch.Tensor, depth: torch.Tensor, generator: torch.Generator):
    """Flip half the frames left-right; jitter brightness, contrast and per-channel gain. rgb float (N, 3, H, W)."""
    n, device = rgb.shape[0], rgb.device
    u = torch.rand(n, 6, generator=generator).to(device)
    flip = u[:, 0] < 0.5
    rgb = torch.where(flip[:, None, None, None], rgb.flip(-1), rgb)
    semantic = torch.where(flip[:, None, None], semantic.flip(-1), semantic)
    depth = torch.where(flip[:, None, None], depth.flip(-1), depth)
    brightness = 0.75 + 0.5 * u[:, 1]
    contrast = 0.75 + 0.5 * u[:, 2]
    gain = 0.9 + 0.2 * u[:, 3:6]
    mean = rgb.mean(dim=(1, 2, 3), keepdim=True)
    rgb = (
        ((rgb - mean) * contrast[:, None, None, None] + mean) * brightness[:, None, None, None] * gain[:, :, None, None]
    )
    return rgb.clamp(0.0, 1.0), semantic, depth


def learning_rate(config: TrainConfig, step: int) -> float:
    """The learning rate at ``step``: linear warm-up over ``warmup_steps``, then decay to 0 with power ``lr_power``."""
    if step < config.warmup_steps:
        return config.lr * (step + 1) / config.warmup_steps
    return config.lr * (1.0 - step / config.steps) ** config.lr_power


class TrainRun:
    """One training run in ``out`` (fresh or resumed from ``state.pt``)."""

    def __init__(self, config: TrainConfig, out: str | Path, fresh: bool = False):
        self.config, self.out = config, Path(out)
        if config.threads:
            torch.set_num_threads(config.threads)
        self.device = pick_device(config.device)
        manifest = read_manifest(config.data)
        # the camera of the frames
        self.settings = RenderSettings.from_json(manifest["settings"], source=Path(config.data) / "manifest.json")
        train = load_split(config.data, "train", config.max_train_frames or None)
        if len(train) < config.batch_size:
            raise UserError(
                f"{len(train)} training frames in {config.data} are fewer than batch_size={config.batch_size}"
            )
        self.val = (
            load_split(config.data, "val", config.val_frames)
            if config.val_frames and "val" in manifest["splits"]
            else None
        )
        # uint8 frames stay uint8 on the device; a batch is converted when drawn
        self.rgb = torch.from_numpy(train.rgb).to(self.device)
        self.semantic = torch.from_numpy(train.semantic).to(self.device)
        self.depth = torch.from_numpy(train.depth).to(self.device)
        self.steps_per_epoch = len(train) // config.batch_size
        weights = class_weights(manifest["splits"]["train"]["class_pixels"], config.class_weighting)
        self.weights = weights.to(self.device)
        self.model = SegDepthNet(config.model)
        init_weights(self.model, torch.Generator().manual_seed(config.seed))
        if config.init:
            start_from(self.model, config.init, self.settings)
        self.model.to(self.device)
        self.optimizer = torch.optim.AdamW(self.model.parameters(), lr=config.lr, weight_decay=config.weight_decay)
        self.step, self.wall_s, self.rows, self._window = 0, 0.0, [], []
        self._perm_epoch, self._perm = -1, None
        state_path = self.out / STATE_FILE
        if state_path.exists() and not fresh:
            torchfile.resume(
                state_path, config, self.load_state_dict, expected="the state.pt of a perception training run"
            )

    def load_state_dict(self, state: dict) -> None:
        """Restore the model, optimizer, step, wall time and log rows from a ``state.pt`` dict."""
        self.model.load_state_dict(state["model"])
        self.optimizer.load_state_dict(state["optimizer"])
        self.step, self.wall_s, self.rows = state["step"], state["wall_s"], list(state["rows"])

    def batch_indices(self, step: int) -> np.ndarray:
        """Training-frame indices (batch_size,) of ``step``: a slice of its epoch's permutation."""
        epoch, i = divmod(step, self.steps_per_epoch)
        if epoch != self._perm_epoch:
            self._perm = np.random.default_rng([self.config.seed, epoch]).permutation(len(self.rgb))
            self._perm_epoch = epoch
        b = self.config.batch_size
        return self._perm[i * b : (i + 1) * b]

    def train_step(self) -> dict:
        """One optimizer step on the next batch (augmented if configured); advances ``step``.

        Returns the step's ``loss``, ``seg_loss``, ``depth_loss`` and ``lr``.
        """
        c = self.config
        idx = torch.from_numpy(self.batch_indices(self.step)).to(self.device)
        rgb = self.rgb[idx].permute(0, 3, 1, 2).float().div_(255.0)
        semantic, depth = self.semantic[idx].long(), self.depth[idx]
        if c.augment:
            generator = torch.Generator().manual_seed(c.seed * 1_000_003 + self.step)
            rgb, semantic, depth = augment(rgb, semantic, depth, generator)
        lr = learning_rate(c, self.step)
        for group in self.optimizer.param_groups:
            group["lr"] = lr
        self.model.train()
        logits, log_depth = self.model(rgb)
        seg_loss = F.cross_entropy(logits, semantic, weight=self.weights)
        valid = (depth > 0) & (depth < self.settings.zfar)
        depth_loss = (
            (log_depth - depth.clamp(min=1e-3).log()).abs()[valid].mean() if valid.any() else log_depth.sum() * 0
        )
        loss = seg_loss + c.depth_weight * depth_loss
        self.optimizer.zero_grad(set_to_none=True)
        loss.backward()
        self.optimizer.step()
        self.step += 1
        return {"loss": loss.item(), "seg_loss": seg_loss.item(), "depth_loss": depth_loss.item(), "lr": lr}

    def validate(self) -> dict:
        """Validation ``val_miou``, ``val_absrel``, ``val_pixel_acc`` (rounded to 4 places); {} without a val split."""
        if self.val is None:
            return {}
        result = evaluate(Predictor(self.model, self.settings, key="training", device=self.device), self.val)
        self.model.train()
        return {
            "val_miou": round(result["miou"], 4),
            "val_absrel": round(result["depth_absrel"], 4),
            "val_pixel_acc": round(result["pixel_accuracy"], 4),
        }

    def log_row(self, extra: dict) -> dict:
        """Append and return a log row: step, epoch, wall time, mean losses since the last row, and ``extra``."""
        window, self._window = self._window, []
        row = {"step": self.step, "epoch": round(self.step / self.steps_per_epoch, 3), "wall_s": round(self.wall_s, 1)}
        if window:
            row["lr"] = f"{window[-1]['lr']:.3g}"
            for key in ("loss", "seg_loss", "depth_loss"):
                row[key] = round(sum(w[key] for w in window) / len(window), 4)
        row.update(extra)
        self.rows.append(row)
        return row

    def write_log(self) -> None:
        """Rewrite ``log.csv`` with every row so far (after each row, not only at checkpoints)."""
        write_csv(self.out / LOG_FILE, LOG_FIELDS, self.rows)

    def save(self) -> None:
        """Write the config, the model checkpoint, ``log.csv`` and ``state.pt`` (what a resume needs) into ``out``."""
        self.out.mkdir(parents=True, exist_ok=True)
        self.config.save(self.out / CONFIG_FILE)
        save_checkpoint(self.out / MODEL_FILE, self.model, self.settings)
        self.write_log()
        state = {
            "config": self.config.to_json(),
            "model": self.model.state_dict(),
            "optimizer": self.optimizer.state_dict(),
            "step": self.step,
            "wall_s": self.wall_s,
            "rows": self.rows,
        }
        torchfile.save(self.out / STATE_FILE, state)

    def run(self, progress: bool = True) -> bool:
        """Train to ``config.steps``, checkpointing as it goes; False if interrupted (Ctrl-C or SIGTERM)."""
        from tqdm import tqdm

        c = self.config
        with stop_on_interrupt() as stop:
            bar = tqdm(
                total=c.steps, initial=self.step, unit="step", desc="train perception", disable=not progress or None
            )
            try:
                t0, wall0 = time.perf_counter(), self.wall_s
                while self.step < c.steps and not stop.is_set():
                    self._window.append(self.train_step())
                    self.wall_s = wall0 + time.perf_counter() - t0
                    bar.update(1)
                    last = self.step == c.steps
                    if self.step % c.log_every == 0 or last or self.step % c.eval_every == 0:
                        extra = self.validate() if (self.step % c.eval_every == 0 or last) else {}
                        row = self.log_row(extra)
                        self.write_log()
                        bar.set_postfix({k: row[k] for k in ("loss", "val_miou", "val_absrel") if k in row})
                    if self.step % c.checkpoint_every == 0 or last:
                        self.save()
                self.save()
            finally:
                bar.close()
            return not stop.is_set()


def train(config: TrainConfig, out: str | Path, fresh: bool = False, progress: bool = True) -> bool:
    """Train (or resume) a run in ``out``; returns False if interrupted."""
    return TrainRun(config, out, fresh).run(progress)


__all__ = ["TrainRun", "train", "class_weights", "augment", "init_weights", "learning_rate"]
