"""The perception metrics a searching agent uses (visibility, 10x10 masks) on hand-made frames with known answers:
visibility at the agents' candidate rule, the 10 x 10 maps the agents see, the target subset."""

import math

import cv2
import numpy as np
import pytest

from objsearch.house.categories import CATEGORY_IDS
from objsearch.perception.metrics import (
    QUALITY_TARGETS,
    VISIBLE_PIXELS,
    Evaluation,
    category_pixels,
    downsample_mask,
    format_table,
    format_targets,
    target_metrics,
    target_status,
    visibility_over,
    visibility_scores,
)

WALL = CATEGORY_IDS["wall"]
SOFA, TV, BED, PLANT = (CATEGORY_IDS[n] for n in ("sofa", "tv", "bed", "plant"))


def frame_with(*blobs, size=64):
    """A wall frame with rectangular blobs (category, rows, cols)."""
    f = np.full((size, size), WALL, np.uint8)
    for c, rows, cols in blobs:
        f[rows, cols] = c
    return f


def evaluate(gt, pred):
    ev = Evaluation(zfar=30.0)
    depth = np.ones(np.shape(gt), np.float32)
    ev.update(np.asarray(gt), np.asarray(pred), depth, depth)
    return ev.result()


def test_visible_pixels_is_the_agents_candidate_rule():
    tables = pytest.importorskip("objsearch_agents.house.tables")
    assert VISIBLE_PIXELS == tables.VISIBLE_PIXELS == 20


def test_category_pixels_counts_each_frame():
    frames = np.stack([frame_with((SOFA, slice(0, 2), slice(0, 10))), frame_with((TV, slice(0, 1), slice(0, 3)))])
    px = category_pixels(frames)
    assert px.shape[0] == 2 and px[0, SOFA] == 20 and px[0, TV] == 0 and px[1, TV] == 3
    assert (px.sum(axis=1) == 64 * 64).all()


def test_a_19_pixel_blob_is_not_visible_and_20_is():
    blob19 = frame_with((SOFA, slice(0, 1), slice(0, 19)))
    blob20 = frame_with((SOFA, slice(0, 2), slice(0, 10)))
    # gt 20 pixels, predicted 19: visible only in the gt -> a miss (fn), not a hit
    r = evaluate([blob20], [blob19])
    assert r["visibility"][SOFA] == {"tp": 0, "fp": 0, "fn": 1}
    assert r["visibility_recall"] == 0.0 and r["visibility_f1"] == 0.0 and math.isnan(r["visibility_precision"])
    # 19 pixels in both: visible in neither, so no pair counts at all
    r = evaluate([blob19], [blob19])
    assert SOFA not in r["visibility"] and math.isnan(r["visibility_f1"])
    r = evaluate([blob20], [blob20])
    assert r["visibility"][SOFA] == {"tp": 1, "fp": 0, "fn": 0} and r["visibility_f1"] == 1.0


def test_visibility_micro_f1_and_per_category_by_hand():
    big = (slice(0, 8), slice(0, 8))  # 64 pixels
    # frame 0: gt sofa + tv, predicted sofa + bed   frame 1: gt tv, predicted tv   frame 2: gt bed, predicted nothing
    gt = [frame_with((SOFA, *big), (TV, slice(10, 18), slice(0, 8))), frame_with((TV, *big)), frame_with((BED, *big))]
    pred = [frame_with((SOFA, *big), (BED, slice(10, 18), slice(0, 8))), frame_with((TV, *big)), frame_with()]
    r = evaluate(gt, pred)
    assert r["visibility"][SOFA] == {"tp": 1, "fp": 0, "fn": 0}
    assert r["visibility"][TV] == {"tp": 1, "fp": 0, "fn": 1}  # seen in gt frame 0, missed there
    assert r["visibility"][BED] == {"tp": 0, "fp": 1, "fn": 1}  # predicted in frame 0, missed in frame 2
    # micro: tp 2, fp 1, fn 2 -> precision 2/3, recall 1/2, F1 4/7
    assert r["visibility_precision"] == pytest.approx(2 / 3) and r["visibility_recall"] == pytest.approx(1 / 2)
    assert r["visibility_f1"] == pytest.approx(4 / 7)
    assert visibility_scores(r["visibility"][TV]) == {"precision": 1.0, "recall": 0.5, "f1": pytest.approx(2 / 3)}
    # the targets subset: [sofa, tv] -> tp 2, fp 0, fn 1; an absent category adds nothing
    assert visibility_over(r, [SOFA, TV, PLANT]) == pytest.approx(4 / 5)
    assert math.isnan(visibility_over(r, [PLANT]))
    # wall is everywhere but is structure, not an object: not in the visibility counts
    assert WALL not in r["visibility"]


def test_category_seen_in_gt_and_never_predicted_has_recall_zero():
    gt = [frame_with((PLANT, slice(0, 10), slice(0, 10))) for _ in range(3)]
    pred = [frame_with() for _ in range(3)]
    r = evaluate(gt, pred)
    v = visibility_scores(r["visibility"][PLANT])
    assert v["recall"] == 0.0 and v["f1"] == 0.0 and math.isnan(v["precision"])
    assert r["visibility"][PLANT]["fn"] == 3


def test_downsample_mask_is_the_agents_10x10_map():
    # a 13 x 7 block at an odd place: the 64 -> 10 area weights split pixels between blocks (6.4 pixels a block)
    f = frame_with((SOFA, slice(5, 18), slice(30, 37)))
    m = downsample_mask(f, SOFA)
    assert m.shape == (10, 10) and m.dtype == np.float32
    assert m.sum() == pytest.approx(13 * 7 / 6.4**2, rel=1e-5)  # area averaging keeps the mass
    # block (1, 5) covers rows 6.4-12.8, cols 32-38.4; the blob covers rows 6.4-12.8 and cols 32-37 of it
    assert m[1, 5] == pytest.approx(5 / 6.4, rel=1e-5)
    # exactly what the env's TargetMaskDepth wrapper computes for the target channel
    expected = cv2.resize((f == SOFA).astype(np.float32), (10, 10), interpolation=cv2.INTER_AREA)
    assert np.array_equal(m, expected)
    wrappers = pytest.importorskip("objsearch.sim.wrappers")
    shim = wrappers.TargetMaskDepth.__new__(wrappers.TargetMaskDepth)
    shim.size, shim.semantic_key = 10, "semantic"
    obs = shim.observation({"semantic": f, "target": SOFA, "depth": np.ones((64, 64), np.float32)})
    assert np.array_equal(obs[0], m)
    tables = pytest.importorskip("objsearch_agents.house.tables")
    _, masks, pixels, _ = tables.frame_features(f, np.ones((64, 64), np.float32))
    assert np.array_equal(masks[SOFA], m) and pixels[SOFA] == 13 * 7


def test_mask10_iou_by_hand():
    # gt sofa: the left half of the frame (5 of 10 block columns); predicted: the left quarter (2.5 columns)
    gt = frame_with((SOFA, slice(0, 64), slice(0, 32)))
    pred = frame_with((SOFA, slice(0, 64), slice(0, 16)))
    r = evaluate([gt], [pred])
    g, p = downsample_mask(gt, SOFA), downsample_mask(pred, SOFA)
    assert g.sum() == pytest.approx(50) and p.sum() == pytest.approx(25)
    # pred inside gt: min sums to the pred's mass, max to the gt's -> 25 / 50
    assert r["mask10_iou"][SOFA] == pytest.approx(0.5, rel=1e-5)
    assert r["iou"][SOFA] == pytest.approx(0.5)
    # a category only predicted does not get a map IoU (no gt pixels), as for the pixel IoU
    r = evaluate([gt], [frame_with((SOFA, slice(0, 64), slice(0, 32)), (TV, slice(0, 4), slice(40, 50)))])
    assert TV not in r["mask10_iou"] and r["mask10_iou"][SOFA] == pytest.approx(1.0)


def test_target_metrics_and_accumulation_over_batches():
    rng = np.random.default_rng(0)
    labels = np.array([WALL, SOFA, TV, BED, PLANT])
    gt = labels[rng.integers(0, 5, (6, 64, 64))]
    pred = np.where(rng.random((6, 64, 64)) < 0.7, gt, labels[rng.integers(0, 5, (6, 64, 64))])
    depth = np.ones((6, 64, 64), np.float32)
    whole, parts = Evaluation(30.0), Evaluation(30.0)
    whole.update(gt, pred, depth, depth)
    parts.update(gt[:2], pred[:2], depth[:2], depth[:2])
    parts.update(gt[2:], pred[2:], depth[2:], depth[2:])
    a, b = whole.result(), parts.result()
    assert a["visibility"] == b["visibility"] and a["visibility_f1"] == b["visibility_f1"]
    assert a["mask10_iou"] == pytest.approx(b["mask10_iou"]) and a["mask10_miou"] == pytest.approx(b["mask10_miou"])
    t = target_metrics(a, [SOFA, TV])
    assert set(t) == {
        "miou_targets",
        "visibility_f1_targets",
        "mask10_iou_targets",
        "stop_precision_targets",
        "stop_recall_targets",
    }
    assert a["near"] == b["near"], "the near detections add up over batches too"
    assert t["miou_targets"] == pytest.approx((a["iou"][SOFA] + a["iou"][TV]) / 2)
    assert t["mask10_iou_targets"] == pytest.approx((a["mask10_iou"][SOFA] + a["mask10_iou"][TV]) / 2)
    assert t["visibility_f1_targets"] == pytest.approx(visibility_over(a, [SOFA, TV]))
    text = format_table(a, [SOFA])
    assert "vis F1" in text and "visibility (>= 20 pixels)" in text


def test_quality_targets_are_reported_met_or_missed_by_how_much():
    assert target_status(0.462, (">=", 0.60)) == "missed by 0.138"
    assert target_status(0.05, ("<=", 0.06)) == "met" and target_status(0.6, (">=", 0.6)) == "met"
    assert target_status(float("nan"), (">=", 0.6)) == "not measured"
    text = format_targets({"miou_targets": 0.462, "miou": 0.5, "visibility_f1": 0.9, "depth_absrel": 0.078})
    assert len(text.splitlines()) == len(QUALITY_TARGETS)
    assert "miou_targets" in text and "missed by 0.138" in text and "missed by 0.018" in text
    assert "not measured" in format_targets({})
