"""``objsearch perception dataset -> train -> eval --json`` in subprocesses, with tiny budgets."""

import json
import os
import subprocess
import sys

from objsearch.cli import main


def _run(*args, cwd):
    env = dict(os.environ, MUJOCO_GL=os.environ.get("MUJOCO_GL", "egl"), OMP_NUM_THREADS="1")
    return subprocess.run(
        [sys.executable, "-m", "objsearch.cli", "perception", *args],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_dataset_train_eval_json(tmp_path, capsys):
    data, run = tmp_path / "data", tmp_path / "run"
    r = _run(
        "dataset",
        "--out",
        str(data),
        "--train-houses",
        "1",
        "--val-houses",
        "0",
        "--test-houses",
        "1",
        "--test-seen-shapes-houses",
        "1",
        "--poses-per-house",
        "16",
        "--eval-poses-per-house",
        "8",
        "--size",
        "32",
        "--quiet",
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr
    assert "train: 16 frames from 1 houses" in r.stdout and (data / "manifest.json").exists()
    assert "test-seen-shapes: 8 frames from 1 houses" in r.stdout
    small = [
        "--set",
        "model.stem=8",
        "--set",
        "model.mid=8",
        "--set",
        "model.deep=8",
        "--set",
        "model.aspp=8",
        "--set",
        "model.skip=8",
        "--set",
        "model.decoder=8",
    ]
    r = _run(
        "train",
        "--data",
        str(data),
        "--out",
        str(run),
        "--steps",
        "3",
        "--batch-size",
        "8",
        "--threads",
        "1",
        "--quiet",
        *small,
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr
    assert {"model.pt", "state.pt", "config.json", "log.csv"} <= {p.name for p in run.iterdir()}
    assert "step,epoch" in (run / "log.csv").read_text()
    r = _run("eval", "--checkpoint", str(run / "model.pt"), "--data", str(data), "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout.strip().splitlines()[-1])
    assert {
        "miou",
        "miou_targets",
        "depth_absrel",
        "depth_rmse",
        "depth_delta1",
        "pixel_accuracy",
        "per_category",
    } <= set(result)
    assert result["split"] == "test" and result["frames"] == 8
    # the large-house tier's small targets are scored apart, when the frames hold any
    assert set(result["small_targets"]) <= set(result["per_category"])
    assert ("miou_small_targets" in result) == bool(result["small_targets"])
    r = _run(
        "eval", "--checkpoint", str(run / "model.pt"), "--data", str(data), "--split", "test-seen-shapes", cwd=tmp_path
    )
    assert r.returncode == 0 and "test-seen-shapes: 8 frames from 1 houses" in r.stdout, r.stderr
    # bad input: exit 2 with a message naming it (in-process: no second interpreter start)
    assert main(["perception", "eval", "--checkpoint", str(tmp_path / "missing.pt"), "--data", str(data)]) == 2
    assert "missing.pt" in capsys.readouterr().err
    assert main(["perception", "train", "--data", str(data), "--out", str(run), "--set", "lr=fast"]) == 2
    assert "lr takes a float" in capsys.readouterr().err
    wrong = tmp_path / "wrong-suite"
    assert main(["perception", "dataset", "--suite", "house-multi", "--out", str(wrong)]) == 2
    assert "house-gen or house-large, not 'house-multi'" in capsys.readouterr().err and not wrong.exists()
