"""The progress of an agent with several training runs: one bar over every run, whose label
says which run plays ("run 2/3") and whose count and ETA cover the whole evaluation."""

import re

import pytest

from objsearch.eval import runner
from objsearch.eval.config import EvalConfig
from objsearch.eval.runner import evaluate

AGENT = "tests.eval.agents_for_tests:RunsAgent"  # three training runs


def progress_lines(text: str) -> list[str]:
    """The progress bar's status lines (not the line naming each run's checkpoint)."""
    return [line for line in text.splitlines() if line.startswith(AGENT) and " ep" in line]


def test_a_multi_run_evaluation_counts_every_run_and_names_the_one_playing(capsys):
    evaluate(EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1,), episodes=10), workers=1, batch=4)
    lines = progress_lines(capsys.readouterr().err)  # stderr is no terminal here: one line per status
    assert lines, "no progress line"
    for line in lines:
        assert re.search(r": \d+/30 ep, ", line), line  # 3 runs x 10 episodes, never one run's 10
    for k in (1, 2, 3):
        assert any(f", run {k}/3: " in line for line in lines), f"no line for run {k}/3: {lines}"
    assert "run 3/3: 30/30 ep" in lines[-1]
    assert all(": 0/10 ep" not in line for line in lines)  # the count does not restart at each run


def test_a_resumed_multi_run_evaluation_starts_its_count_at_what_was_kept(tmp_path, capsys, monkeypatch):
    config = EvalConfig(agent=AGENT, splits=("unseen-goals",), seeds=(1,), episodes=4)
    out = tmp_path / "r.json"
    real = runner.play_units

    def cut_at_the_second_run(plan, play, *args, **kwargs):
        if plan.plays[play].config.training_run == 1:
            raise KeyboardInterrupt("cut")
        return real(plan, play, *args, **kwargs)

    monkeypatch.setattr(runner, "play_units", cut_at_the_second_run)
    with pytest.raises(KeyboardInterrupt):
        evaluate(config, progress=False, out=out)
    monkeypatch.setattr(runner, "play_units", real)
    capsys.readouterr()
    evaluate(config, out=out)
    lines = progress_lines(capsys.readouterr().err)
    assert lines[0].startswith(f"{AGENT} on gridworld, run 1/3: 4/12 ep"), lines  # run 1's 4 kept
    assert "run 3/3: 12/12 ep" in lines[-1]


def test_one_run_keeps_its_plain_label(capsys):
    evaluate(EvalConfig(agent="random", splits=("unseen-goals",), seeds=(1,), episodes=5))
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("random on gridworld")]
    assert lines and all(re.match(r"random on gridworld: \d+/5 ep, ", line) for line in lines), lines
