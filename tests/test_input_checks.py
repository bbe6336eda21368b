"""Small lies closed: input that was accepted and silently gave a wrong result, or ended in a
traceback, is refused with one line naming it and the fix (exit 2)."""

import argparse
import os
import subprocess
import sys

import gymnasium
import numpy as np
import pytest

from objsearch.cli import main
from objsearch.cliargs import positive_int, seed_list
from objsearch.eval.cli import build_eval_parser


@pytest.mark.parametrize(
    "text, message",
    [
        ("1,1", "seed 1 is given twice in '1,1'; give each seed once, e.g. 1"),
        ("1,5,1,5", "seed 1 is given twice"),
        ("-1", "seeds are integers >= 0; -1 is not"),
        ("3,-2", "-2 is not"),
    ],
)
def test_duplicate_and_negative_seeds_are_refused(text, message):
    with pytest.raises(argparse.ArgumentTypeError, match=message):
        seed_list(text)


def test_the_eval_command_refuses_duplicate_seeds_with_exit_2(capsys):
    with pytest.raises(SystemExit) as exit_:
        build_eval_parser().parse_args(["--suite", "gridworld", "--seeds", "1,1"])
    assert exit_.value.code == 2
    assert "--seeds: seed 1 is given twice" in capsys.readouterr().err


def test_positive_counts_say_what_they_expect_for_zero_and_negatives():
    for text in ("0", "-1", "x"):
        with pytest.raises(
            argparse.ArgumentTypeError, match=rf"expected a positive integer \(an integer >= 1\), got '{text}'"
        ):
            positive_int(text)
    assert positive_int("3") == 3


@pytest.mark.parametrize(
    "argv", [["train", "--agent", "dqn", "--episodes", "0"], ["generate", "--num", "0", "--out", "x"]]
)
def test_zero_training_episodes_or_houses_is_refused(argv, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    assert "expected a positive integer" in capsys.readouterr().err


def test_cache_verify_of_a_missing_folder_a_file_or_an_empty_folder_is_not_all_intact(tmp_path, capsys):
    (tmp_path / "afile").write_text("")
    (tmp_path / "empty").mkdir()
    for folder, message in [
        (tmp_path / "missing", "does not exist"),
        (tmp_path / "afile", "is a file, not a folder"),
        (tmp_path / "empty", "no caches in"),
    ]:
        assert main(["cache", "verify", "--cache-dir", str(folder)]) == 2
        err = capsys.readouterr().err
        assert str(folder) in err and message in err and "all intact" not in err


BAD_ACTIONS = [1.5, np.float32(1.0), "1", None, np.array([1]), -1, 99]


def test_the_grid_world_rejects_non_integer_and_out_of_range_actions():
    env = gymnasium.make("ObjSearch/GridWorld-v0").unwrapped
    env.reset(seed=0)
    for action in BAD_ACTIONS:
        with pytest.raises(ValueError, match=r"invalid action .*; expected an integer in 0\.\.3 \(0 up, 1 down"):
            env.step(action)
    env.step(np.int64(1))  # numpy integers are integers


@pytest.fixture
def house_env():
    from objsearch.sim.env import HouseEnv
    from objsearch.sim.world import HouseRef

    env = HouseEnv([HouseRef(seed=3)], mode="live")  # live: no cache to build for two steps
    yield env
    env.close()


def test_the_house_env_rejects_what_the_grid_world_rejects(house_env):
    house_env.reset(seed=0)
    for action in BAD_ACTIONS:
        with pytest.raises(ValueError, match=r"invalid action .*; expected an integer in 0\.\.5 \(0 move_ahead"):
            house_env.step(action)
    house_env.step(np.int64(1))


def test_a_bad_mujoco_gl_does_not_stop_commands_that_render_nothing(tmp_path):
    env = {**os.environ, "MUJOCO_GL": "bogus"}
    run = lambda *argv: subprocess.run(  # noqa: E731
        [sys.executable, "-m", "objsearch.cli", *argv], env=env, capture_output=True, text=True, timeout=120
    )
    assert run("eval", "--help").returncode == 0
    grid = run("eval", "--suite", "gridworld", "--split", "seen-goals", "--seeds", "1", "--quiet")
    assert grid.returncode == 0 and "Traceback" not in grid.stderr, grid.stderr


def test_a_training_seed_torch_cannot_take_is_refused(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["train", "--agent", "dqn", "--seed", str(2**64)])
    assert exit_.value.code == 2
    assert "expected a seed in 0..4294967295" in capsys.readouterr().err


def test_an_empty_out_is_refused_not_taken_as_no_out(capsys):
    assert main(["eval", "--suite", "gridworld", "--out", ""]) == 2
    assert "--out is empty" in capsys.readouterr().err
