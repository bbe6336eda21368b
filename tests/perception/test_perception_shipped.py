"""The shipped perception checkpoint: the default everywhere, described by its files, and
still predicting what its evaluation says on a test house."""

import json

from objsearch.perception.dataset import build_dataset, load_split
from objsearch.perception.inference import SHIPPED_CHECKPOINT, Predictor, evaluate
from objsearch.sim.camera import AGENT_CAMERA


def test_shipped_checkpoint_is_the_default_and_matches_its_files():
    predictor = Predictor.from_checkpoint(device="cpu")
    assert predictor.settings == AGENT_CAMERA  # the camera the house suites' agents see
    folder = SHIPPED_CHECKPOINT.parent
    recorded = json.loads((folder / "eval_test.json").read_text())
    assert recorded["checkpoint_key"] == predictor.key  # the evaluation describes these weights
    assert "objsearch perception train" in (folder / "command.txt").read_text()


def test_shipped_checkpoint_on_frames_of_a_test_house(tmp_path):
    """50 fresh frames of the first test house (unseen instances): the network still segments
    the structure and gets depth about right (the full figures: docs/perception.md)."""
    build_dataset(tmp_path, seed=0, eval_poses_per_house=50, houses={"train": 0, "val": 0, "test": 1}, progress=False)
    result = evaluate(Predictor.from_checkpoint(device="cpu"), load_split(tmp_path, "test"))
    assert result["pixel_accuracy"] > 0.85 and result["depth_absrel"] < 0.15, result
