"""``objsearch generate`` in a subprocess."""

import json
import os
import subprocess
import sys

import pytest

CMD = [sys.executable, "-m", "objsearch.cli", "generate"]
ENV = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}


def test_generate_writes_houses(tmp_path):
    r = subprocess.run(
        CMD + ["--seed", "11", "--num", "2", "--out", str(tmp_path), "--rooms", "small", "--quiet"],
        capture_output=True,
        text=True,
        env=ENV,
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    for hid in ("train_000011", "train_000012"):
        d = tmp_path / hid
        assert (d / "house.xml").exists() and (d / "preview.png").exists()
        spec = json.loads((d / "spec.json").read_text())
        assert spec["size_class"] == "small" and spec["house_id"] == hid
        assert spec["generator_version"] == "house-gen-2"  # the default generator
    table = json.loads((tmp_path / "categories.json").read_text())
    assert table["ids"]["background"] == 0 and len(table["ids"]) >= 55


@pytest.mark.parametrize("args", [["--rooms", "huge"], ["--num", "0"], ["--seed", "-3"]])
def test_bad_arguments_exit_2(tmp_path, args):
    r = subprocess.run(CMD + ["--out", str(tmp_path)] + args, capture_output=True, text=True, env=ENV, timeout=60)
    assert r.returncode == 2 and "generate" in r.stderr
