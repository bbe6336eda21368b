"""Table 4 of paper_tables.md: each method's improvement over Random on the rooms suite, beside
the paper's AI2-THOR figures."""

from objsearch.leaderboard.render import render_paper_tables
from objsearch.leaderboard.table4 import TABLE4_SPLITS, ordering_cells, table4_rows


def _entry(agent: str, success_every: int, steps: int) -> dict:
    """A rooms entry whose every ``success_every``-th episode of each split succeeds in ``steps`` steps
    (minimal steps 5), 40 episodes a split."""
    episodes = [
        {"split": split, "seed": 1, "episode_id": i, "success": i % success_every == 0, "steps": steps, "min_steps": 5}
        for split in TABLE4_SPLITS
        for i in range(40)
    ]
    config = {"weights_sha256": None}
    return {
        "suite": "rooms",
        "agent": agent,
        "config": config,
        "splits": {s: {} for s in TABLE4_SPLITS},
        "episodes": episodes,
    }


def test_improvement_over_random_with_the_papers_figures_beside_it():
    random, grg = _entry("random", 4, 50), _entry("hrl_grg", 1, 10)  # SR 0.25 (SPL 0.025) and 1.0 (SPL 0.5)
    rows = table4_rows([("random", random), ("hrl_grg", grg)], lambda results: "1")
    assert [(r["method"], r["observation"]) for r in rows] == [("hrl_grg", "gt")]
    cell = rows[0]["seen-env-seen-goals"]
    assert abs(cell["sr"][0] - 0.75) < 1e-9 and abs(cell["spl"][0] - 0.475) < 1e-9
    assert cell["sr"][1][0] <= 0.75 <= cell["sr"][1][1]  # the interval holds the difference
    assert cell["paper"] == (0.37, 0.24)
    tables = render_paper_tables([("random", random), ("hrl_grg", grg)])
    assert "## Table 4: AI2-THOR's single rooms" in tables
    assert "| HRL-GRG | gt | 1* | **+0.75 / +0.47** [" in tables and "(+0.37 / +0.24)" in tables


def test_no_table4_without_randoms_entry_and_predicted_rows_have_no_paper_figures():
    grg = _entry("hrl_grg", 1, 10)
    assert table4_rows([("hrl_grg", grg)], lambda results: "1") == []
    assert "Table 4" not in render_paper_tables([("hrl_grg", grg)])
    rows = table4_rows([("random", _entry("random", 2, 50)), ("hrl_grg_predicted", grg)], lambda results: "1")
    assert [(r["method"], r["observation"]) for r in rows] == [("hrl_grg", "predicted")]
    assert all(rows[0][split]["paper"] is None for split in TABLE4_SPLITS)


def test_the_papers_ordering_is_hrl_grg_minus_scene_priors_on_the_same_episodes():
    random, grg, priors = _entry("random", 4, 50), _entry("hrl_grg", 1, 10), _entry("scene_priors", 2, 10)
    assert ordering_cells([("random", random), ("hrl_grg", grg)]) is None  # no Scene Priors entry: no comparison
    cells = ordering_cells([("random", random), ("hrl_grg", grg), ("scene_priors", priors)])
    sr, (lo, hi) = cells["seen-env-seen-goals"]["sr"]
    assert abs(sr - 0.5) < 1e-9 and lo <= 0.5 <= hi  # SR 1.0 against 0.5
    assert abs(cells["seen-env-seen-goals"]["spl"][0] - 0.25) < 1e-9  # SPL 0.5 against 0.25
    assert cells["seen-env-unseen-goals"]["paper"] == (0.25, 0.16)  # +0.33 / +0.23 minus +0.08 / +0.07
    tables = render_paper_tables([("random", random), ("hrl_grg", grg), ("scene_priors", priors)])
    assert "The paper's ordering: HRL-GRG minus Scene Priors" in tables
    assert "| SR | **+0.50** [" in tables and "| SPL | **+0.25** [" in tables
    assert "The paper's ordering" not in render_paper_tables([("hrl_grg", grg), ("scene_priors", priors)])
