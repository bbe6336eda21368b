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

What a searching agent uses of a frame, per frame and object category:

* visibility: a category is *visible* in a frame when it covers at least ``VISIBLE_PIXELS``
  (20) pixels of it, the agents' candidate rule (``objsearch_agents.house.tables.
  VISIBLE_PIXELS``, mirrored here because perception may not import the agents). Every
  (frame, object category) pair is a detection: ground-truth visible vs predicted visible.
  ``visibility_f1`` / ``_precision`` / ``_recall``: micro-averaged over all pairs of all
  object categories (a predicted-visible category absent from the ground truth is a false
  positive); ``visibility`` holds each category's counts (``tp``, ``fp``, ``fn``) and
  ``visibility_over(result, ids)`` the micro-F1 over a subset (``visibility_f1_targets``).
* 10 x 10 masks: the agents see each category as a 10 x 10 map, the fraction of every
  block that shows it (``cv2.resize(mask, (10, 10), INTER_AREA)``, exactly
  ``objsearch.sim.wrappers.TargetMaskDepth``; ``downsample_mask``). ``mask10_iou`` of a
  category = sum over frames and blocks of min(gt, pred) / sum of max(gt, pred) (the IoU
  of the fractional maps; the plain IoU where they are 0/1), for categories with
  ground-truth pixels; ``mask10_miou`` its mean over ``counted``, ``mask10_iou_targets``
  over the suites' target categories (``target_metrics``).

* near: the same detections counted only on pixels within ``NEAR_DISTANCE`` (1 m, by each
  side's own depth): a category predicted near is the ObjectNav STOP test (``min_pixels`` 20
  within 1 m) passing on the prediction, and ``near_precision`` the share of those frames where
  the ground truth passes it too (one frame's STOP precision); ``near`` holds the counts,
  ``stop_precision_targets`` / ``stop_recall_targets`` the micro scores over the suites' targets.

``target_metrics(result, ids)`` adds ``miou_targets``, ``visibility_f1_targets`` and
``mask10_iou_targets``; ``QUALITY_TARGETS`` are the figures a network should reach on the test houses for agents
to search on its predictions as on ground truth, and ``format_targets`` prints a result beside them.
"""

from __future__ import annotations

import cv2
import numpy as np

from objsearch.house.categories import CATEGORY_NAMES, FIRST_OBJECT_ID
from objsearch.perception.model import NUM_CLASSES

#: Pixels (of the 64 x 64 frame) a category must cover to count as visible: the agents'
#: candidate rule ``objsearch_agents.house.tables.VISIBLE_PIXELS`` (a test checks they agree).
VISIBLE_PIXELS = 20
#: Metres: pixels within this count for the near detections (the ObjectNav goal rule's distance).
NEAR_DISTANCE = 1.0
#: Side of the block maps the agents see (the paper's 10 x 10).
MASK_SIZE = 10
#: The figures a network should reach on the test houses: metric -> (">=" or "<=", value).
QUALITY_TARGETS = {
    "miou_targets": (">=", 0.60),
    "miou": (">=", 0.40),
    "visibility_f1": (">=", 0.85),
    "depth_absrel": ("<=", 0.06),
}


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


def category_pixels(semantic: np.ndarray, num_classes: int = NUM_CLASSES) -> np.ndarray:
    """int64 (N, C): pixels of every category id in each of the frames ``semantic`` (N, H, W)."""
    semantic = np.asarray(semantic, np.int64)
    n = len(semantic)
    frame = np.repeat(np.arange(n, dtype=np.int64), semantic[0].size if n else 0)
    counts = np.bincount(frame * num_classes + semantic.ravel(), minlength=n * num_classes)
    return counts.reshape(n, num_classes)


def downsample_mask(semantic: np.ndarray, category: int, size: int = MASK_SIZE) -> np.ndarray:
    """float32 (size, size): the fraction of each block of one frame that shows ``category``,
    the agents' map (``objsearch.sim.wrappers.TargetMaskDepth``: area averaging)."""
    mask = (np.asarray(semantic) == category).astype(np.float32)
    return cv2.resize(mask, (size, size), interpolation=cv2.INTER_AREA)


def near(depth) -> np.ndarray:
    """Pixels a depth map (metres) puts within ``NEAR_DISTANCE``: the goal rule's ``depth <= max_distance``
    (0: no hit)."""
    depth = np.asarray(depth)
    return (depth > 0) & (depth <= NEAR_DISTANCE)


def _ratio(num: float, den: float) -> float:
    return float(num / den) if den else float("nan")


class VisibilityCounts:
    """Per object category: frames where it is visible in both, only predicted, only in the ground truth."""

    def __init__(self, num_classes: int = NUM_CLASSES, min_pixels: int = VISIBLE_PIXELS):
        self.min_pixels = int(min_pixels)
        self.tp = np.zeros(num_classes, np.int64)
        self.fp = np.zeros(num_classes, np.int64)
        self.fn = np.zeros(num_classes, np.int64)

    def update(self, gt_pixels: np.ndarray, pred_pixels: np.ndarray) -> None:
        """Add frames given their (N, C) category pixel counts (``category_pixels``)."""
        gt = np.asarray(gt_pixels) >= self.min_pixels
        pred = np.asarray(pred_pixels) >= self.min_pixels
        self.tp += np.sum(gt & pred, axis=0)
        self.fp += np.sum(~gt & pred, axis=0)
        self.fn += np.sum(gt & ~pred, axis=0)

    def result(self) -> dict:
        """``visibility_f1`` / ``_precision`` / ``_recall`` (micro over object categories), and
        ``visibility``: {id: {tp, fp, fn}} for every object category visible in either."""
        objects = slice(FIRST_OBJECT_ID, None)
        per = {
            int(c): {"tp": int(self.tp[c]), "fp": int(self.fp[c]), "fn": int(self.fn[c])}
            for c in range(FIRST_OBJECT_ID, len(self.tp))
            if self.tp[c] + self.fp[c] + self.fn[c]
        }
        tp, fp, fn = (int(a[objects].sum()) for a in (self.tp, self.fp, self.fn))
        return {
            "visibility_f1": _ratio(2 * tp, 2 * tp + fp + fn),
            "visibility_precision": _ratio(tp, tp + fp),
            "visibility_recall": _ratio(tp, tp + fn),
            "visible_pixels": self.min_pixels,
            "visibility": per,
        }


def visibility_scores(counts: dict) -> dict:
    """``precision``, ``recall``, ``f1`` (nan where undefined) of one category's ``{tp, fp, fn}``."""
    tp, fp, fn = counts["tp"], counts["fp"], counts["fn"]
    return {"precision": _ratio(tp, tp + fp), "recall": _ratio(tp, tp + fn), "f1": _ratio(2 * tp, 2 * tp + fp + fn)}


def counts_over(per_category: dict, ids) -> dict:
    """The ``{tp, fp, fn}`` counts of the category ``ids``, summed (micro-averaging)."""
    rows = [per_category[c] for c in ids if c in per_category]
    return {k: sum(r[k] for r in rows) for k in ("tp", "fp", "fn")}


def visibility_over(result: dict, ids) -> float:
    """Micro-F1 of visibility over the (frame, category) pairs of the category ``ids`` (nan if
    none of them is visible in either the ground truth or the prediction)."""
    return visibility_scores(counts_over(result["visibility"], ids))["f1"]


class MaskOverlap:
    """Sums of min and max of the ground-truth and predicted 10 x 10 maps, per category."""

    def __init__(self, num_classes: int = NUM_CLASSES, size: int = MASK_SIZE):
        self.size = size
        self.inter = np.zeros(num_classes, np.float64)
        self.union = np.zeros(num_classes, np.float64)

    def update(self, gt_semantic, pred_semantic, gt_pixels: np.ndarray, pred_pixels: np.ndarray) -> None:
        """Add frames (``*_pixels``: their ``category_pixels``, to skip categories in neither)."""
        empty = np.zeros((self.size, self.size), np.float32)
        for i in range(len(gt_semantic)):
            for c in np.flatnonzero((gt_pixels[i] > 0) | (pred_pixels[i] > 0)):
                g = downsample_mask(gt_semantic[i], c, self.size) if gt_pixels[i, c] else empty
                p = downsample_mask(pred_semantic[i], c, self.size) if pred_pixels[i, c] else empty
                self.inter[c] += float(np.minimum(g, p).sum(dtype=np.float64))
                self.union[c] += float(np.maximum(g, p).sum(dtype=np.float64))

    def iou(self, present) -> dict:
        """{id: IoU of the 10 x 10 maps} for the category ids ``present``."""
        return {int(c): _ratio(self.inter[c], self.union[c]) for c in present}


def mean_over(per_category: dict, ids) -> float:
    """Mean of ``per_category[c]`` over those of ``ids`` it holds (nan if none)."""
    values = [per_category[c] for c in ids if c in per_category]
    return float(np.mean(values)) if values else float("nan")


def target_metrics(result: dict, ids) -> dict:
    """``miou_targets``, ``visibility_f1_targets``, ``stop_precision_targets`` / ``stop_recall_targets``
    and ``mask10_iou_targets`` over the category ``ids``."""
    out = {"miou_targets": miou_over(result, ids)}
    if "visibility" in result:
        out["visibility_f1_targets"] = visibility_over(result, ids)
    if "near" in result:
        scores = visibility_scores(counts_over(result["near"], ids))
        out["stop_precision_targets"], out["stop_recall_targets"] = scores["precision"], scores["recall"]
    if "mask10_iou" in result:
        out["mask10_iou_targets"] = mean_over(result["mask10_iou"], ids)
    return out


class Evaluation:
    """Accumulates segmentation and depth metrics over batches of frames."""

    def __init__(self, zfar: float, num_classes: int = NUM_CLASSES, visible_pixels: int = VISIBLE_PIXELS):
        self.conf = np.zeros((num_classes, num_classes), np.int64)
        self.depth = DepthErrors(zfar)
        self.visibility = VisibilityCounts(num_classes, visible_pixels)
        self.near = VisibilityCounts(num_classes, visible_pixels)
        self.masks = MaskOverlap(num_classes)
        self.num_classes = num_classes
        self.frames = 0

    def update(self, gt_semantic, pred_semantic, gt_depth, pred_depth) -> None:
        """Add one batch of (N, H, W) frames: semantic labels to the confusion matrix, the
        visibility counts and the 10 x 10 map overlaps, depth maps to the depth errors."""
        gt_semantic, pred_semantic = np.asarray(gt_semantic), np.asarray(pred_semantic)
        self.conf += confusion_matrix(gt_semantic, pred_semantic, self.num_classes)
        self.depth.update(gt_depth, pred_depth)
        if gt_semantic.ndim == 3:  # whole frames (a flat array of pixels has no frames to score)
            gt_pixels = category_pixels(gt_semantic, self.num_classes)
            pred_pixels = category_pixels(pred_semantic, self.num_classes)
            self.visibility.update(gt_pixels, pred_pixels)
            self.near.update(
                category_pixels(np.where(near(gt_depth), gt_semantic, 0), self.num_classes),
                category_pixels(np.where(near(pred_depth), pred_semantic, 0), self.num_classes),
            )
            self.masks.update(gt_semantic, pred_semantic, gt_pixels, pred_pixels)
            self.frames += len(gt_semantic)

    def result(self) -> dict:
        """The segmentation metrics (``segmentation_metrics``), visibility (and within 1 m), 10 x 10
        map IoUs and depth errors so far, in one dict."""
        seg = segmentation_metrics(self.conf)
        mask10 = self.masks.iou(seg["iou"])
        close = self.near.result()
        return {
            **seg,
            **self.visibility.result(),
            "near_precision": close["visibility_precision"],
            "near_recall": close["visibility_recall"],
            "near": close["visibility"],
            "mask10_iou": mask10,
            "mask10_miou": mean_over(mask10, seg["counted"]),
            **self.depth.result(),
        }


def format_table(result: dict, targets=()) -> str:
    """The per-category table (every class with ground-truth pixels) and the summary lines.

    With the visibility and 10 x 10 map metrics in ``result`` the table has their columns
    too: visibility precision / recall / F1 and the frames where the category is visible in
    the ground truth; ``targets``: category ids marked as the suites' targets.
    """
    full = "visibility" in result and "mask10_iou" in result
    targets = set(targets)
    header = f"{'id':>3}  {'category':<16} {'IoU':>6} {'gt pixels':>10}  counted"
    if full:
        header += f"  {'vis P':>5} {'vis R':>5} {'vis F1':>6} {'gt vis':>6} {'IoU10':>6}  target"
    lines = [header + "  most taken by"]
    for c, iou in sorted(result["iou"].items()):
        mark = "yes" if c in result["counted"] else "-"
        other, share = result["confused_with"][c]
        line = f"{c:>3}  {CATEGORY_NAMES.get(c, '?'):<16} {iou:6.3f} {result['gt_pixels'][c]:>10}  {mark:<7}"
        if full and c < FIRST_OBJECT_ID:  # structure: no visibility, no target
            line += f"  {'':>5} {'':>5} {'':>6} {'':>6} {result['mask10_iou'].get(c, float('nan')):6.3f}  {'-':<6}"
        elif full:
            counts = result["visibility"].get(c, {"tp": 0, "fp": 0, "fn": 0})
            v = visibility_scores(counts)
            line += (
                f"  {v['precision']:5.2f} {v['recall']:5.2f} {v['f1']:6.3f} {counts['tp'] + counts['fn']:>6} "
                f"{result['mask10_iou'].get(c, float('nan')):6.3f}  {'yes' if c in targets else '-':<6}"
            )
        lines.append(f"{line}  {CATEGORY_NAMES.get(other, '?')} {share:.0%}")
    lines.append(
        f"mIoU over {len(result['counted'])} object categories: {result['miou']:.3f}   "
        f"pixel accuracy: {result['pixel_accuracy']:.3f}"
    )
    if full:
        lines.append(
            f"visibility (>= {result['visible_pixels']} pixels) over all object categories: "
            f"F1 {result['visibility_f1']:.3f}   precision {result['visibility_precision']:.3f}   "
            f"recall {result['visibility_recall']:.3f}   10x10 map mIoU: {result['mask10_miou']:.3f}"
        )
    lines.append(
        f"depth AbsRel: {result['depth_absrel']:.3f}   RMSE: {result['depth_rmse']:.3f} m   "
        f"delta<1.25: {result['depth_delta1']:.3f}"
    )
    return "\n".join(lines)


def target_status(value: float, target: tuple[str, float]) -> str:
    """``met``, ``missed by D`` or ``not measured`` for a value against (">=" or "<=", threshold)."""
    op, threshold = target
    if value is None or np.isnan(value):
        return "not measured"
    met = value >= threshold if op == ">=" else value <= threshold
    return "met" if met else f"missed by {abs(value - threshold):.3f}"


def format_targets(result: dict, labels: dict | None = None) -> str:
    """One line per ``QUALITY_TARGETS`` metric in ``result``: the value, the target and whether it is met."""
    labels = labels or {}
    lines = []
    for key, (op, threshold) in QUALITY_TARGETS.items():
        value = result.get(key, float("nan"))
        lines.append(
            f"{labels.get(key, key):<44} {value:6.3f}   target {op} {threshold:.2f}: "
            f"{target_status(value, (op, threshold))}"
        )
    return "\n".join(lines)
