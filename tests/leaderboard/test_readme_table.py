"""The results table at the top of the project's README.md is the one the leaderboard generates
(``objsearch.leaderboard.headline``), and ``objsearch leaderboard render`` rewrites it."""

import copy
import json
import shutil
from pathlib import Path

import pytest

from objsearch.errors import UserError
from objsearch.leaderboard.headline import BEGIN, END, headline_tables, with_headline
from objsearch.leaderboard.render import render

ROOT = Path(__file__).resolve().parents[2]


def test_the_readme_results_table_matches_the_leaderboard(tmp_path):
    """As ``objsearch leaderboard render`` rewrites it from the stored entries: a README edited by
    hand, or an entry added without rendering, fails here."""
    assert BEGIN in (ROOT / "README.md").read_text(), "README.md holds the generated results table"
    shutil.copytree(ROOT / "leaderboard" / "submissions", tmp_path / "leaderboard" / "submissions")
    shutil.copy(ROOT / "README.md", tmp_path / "README.md")
    render(tmp_path / "leaderboard")
    assert (tmp_path / "README.md").read_text() == (ROOT / "README.md").read_text(), (
        "the README's results table differs from the leaderboard's; run: objsearch leaderboard render"
    )


def entry(suite, agent, splits, runs=0, perception_key=None):
    """A stored result as the table reads it: suite, agent, seeds, config, split summaries."""
    config = {"suite_config": {"perception_key": perception_key} if perception_key else {}}
    results = {"suite": suite, "agent": agent, "seeds": [1, 5], "config": config, "splits": {}}
    for split, (sr, spl) in splits.items():
        episodes = 200 * max(runs, 1)
        results["splits"][split] = {"sr": sr, "spl": spl, "sr_ci": [sr - 0.05, sr + 0.05], "episodes": episodes}
    if runs:
        results["training_runs"] = [{"seed": seed, "env_steps": 1000} for seed in range(runs)]
    return results


def test_the_table_shows_gt_reference_entries_and_marks_multi_run_ones():
    submissions = [
        ("frontier", entry("house-single", "frontier", {"seen-goals": (1.0, 0.53), "unseen-goals": (0.99, 0.66)})),
        ("a3c", entry("house-single", "a3c", {"seen-goals": (0.88, 0.45)}, runs=3)),
        ("a3c_predicted", entry("house-single", "a3c", {"seen-goals": (0.11, 0.11)}, perception_key="abc")),
        ("my_agent", entry("house-single", "my_agent", {"seen-goals": (0.22, 0.22)})),
        ("hrl_grg", entry("gridworld", "hrl_grg", {"seen-goals": (0.68, 0.45)})),
        ("oracle", entry("house-gen-v2-shuffled", "oracle", {"test-seen": (0.33, 0.33)})),  # not a headline suite
    ]
    table = headline_tables(submissions)
    assert "| `frontier` | 1.00 / 0.53 | 0.99 / 0.66 | – |" in table
    # its 3 runs on ground truth, and under them, in italics, its entry on the predictions
    assert "| `a3c` | 0.88 / 0.45 ×3<br>*0.11 / 0.11* | – |" in table
    assert "| `hrl_grg` | 0.68 / 0.45 | – | – |" in table
    assert table.index("`frontier`") < table.index("`a3c`"), "rows in HEADLINE_AGENTS order"
    assert "*predicted* and the italic second line of a cell: the shipped perception network's" in table
    for absent in ("0.22", "0.33", "my_agent", "oracle` |", "<br>*predicted*"):  # no predicted column in Houses
        assert absent not in table
    assert "100 episodes a split, each played with seeds 1, 5" in table
    assert "±0.05 to ±0.05 SR" in table


def test_the_large_tier_shows_predictions_beside_ground_truth_once_it_has_them():
    gt_only = [("frontier", entry("house-large", "frontier", {"test": (0.70, 0.21)}))]
    assert "*predicted*" not in headline_tables(gt_only)
    both = gt_only + [
        ("frontier_predicted", entry("house-large", "frontier", {"test": (0.10, 0.03)}, perception_key="abc")),
        ("object_prior_frontier", entry("house-large", "object_prior_frontier", {"test": (0.94, 0.30)})),
        ("mine_predicted", entry("house-large", "mine", {"test": (0.5, 0.5)}, perception_key="abc")),  # not headline
    ]
    table = headline_tables(both)
    header = next(line for line in table.splitlines() if line.startswith("| agent |"))
    # a predicted column beside the suite's gt one, only where the suite has a predicted entry
    assert header.count("<br>*predicted*") == 1 and header.index("house-large<br>test |") < header.index("*predicted*")
    assert "| `frontier` | 0.70 / 0.21 | 0.10 / 0.03 |" in table
    assert "| `object_prior_frontier` | 0.94 / 0.30 | – |" in table and "mine" not in table
    assert "columns marked *predicted*: the shipped perception network's" in table


def test_render_rewrites_only_the_text_between_the_markers(tmp_path, oracle_results):
    board = tmp_path / "leaderboard"
    (board / "submissions" / "gridworld").mkdir(parents=True)
    full = copy.deepcopy(oracle_results)
    full.pop("partial", None)
    (board / "submissions" / "gridworld" / "oracle.json").write_text(json.dumps(full))
    before, after = "# My project\n\nintro\n", "\n## More\n\ntext\n"
    (tmp_path / "README.md").write_text(f"{before}{BEGIN}\nstale table\n{END}{after}")
    written = render(board)
    text = (tmp_path / "README.md").read_text()
    assert tmp_path / "README.md" in written and "stale table" not in text
    assert text.startswith(before + BEGIN + "\n") and text.endswith(END + after)
    assert "| `oracle` (privileged) | – | 1.00 / 1.00 | – |" in text  # the fixture holds unseen-goals only
    assert "*privileged*: reads ground truth" in text
    render(board)
    assert (tmp_path / "README.md").read_text() == text, "rendering twice changes nothing"


def test_a_readme_without_the_markers_is_left_alone(tmp_path):
    (tmp_path / "leaderboard" / "submissions").mkdir(parents=True)
    (tmp_path / "README.md").write_text("# Someone else's README\n")
    written = render(tmp_path / "leaderboard")
    assert tmp_path / "README.md" not in written
    assert (tmp_path / "README.md").read_text() == "# Someone else's README\n"


@pytest.mark.parametrize(
    "text",
    [f"{BEGIN}\nno end\n", f"{END}\n{BEGIN}\n", f"{BEGIN}\n{BEGIN}\n{END}\n"],
    ids=["no end", "reversed", "twice"],
)
def test_broken_markers_stop_render_before_anything_is_written(tmp_path, text):
    (tmp_path / "leaderboard" / "submissions").mkdir(parents=True)
    (tmp_path / "README.md").write_text(text)
    with pytest.raises(UserError, match="results table needs the line"):
        render(tmp_path / "leaderboard")
    assert not (tmp_path / "leaderboard" / "README.md").exists() and (tmp_path / "README.md").read_text() == text
    with pytest.raises(UserError):
        with_headline(text, "table\n")
