"""The fidelity curve of paper_tables.md and ``leaderboard/fidelity.svg``: each agent's SR and its
gain over ``frontier`` against the share p of objects moved, with intervals over houses, from
hand-made records whose answers are known; and the page's copy of the tier's suites."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from objsearch.leaderboard.fidelity import FIDELITY, fidelity_rows, fidelity_svg, render_fidelity
from objsearch.leaderboard.relations import TIER_VERSIONS


def _entry(suite: str, rate: float, n: int = 40, houses: int = 8) -> dict:
    """A gt entry on ``suite``'s test split: the first ``rate * n`` episodes succeed; episode i in house i % houses."""
    episodes = [
        {
            "split": "test",
            "seed": 1,
            "episode_id": i,
            "success": i < round(rate * n),
            "steps": 10,
            "min_steps": 5,
            "spl": 0.5 * (i < round(rate * n)),
            "task": {"house": f"test_{i % houses:06d}"},
        }
        for i in range(n)
    ]
    return {"suite": suite, "episodes": episodes, "config": {"suite_config": {}}}


def _submissions() -> list[tuple[str, dict]]:
    """frontier at 0.5 at every p; a prior at 0.9 when nothing is moved, losing 0.1 per quarter moved."""
    subs = []
    for p, suite in FIDELITY:
        subs += [
            ("frontier", _entry(suite, 0.5)),
            ("object_prior_frontier", _entry(suite, 0.9 - 0.4 * p)),
            ("oracle", _entry(suite, 1.0)),  # a bound: not on the curve
        ]
    return subs


def test_fidelity_rows_give_each_p_its_sr_and_paired_gain_over_houses():
    rows = fidelity_rows(_submissions())
    assert {r["name"] for r in rows} == {"frontier", "object_prior_frontier"} and len(rows) == 2 * len(FIDELITY)
    prior = sorted((r for r in rows if r["name"] == "object_prior_frontier"), key=lambda r: r["p"])
    assert [round(r["gain"], 3) for r in prior] == [0.4, 0.3, 0.2, 0.1, 0.0]
    for r in prior:
        low, high = r["gain_house_ci"]
        assert low <= r["gain"] <= high
        assert r["sr_house_ci"][0] <= r["sr"] <= r["sr_house_ci"][1]
    reference = [r for r in rows if r["name"] == "frontier"]
    assert all(r["gain"] is None and r["sr"] == 0.5 for r in reference)
    table = "\n".join(render_fidelity(rows))
    assert "| Method | p = 0 | p = 0.25 | p = 0.5 | p = 0.75 | p = 1 |" in table
    low, high = prior[0]["gain_house_ci"]
    assert f"0.90 ({prior[0]['sr_house_ci'][0]:.2f}-{prior[0]['sr_house_ci'][1]:.2f})<br>+0.40 ({low:+.2f} to " in table


def test_a_missing_p_is_a_dash_and_no_entries_no_section():
    subs = [s for s in _submissions() if s[1]["suite"] != "house-large-v2-p50"]
    table = "\n".join(render_fidelity(fidelity_rows(subs)))
    assert table.count(" | - |") == 2  # each method's p = 0.5 cell, the middle column
    assert render_fidelity(fidelity_rows([])) == []


def test_fidelity_svg_plots_sr_and_gain_against_p_with_house_bars():
    rows = fidelity_rows(_submissions())
    svg = ET.fromstring(fidelity_svg(rows))
    ns = "{http://www.w3.org/2000/svg}"
    lines = svg.findall(f"{ns}polyline")
    assert len(lines) == 2 + 1  # SR: both methods; gain: the prior only
    # the prior's gain falls with p: its points' y grows (SVG y grows downwards)
    ys = [float(p.split(",")[1]) for p in lines[-1].attrib["points"].split()]
    assert len(ys) == len(FIDELITY) and np.all(np.diff(ys) > 0)
    texts = [t.text for t in svg.findall(f"{ns}text")]
    assert "SR gain over frontier (95% CI over houses)" in texts and "object_prior_frontier" in texts


def test_the_pages_copies_of_the_tiers_suites_are_the_tiers():
    pytest.importorskip("mujoco")
    from objsearch.sim.large_suite import LARGE, LARGE_V2

    assert TIER_VERSIONS[0] == tuple(LARGE.placements)
    assert set(TIER_VERSIONS[1]) == set(LARGE_V2.placements) and TIER_VERSIONS[1][0] == LARGE_V2.names[0]
    dial = {suite: p for suite, p in LARGE_V2.placements.items() if p.startswith("anywhere-") or p == "functional"}
    assert {suite for _, suite in FIDELITY} == set(dial)
    assert all(p == (0.0 if dial[s] == "functional" else int(dial[s].split("-")[1]) / 100) for p, s in FIDELITY)
