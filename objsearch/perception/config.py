"""The training configuration of the perception network, written as ``config.json`` next to
every checkpoint so that a run can be rebuilt from the file alone."""

from __future__ import annotations

from dataclasses import dataclass, field

from objsearch.configs import JsonConfig, require_at_least
from objsearch.errors import UserError
from objsearch.perception.model import ModelConfig

WEIGHTINGS = ("enet", "none")


@dataclass(frozen=True)
class TrainConfig(JsonConfig):
    """Serialised, read and overridden (``--set``, ``--set model.KEY=...``) through
    ``objsearch.configs.JsonConfig``."""

    DESCRIPTION = "a perception training config"
    LEGACY_KEYS = {}  # no field has been renamed or removed since the shipped checkpoint

    data: str = "data/perception"
    """Dataset folder written by ``objsearch perception dataset`` (its ``train`` and ``val`` splits)."""
    seed: int = 0
    """Seeds the weight initialisation, the order of frames in every epoch and the augmentation."""
    steps: int = 12_000
    """Optimizer steps (one batch each). The default, 9.6 epochs of the default 40,000-frame train split, takes
    about 90 minutes on 2 free CPU cores (0.44 s a step; docs/perception.md)."""
    batch_size: int = 32
    """Frames per step."""
    lr: float = 2e-3
    """Peak AdamW learning rate (after warm-up), decayed by the poly rule (1 - step / steps) ** lr_power."""
    lr_power: float = 0.9
    """Exponent of the poly learning-rate decay (DeepLab's)."""
    warmup_steps: int = 200
    """Steps of linear learning-rate warm-up from 0."""
    weight_decay: float = 1e-4
    """AdamW weight decay."""
    depth_weight: float = 1.0
    """Weight of the depth loss (L1 on log depth over pixels that hit something) beside the cross-entropy."""
    class_weighting: str = "enet"
    """Cross-entropy class weights: ``enet`` (1 / ln(1.02 + training pixel frequency), ENet's; rare object
    categories weigh up to ~50x) or ``none``."""
    augment: bool = True
    """Random horizontal flips and colour jitter (brightness, contrast, per-channel gain) of training frames."""
    max_train_frames: int = 0
    """Use only the first this many training frames (0: all)."""
    val_frames: int = 1000
    """Validation frames evaluated every ``eval_every`` steps and at the end (0: no validation)."""
    eval_every: int = 2000
    """Evaluate on the validation frames every this many steps."""
    log_every: int = 50
    """Append a row (mean losses of the last rows' steps) to ``log.csv`` every this many steps."""
    checkpoint_every: int = 500
    """Write ``model.pt`` and the resumable ``state.pt`` every this many steps."""
    device: str = "auto"
    """``auto`` (CUDA when present, else CPU), ``cpu`` or ``cuda``."""
    threads: int = 0
    """torch CPU threads (0: torch's default, the number of cores)."""
    model: ModelConfig = field(default_factory=ModelConfig)
    """Network widths (``--set model.stem=16``)."""
    init: str = ""
    """A perception ``model.pt`` whose weights start the run instead of the seeded initialisation
    (fine-tuning, or more steps for a finished run under a new schedule); it must have this
    run's ``model`` and have been trained on frames of the dataset's camera. Empty: random weights."""

    def __post_init__(self):
        if self.class_weighting not in WEIGHTINGS:
            raise UserError(f"class_weighting must be one of {WEIGHTINGS}, not {self.class_weighting!r}")
        require_at_least(self, ("steps", "batch_size", "eval_every", "log_every", "checkpoint_every"), 1)
        require_at_least(self, ("warmup_steps", "max_train_frames", "val_frames", "threads"), 0)
        if isinstance(self.model, dict):
            object.__setattr__(self, "model", ModelConfig.from_json(self.model))
