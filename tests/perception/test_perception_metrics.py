import math

import numpy as np
import pytest

from objsearch.house.categories import CATEGORY_IDS
from objsearch.perception.metrics import (
    DepthErrors,
    Evaluation,
    confusion_matrix,
    format_table,
    miou_over,
    segmentation_metrics,
)

WALL, FLOOR = CATEGORY_IDS["wall"], CATEGORY_IDS["floor"]
SOFA, TV, BED = CATEGORY_IDS["sofa"], CATEGORY_IDS["tv"], CATEGORY_IDS["bed"]


def test_confusion_matrix_counts_gt_rows_and_prediction_columns():
    gt = np.array([[WALL, WALL, SOFA, SOFA]])
    pred = np.array([[WALL, SOFA, SOFA, TV]])
    conf = confusion_matrix(gt, pred)
    assert (
        conf.sum() == 4
        and conf[WALL, WALL] == 1
        and conf[WALL, SOFA] == 1
        and conf[SOFA, SOFA] == 1
        and conf[SOFA, TV] == 1
    )


def test_iou_by_hand_with_a_predicted_but_absent_class():
    # gt:   wall x4, sofa x4, floor x2       pred: wall x3 + sofa x1 | sofa x2 + tv x2 | floor x2
    gt = np.array([WALL] * 4 + [SOFA] * 4 + [FLOOR] * 2)
    pred = np.array([WALL] * 3 + [SOFA] + [SOFA] * 2 + [TV] * 2 + [FLOOR] * 2)
    m = segmentation_metrics(confusion_matrix(gt, pred))
    # sofa: TP 2, FP 1 (a wall pixel), FN 2 (the tv pixels) -> 2 / 5
    assert m["iou"][SOFA] == pytest.approx(2 / 5)
    assert m["iou"][WALL] == pytest.approx(3 / 4) and m["iou"][FLOOR] == 1.0
    # tv has no ground-truth pixel: no IoU, not counted; only objects count (walls/floors do not)
    assert TV not in m["iou"] and m["counted"] == [SOFA]
    assert m["miou"] == pytest.approx(2 / 5)
    assert m["pixel_accuracy"] == pytest.approx(7 / 10)
    # what each class loses its pixels to: half the sofa's went to the tv, a quarter of the wall's to the sofa
    assert m["confused_with"][SOFA] == (TV, pytest.approx(2 / 4)) and m["confused_with"][WALL] == (
        SOFA,
        pytest.approx(1 / 4),
    )
    assert "tv 50%" in format_table({**m, "depth_absrel": 0.0, "depth_rmse": 0.0, "depth_delta1": 1.0})


def test_miou_averages_present_object_categories_only():
    gt = np.array([SOFA, SOFA, BED, BED, WALL])
    pred = np.array([SOFA, SOFA, BED, SOFA, FLOOR])
    m = segmentation_metrics(confusion_matrix(gt, pred))
    assert m["iou"][SOFA] == pytest.approx(2 / 3) and m["iou"][BED] == pytest.approx(1 / 2) and m["iou"][WALL] == 0.0
    assert m["counted"] == [SOFA, BED] and m["miou"] == pytest.approx((2 / 3 + 1 / 2) / 2)
    empty = segmentation_metrics(confusion_matrix(np.array([WALL]), np.array([WALL])))
    assert empty["counted"] == [] and math.isnan(empty["miou"])
    # a subset (the suites' target categories): absent members are skipped, not counted as 0
    assert miou_over(m, [BED]) == pytest.approx(1 / 2)
    toilet = CATEGORY_IDS["toilet"]  # absent from these frames
    assert miou_over(m, [BED, SOFA, toilet]) == pytest.approx(m["miou"]) and math.isnan(miou_over(m, [toilet]))


def test_depth_errors_by_hand_skip_pixels_that_hit_nothing():
    gt = np.array([1.0, 2.0, 4.0, 30.0, 0.0])  # the last two: nothing hit (zfar) and invalid
    pred = np.array([1.1, 1.0, 4.0, 5.0, 3.0])
    d = DepthErrors(zfar=30.0)
    d.update(gt, pred)
    r = d.result()
    assert r["depth_pixels"] == 3
    assert r["depth_absrel"] == pytest.approx((0.1 / 1 + 1.0 / 2 + 0) / 3)
    assert r["depth_rmse"] == pytest.approx(math.sqrt((0.01 + 1.0 + 0) / 3))
    assert r["depth_delta1"] == pytest.approx(2 / 3)  # 1.1/1 and 4/4 pass, 2/1 fails


def test_evaluation_accumulates_batches_like_one():
    rng = np.random.default_rng(0)
    labels = np.array([WALL, FLOOR, SOFA, TV, BED])
    gt, pred = labels[rng.integers(0, 5, (6, 8, 8))], labels[rng.integers(0, 5, (6, 8, 8))]
    gd, pd = rng.uniform(0.5, 8, (6, 8, 8)), rng.uniform(0.5, 8, (6, 8, 8))
    whole, parts = Evaluation(30.0), Evaluation(30.0)
    whole.update(gt, pred, gd, pd)
    parts.update(gt[:2], pred[:2], gd[:2], pd[:2])
    parts.update(gt[2:], pred[2:], gd[2:], pd[2:])
    a, b = whole.result(), parts.result()
    assert a["miou"] == pytest.approx(b["miou"]) and a["depth_absrel"] == pytest.approx(b["depth_absrel"])
    assert "sofa" in format_table(a) and "mIoU over 3 object categories" in format_table(a)


def test_near_detections_score_the_stop_test_on_each_sides_own_depth():
    """A tv the network puts within 1 m where it stands 1.5 m off is a false STOP (near false
    positive); one within 1 m in both counts; a near one the network puts beyond 1 m is missed."""
    from objsearch.perception.metrics import target_metrics

    semantic = np.full((3, 8, 8), WALL)
    semantic[:, 2:7, 2:7] = TV  # 25 pixels: enough for the 20-pixel rule
    gt_depth = np.stack([np.full((8, 8), d, np.float32) for d in (1.5, 0.8, 0.8)])
    pred_depth = np.stack([np.full((8, 8), d, np.float32) for d in (0.9, 0.7, 1.2)])
    evaluation = Evaluation(zfar=10.0)
    evaluation.update(semantic, semantic, gt_depth, pred_depth)
    result = evaluation.result()
    assert result["near"][TV] == {"tp": 1, "fp": 1, "fn": 1}
    assert result["visibility"][TV] == {"tp": 3, "fp": 0, "fn": 0}, "beyond 1 m it is still visible"
    scores = target_metrics(result, [TV, SOFA])
    assert scores["stop_precision_targets"] == 0.5 and scores["stop_recall_targets"] == 0.5
