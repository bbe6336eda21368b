"""``objsearch perception eval --json`` reports the quality targets' figures, and the shipped
checkpoint's stored evaluation (``eval_test.json``) holds them consistently."""

import json
import math

import pytest

from objsearch.cli import main
from objsearch.perception.dataset import build_dataset
from objsearch.perception.inference import SHIPPED_CHECKPOINT

TARGET_KEYS = {"miou", "miou_targets", "visibility_f1", "depth_absrel"}
NEW_KEYS = {
    "visibility_precision",
    "visibility_recall",
    "visibility_f1_targets",
    "mask10_iou_targets",
    "mask10_miou",
    "visibility_per_category",
    "mask10_per_category",
    "quality_targets",
    "targets",
}


def micro_f1(rows):
    tp, fp, fn = (sum(r[k] for r in rows) for k in ("tp", "fp", "fn"))
    return 2 * tp / (2 * tp + fp + fn)


def test_eval_json_reports_the_quality_metrics_beside_their_targets(tmp_path, capsys):
    build_dataset(tmp_path, seed=0, eval_poses_per_house=24, houses={"train": 0, "val": 0, "test": 1}, progress=False)
    assert main(["perception", "eval", "--data", str(tmp_path), "--device", "cpu", "--json"]) == 0
    out = capsys.readouterr().out
    result = json.loads(out.strip().splitlines()[-1])
    assert TARGET_KEYS | NEW_KEYS <= set(result) and result["frames"] == 24
    assert result["visible_pixels"] == 20 and len(result["targets"]) == 25
    assert result["visibility_f1"] == pytest.approx(micro_f1(result["visibility_per_category"].values()))
    # the human part names every target beside its figure
    for line in ("target >= 0.60", "target >= 0.40", "target >= 0.85", "target <= 0.06"):
        assert line in out
    assert set(result["quality_targets"]) == TARGET_KEYS


def test_stored_evaluation_holds_the_quality_metrics():
    stored = json.loads((SHIPPED_CHECKPOINT.parent / "eval_test.json").read_text())
    assert TARGET_KEYS | NEW_KEYS <= set(stored) and stored["frames"] == 2000
    per = stored["visibility_per_category"]
    assert stored["visibility_f1"] == pytest.approx(micro_f1(per.values()))
    targets = [per[n] for n in stored["targets"] if n in per]
    assert stored["visibility_f1_targets"] == pytest.approx(micro_f1(targets))
    mask10 = [stored["mask10_per_category"][n] for n in stored["targets"] if n in stored["mask10_per_category"]]
    assert stored["mask10_iou_targets"] == pytest.approx(sum(mask10) / len(mask10), abs=1e-3)  # stored rounded
    assert not any(isinstance(v, float) and math.isnan(v) for v in stored.values())
