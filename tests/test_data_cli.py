"""``objsearch data rebuild``, ``objsearch cache`` (now in objsearch/perception/cache_cli.py)
and the old ``python -m`` entry points, which name the commands that replaced them."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from objsearch.cli import main
from objsearch.sim import suite_build
from objsearch.sim import suites as sim_suites

BIN = Path(sys.executable).parent


def test_data_rebuild_suites_is_suite_rebuild(monkeypatch, tmp_path, capsys):
    """One implementation behind both commands: the same file and the same report."""
    built = {"suite": "house-single", "version": "house-single-v1", "houses": {}}
    monkeypatch.setattr(sim_suites, "DATA_DIR", tmp_path)
    monkeypatch.setattr(suite_build, "build_suite", lambda name, cache_dir=None: {**built, "suite": name})
    assert main(["data", "rebuild", "suites", "house-single", "--cache-dir", str(tmp_path)]) == 0
    via_data = (tmp_path / "house-single.json").read_text(), capsys.readouterr().out
    (tmp_path / "house-single.json").unlink()
    assert main(["suite", "rebuild", "house-single", "--cache-dir", str(tmp_path)]) == 0
    assert ((tmp_path / "house-single.json").read_text(), capsys.readouterr().out) == via_data
    assert via_data[0] == json.dumps(built) + "\n"
    with pytest.raises(SystemExit) as exit_:
        main(["data", "rebuild", "suites", "house-x"])
    assert exit_.value.code == 2 and "invalid choice: 'house-x'" in capsys.readouterr().err


@pytest.mark.parametrize("kind", ["gridworld", "assets"])
def test_data_rebuild_refuses_a_file_as_out(tmp_path, capsys, kind):
    (tmp_path / "file").write_text("x")
    assert main(["data", "rebuild", kind, "--out", str(tmp_path / "file")]) == 2
    assert f"--out {tmp_path / 'file'} is a file" in capsys.readouterr().err
    assert (tmp_path / "file").read_text() == "x"


def test_cache_command_is_unchanged(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["cache", "--help"])
    assert exit_.value.code == 0
    help_text = capsys.readouterr().out
    assert all(action in help_text for action in ("build", "list", "verify", "clear"))
    with pytest.raises(SystemExit) as exit_:
        main(["cache", "build", "--help"])
    assert "--observation" in capsys.readouterr().out


@pytest.mark.parametrize(
    "module, command",
    [
        ("objsearch.gridworld.dataset", "objsearch data rebuild gridworld"),
        ("objsearch.house.assets", "objsearch data rebuild assets"),
        ("objsearch.eval.agent_io", "objsearch data rebuild agent-io-doc [--check]"),
        ("objsearch_agents.grg_plot", "objsearch plot grg RUN"),
        ("objsearch_agents.house.grg_figure", "objsearch plot grg RUN"),
    ],
)
def test_old_entry_points_name_the_new_command(tmp_path, module, command):
    out = subprocess.run([sys.executable, "-m", module, str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 1 and command in out.stderr, out.stderr
    assert not list(tmp_path.iterdir())  # and did nothing


def test_plot_grg_in_a_subprocess(tmp_path):
    """As a user runs it: the shipped grid-world checkpoint gives a PNG; a bad RUN exits 2 naming it."""
    checkpoint = Path(__file__).resolve().parents[1] / "agents" / "checkpoints" / "gridworld" / "hrl_grg"
    out = subprocess.run(
        [str(BIN / "objsearch"), "plot", "grg", str(checkpoint), "--out", str(tmp_path / "g.png")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "g.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and "chain recovery" in out.stdout
    bad = subprocess.run(
        [str(BIN / "objsearch"), "plot", "grg", str(tmp_path / "nowhere")], capture_output=True, text=True, timeout=120
    )
    assert bad.returncode == 2 and "Traceback" not in bad.stderr
    assert bad.stderr.strip().splitlines() == [
        f"objsearch: error: no GRG at {tmp_path / 'nowhere'}: give a checkpoint or "
        "run folder with a grg.npz (e.g. agents/checkpoints/gridworld/hrl_grg) "
        "or a grg.npz file"
    ]
