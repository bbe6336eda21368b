"""Segmentation and depth metrics, accumulated over batches.

Segmentation: one confusion matrix ``conf[gt, pred]`` over every category id.

* IoU of class c = TP / (TP + FP + FN), defined for classes with ground-truth pixels.
* ``miou``: the mean IoU over the OBJECT categories (ids >= ``FIRST_OBJECT_ID``) that
  have at least one ground-truth pixel in the evaluated frames. Structure classes
  (background, wall, floor, door, ceiling) are reported but not counted; object categories
  absent from the ground truth are not counted either (their false positives still lower
  the IoU of the classes whose pixels they took). ``counted`` lists the ids averaged.
* ``pixel_accuracy``: correct pixels / all pixels (every class).
* ``confused_with``: for each class with ground-truth pixels, the other class that took
  most of them and the share it took (what a low IoU is lost to).
* ``miou_over(result, ids)``: the same mean over a subset of categories (``objsearch
  perception eval`` reports it for the house suites' target categories as ``miou_targets``).

Depth, over pixels whose ground truth hit something (0 < gt < ``zfar``):

* ``depth_absrel`` = mean |d - g| / g; ``depth_rmse`` = sqrt(mean (d - g)^2) metres;
  ``depth_delta1`` = fraction with max(d / g, g / d) < 1.25.
"""

from __future__ import annotations

import numpy as np

from objsearch.house.categories import CATEGORY_NAMES, FIRST_OBJECT_ID
from objsearch.perception.model import NUM_CLASSES


def confusion_matrix(gt: np.ndarray, pred: np.ndarray, num_classes: int = NUM_CLASSES) -> np.ndarray:
    """int64 (C, C) counts of (ground truth, prediction) pairs over all pixels."""
    gt = np.asarray(gt, np.int64).ravel()
    pred = np.asarray(pred, np.int64).ravel()
    return np.bincount(gt * num_classes + pred, minlength=num_classes * num_classes).reshape(num_classes, num_classes)


def segmentation_metrics(conf: np.ndarray) -> dict:
    """IoU per class, mIoU over present object categories, pixel accuracy, from ``conf[gt, pred]``."""
    conf = np.asarray(conf, np.float64)
    tp = np.diag(conf)
    gt_pixels = conf.sum(axis=1)
    union = gt_pixels + conf.sum(axis=0) - tp
    present = gt_pixels > 0
    iou = np.where(present, tp / np.maximum(union, 1), np.nan)
    counted = [int(c) for c in np.flatnonzero(present) if c >= FIRST_OBJECT_ID]
    total = conf.sum()
    others = conf - np.diag(tp)
    confused_with = {}
    for c in np.flatnonzero(present):
        worst = int(np.argmax(others[c]))
        confused_with[int(c)] = (worst, float(others[c, worst] / gt_pixels[c]))
    return {
        "miou": float(np.mean(iou[counted])) if counted else float("nan"),
        "pixel_accuracy": float(tp.sum() / total) if total else float("nan"),
        "counted": counted,
        "iou": {int(c): float(iou[c]) for c in np.flatnonzero(present)},
        "gt_pixels": {int(c): int(gt_pixels[c]) for c in np.flatnonzero(present)},
        "confused_with": confused_with,
    }


def miou_over(result: dict, ids) -> float:
    """Mean IoU over those of the category ``ids`` that have ground-truth pixels (nan if none)."""
    present = [result["iou"][c] for c in ids if c in result["iou"]]
    return float(np.mean(present)) if present else float("nan")


class DepthErrors:
    """Running sums for AbsRel, RMSE and delta < 1.25 over valid pixels."""

    def __init__(self, zfar: float):
        self.zfar = float(zfar)
        self.n = 0
        self.absrel = 0.0
        self.sq = 0.0
        self.delta1 = 0

    def update(self, gt: np.ndarray, pred: np.ndarray) -> None:
        """Add the errors of one batch of depth maps (metres), over pixels with 0 < gt < zfar."""
        gt = np.asarray(gt, np.float64)
        pred = np.asarray(pred, np.float64)
        valid = (gt > 0) & (gt < self.zfar)
        g, d = gt[valid], np.maximum(pred[valid], 1e-6)
        self.n += int(g.size)
        self.absrel += float(np.sum(np.abs(d - g) / g))
        self.sq += float(np.sum((d - g) ** 2))
        self.delta1 += int(np.sum(np.maximum(d / g, g / d) < 1.25))

    def result(self) -> dict:
        """``depth_absrel``, ``depth_rmse`` (metres), ``depth_delta1`` and ``depth_pixels``; NaN without pixels."""
        n = max(self.n, 1)
        nan = float("nan")
        return {
            "depth_absrel": self.absrel / n if self.n else nan,
            "depth_rmse": float(np.sqrt(self.sq / n)) if self.n else nan,
            "depth_delta1": self.delta1 / n if self.n else nan,
            "depth_pixels": self.n,
        }


class Evaluation:
    """Accumulates segmentation and depth metrics over batches of frames."""

    def __init__(self, zfar: float, num_classes: int = NUM_CLASSES):
        self.conf = np.zeros((num_classes, num_classes), np.int64)
        self.depth = DepthErrors(zfar)
        self.num_classes = num_classes

    def update(self, gt_semantic, pred_semantic, gt_depth, pred_depth) -> None:
        """Add one batch: semantic labels to the confusion matrix, depth maps to the depth errors."""
        self.conf += confusion_matrix(gt_semantic, pred_semantic, self.num_classes)
        self.depth.update(gt_depth, pred_depth)

    def result(self) -> dict:
        """The segmentation metrics (``segmentation_metrics``) and depth errors so far, in one dict."""
        return {**segmentation_metrics(self.conf), **self.depth.result()}


def format_table(result: dict) -> str:
    """The per-category table (every class with ground-truth pixels) and the summary lines."""
    lines = [f"{'id':>3}  {'category':<16} {'IoU':>6} {'gt pixels':>10}  counted  most taken by"]
    for c, iou in sorted(result["iou"].items()):
        mark = "yes" if c in result["counted"] else "-"
        other, share = result["confused_with"][c]
        lines.append(
            f"{c:>3}  {CATEGORY_NAMES.get(c, '?'):<16} {iou:6.3f} {result['gt_pixels'][c]:>10}  {mark:<7}  "
            f"{CATEGORY_NAMES.get(other, '?')} {share:.0%}"
        )
    lines.append(
        f"mIoU over {len(result['counted'])} object categories: {result['miou']:.3f}   "
        f"pixel accuracy: {result['pixel_accuracy']:.3f}"
    )
    lines.append(
        f"depth AbsRel: {result['depth_absrel']:.3f}   RMSE: {result['depth_rmse']:.3f} m   "
        f"delta<1.25: {result['depth_delta1']:.3f}"
    )
    return "\n".join(lines)
