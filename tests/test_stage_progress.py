"""Long work with no count to show says it is under way (``objsearch.progress.stage``), and a
long ``objsearch leaderboard add`` says what it is doing; quick work stays silent."""

import json
import time

from objsearch import progress
from objsearch.cli import main
from objsearch.eval.runner import EvalConfig, evaluate


def test_a_stage_is_silent_when_quick_and_says_when_it_started_and_ended_when_slow(capsys):
    with progress.stage("quick work", delay=5):
        pass
    assert capsys.readouterr().err == ""
    with progress.stage("slow work", delay=0.05):
        time.sleep(0.3)
    lines = capsys.readouterr().err.splitlines()
    assert lines[0] == "slow work ..." and lines[-1].startswith("slow work: done in ")


def test_a_slow_leaderboard_add_says_what_it_is_doing(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(progress, "STAGE_DELAY_S", 0)  # every step counts as slow
    board = tmp_path / "board"
    for agent in ("random", "oracle"):
        results = evaluate(EvalConfig(agent=agent, splits=("unseen-goals",), seeds=(1,)), progress=False)
        (tmp_path / f"{agent}.json").write_text(json.dumps(results))
        assert (
            main(["leaderboard", "--dir", str(board), "add", str(tmp_path / f"{agent}.json"), "--create", "--partial"])
            == 0
        )
    err = capsys.readouterr().err
    assert f"checking {tmp_path / 'oracle.json'} ..." in err and f"checking {tmp_path / 'oracle.json'}: done in" in err
    assert "checking the stored entries: 1/1 entry" in err  # the other entries, against a duplicate
    assert "rendering the pages: done in" in err
