"""The "Does it use relations?" figures of paper_tables.md and the size sweep's plot: gains over
``frontier`` paired on the same episodes, what an agent owes to where things are, and the
sweep's table and SVG, from hand-made records whose answers are known."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from objsearch.leaderboard.relations import gain_rows, owed_rows
from objsearch.leaderboard.sweep import SWEEP_ROOMS, render_sweep, sweep_rows, sweep_suite, sweep_svg


def _entry(suite: str, successes: list[bool], seed: int = 1, perception_key: str | None = None) -> dict:
    """A gt (or predicted) entry on ``suite``'s test split: episode i succeeds as ``successes[i]``,
    in 10 steps of a shortest 5 (SPL 0.5)."""
    episodes = [
        {"split": "test", "seed": seed, "episode_id": i, "success": ok, "steps": 10, "min_steps": 5, "spl": 0.5 * ok}
        for i, ok in enumerate(successes)
    ]
    suite_config = {"perception_key": perception_key} if perception_key else {}
    return {"suite": suite, "episodes": episodes, "config": {"suite_config": suite_config}}


def _pattern(rate: float, n: int = 40) -> list[bool]:
    return [i < round(rate * n) for i in range(n)]


def test_gain_over_frontier_is_paired_on_the_same_episodes_and_skips_other_seeds():
    subs = [
        ("frontier", _entry("house-large", _pattern(0.5))),
        ("object_prior_frontier", _entry("house-large", _pattern(0.75))),
        ("room_prior_frontier", _entry("house-large", _pattern(0.75), seed=2)),  # other seeds: no pairing
        ("object_prior_frontier-predicted", _entry("house-large", _pattern(1.0), perception_key="k")),
    ]
    rows = gain_rows(subs)
    assert [(r["suite"], r["name"]) for r in rows] == [("house-large", "object_prior_frontier")]
    row = rows[0]
    assert row["sr"] == pytest.approx(0.25) and row["spl"] == pytest.approx(0.125)
    low, high = row["sr_ci"]
    assert 0 < low < 0.25 < high < 0.5  # every pair differs by 0 or +1: the interval is above zero


def test_owed_cancels_what_moving_the_objects_does_to_frontier():
    # moving the objects makes every episode easier for frontier and the agent alike: no debt
    same = [
        ("frontier", _entry("house-large", _pattern(0.5))),
        ("object_prior_frontier", _entry("house-large", _pattern(0.75))),
        ("frontier", _entry("house-large-shuffled", _pattern(0.75))),
        ("object_prior_frontier", _entry("house-large-shuffled", _pattern(1.0))),
    ]
    (row,) = owed_rows(same)
    assert row["suite"] == "house-large-shuffled" and row["sr"] == pytest.approx(0.0)
    # the agent's gain vanishes when the objects move, frontier's score does not change: it owed it
    used = same[:2] + [
        ("frontier", _entry("house-large-shuffled", _pattern(0.5))),
        ("object_prior_frontier", _entry("house-large-shuffled", _pattern(0.5))),
    ]
    (row,) = owed_rows(used)
    assert row["sr"] == pytest.approx(0.25) and row["sr_ci"][0] > 0


def _sweep_submissions() -> list[tuple[str, dict]]:
    """frontier at 0.5 everywhere; a prior gaining 0.05 per size step on functional houses, none shuffled."""
    subs = []
    for k, rooms in enumerate(SWEEP_ROOMS):
        for placement, gain in (("functional", 0.05 * (k + 1)), ("shuffled", 0.0)):
            suite = sweep_suite(rooms, placement)
            subs += [
                ("frontier", _entry(suite, _pattern(0.5))),
                ("object_prior_frontier", _entry(suite, _pattern(0.5 + gain))),
                ("random", _entry(suite, _pattern(0.0))),  # a bound, not a searcher: left out
            ]
    return subs


def test_sweep_rows_give_each_size_and_placement_its_paired_gain():
    rows = sweep_rows(_sweep_submissions())
    assert {r["name"] for r in rows} == {"object_prior_frontier"} and len(rows) == 2 * len(SWEEP_ROOMS)
    functional = {r["rooms"]: r for r in rows if r["placement"] == "functional"}
    shuffled = {r["rooms"]: r for r in rows if r["placement"] == "shuffled"}
    assert [round(functional[n]["sr_gain"], 3) for n in SWEEP_ROOMS] == [0.05, 0.1, 0.15, 0.2]
    assert all(shuffled[n]["sr_gain"] == 0 and shuffled[n]["sr_gain_ci"] == [0, 0] for n in SWEEP_ROOMS)
    assert all(r["reference_sr"] == 0.5 for r in rows)
    table = render_sweep(rows)
    assert sum(line.startswith("| object_prior_frontier |") for line in table) == len(SWEEP_ROOMS)
    assert "| object_prior_frontier | 14 | 0.50 / 0.25 · 0.50 / 0.25 | +0.20 (" in "\n".join(table)


def test_sweep_svg_is_a_plot_of_every_method_in_both_placements():
    rows = sweep_rows(_sweep_submissions())
    svg = ET.fromstring(sweep_svg(rows))
    ns = "{http://www.w3.org/2000/svg}"
    lines = svg.findall(f"{ns}polyline")
    assert len(lines) == 2 * 2  # two panels (SR, SPL) x two placements
    assert sum("stroke-dasharray" in line.attrib for line in lines) == 2  # shuffled: dashed
    # the functional SR line climbs with size: its points' y falls (SVG y grows downwards)
    ys = [float(p.split(",")[1]) for p in lines[0].attrib["points"].split()]
    assert len(ys) == len(SWEEP_ROOMS) and np.all(np.diff(ys) < 0)
    assert any(t.text == "object_prior_frontier" for t in svg.findall(f"{ns}text"))


def test_the_report_names_the_suites_the_sweep_ships():
    # sweep.py keeps its own copy of the sizes so that the pages import no MuJoCo: it must match
    from objsearch.sim.large_suite import SWEEP

    assert SWEEP_ROOMS == tuple(SWEEP)
    for rooms, tier in SWEEP.items():
        assert tier.names == (sweep_suite(rooms, "functional"), sweep_suite(rooms, "shuffled"))
