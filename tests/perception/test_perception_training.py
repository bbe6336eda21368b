"""The training path learns: a tiny network overfits a few dozen frames of one house."""

import dataclasses

import torch

from objsearch.perception.config import TrainConfig
from objsearch.perception.dataset import load_split
from objsearch.perception.inference import Predictor, evaluate
from objsearch.perception.model import ModelConfig
from objsearch.perception.train import TrainRun

TINY_MODEL = ModelConfig(stem=16, mid=32, deep=48, aspp=32, aspp_rates=(2, 4), skip=16, decoder=32)  # trains in seconds


def _config(data, **changes) -> TrainConfig:
    base = TrainConfig(
        data=str(data),
        steps=120,
        batch_size=16,
        lr=1e-2,
        warmup_steps=10,
        augment=False,
        class_weighting="enet",
        val_frames=0,
        log_every=40,
        checkpoint_every=1000,
        device="cpu",
        threads=1,
        model=TINY_MODEL,
    )
    return dataclasses.replace(base, **changes)


def test_overfits_a_tiny_rendered_set(tiny_dataset, tmp_path):
    frames = load_split(tiny_dataset, "train", max_frames=16)
    run = TrainRun(_config(tiny_dataset, max_train_frames=16), tmp_path / "run")
    before = evaluate(Predictor(run.model, run.settings, "before", "cpu"), frames)
    assert run.run(progress=False)  # 120 steps of 16 frames at 32x32: ~10 s on one core
    after = evaluate(Predictor.from_checkpoint(tmp_path / "run" / "model.pt", "cpu"), frames)
    losses = [row["loss"] for row in run.rows]
    assert losses[-1] < 0.1 * losses[0]
    # measured (seed 0): pixel accuracy 0.96, mIoU 0.64 over 15 object categories (some 1-12 pixels
    # large), 0.79 over the 8 with >= 50 pixels, AbsRel 0.03; before training: mIoU ~0, AbsRel ~0.6
    big = [c for c in after["counted"] if after["gt_pixels"][c] >= 50]
    assert after["pixel_accuracy"] > 0.93 and after["miou"] > 0.5, after
    assert len(big) >= 5 and sum(after["iou"][c] for c in big) / len(big) > 0.65, after
    assert after["depth_absrel"] < 0.1 < before["depth_absrel"]
    assert before["miou"] < 0.1


def test_resumed_run_equals_uninterrupted_run(tiny_dataset, tmp_path):
    config = _config(tiny_dataset, steps=4, batch_size=8, augment=True, class_weighting="enet", checkpoint_every=2)
    straight = TrainRun(config, tmp_path / "a")
    straight.run(progress=False)
    first = TrainRun(config, tmp_path / "b")
    for _ in range(2):
        first.train_step()
    first.save()
    resumed = TrainRun(config, tmp_path / "b")
    assert resumed.step == 2
    resumed.run(progress=False)
    for name, tensor in straight.model.state_dict().items():
        assert torch.equal(tensor, resumed.model.state_dict()[name]), name
    assert (tmp_path / "a" / "config.json").exists() and (tmp_path / "a" / "log.csv").exists()
    assert TrainConfig.load(tmp_path / "a" / "config.json") == config


def test_log_rows_reach_log_csv_before_any_checkpoint(tiny_dataset, tmp_path, monkeypatch):
    """A long run shows its curve as it goes, not only every checkpoint_every steps."""
    import csv

    run = TrainRun(_config(tiny_dataset, steps=3, log_every=1), tmp_path / "run")
    monkeypatch.setattr(run, "save", lambda: None)  # no checkpoint at all
    assert run.run(progress=False)
    rows = list(csv.DictReader((tmp_path / "run" / "log.csv").open()))
    assert [r["step"] for r in rows] == ["1", "2", "3"] and not (tmp_path / "run" / "model.pt").exists()


def test_init_starts_a_run_from_a_checkpoints_weights_and_refuses_another_network(tiny_dataset, tmp_path):
    import pytest

    from objsearch.errors import UserError

    first = TrainRun(_config(tiny_dataset, steps=3), tmp_path / "a")
    assert first.run(progress=False)
    init = str(tmp_path / "a" / "model.pt")
    second = TrainRun(_config(tiny_dataset, steps=3, seed=7, init=init), tmp_path / "b")
    for name, tensor in first.model.state_dict().items():
        assert torch.equal(tensor, second.model.state_dict()[name]), name  # not seed 7's random weights
    assert second.run(progress=False)
    assert TrainConfig.load(tmp_path / "b" / "config.json").init == init  # the run records where it started
    wider = dataclasses.replace(TINY_MODEL, decoder=48)
    with pytest.raises(UserError, match="init=.*decoder"):
        TrainRun(_config(tiny_dataset, init=init, model=wider), tmp_path / "c")
    from objsearch.perception.inference import save_checkpoint
    from objsearch.sim.camera import AGENT_CAMERA

    save_checkpoint(tmp_path / "other-camera.pt", first.model, AGENT_CAMERA)  # the tiny set is rendered smaller
    with pytest.raises(UserError, match="init=.*other-camera.pt"):
        TrainRun(_config(tiny_dataset, init=str(tmp_path / "other-camera.pt")), tmp_path / "d")
