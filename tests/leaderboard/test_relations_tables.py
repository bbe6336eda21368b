"""The "Does it use relations?" figures of paper_tables.md and the size sweep's plot: gains over
``frontier`` paired on the same episodes, what an agent owes to where things are, and the
sweep's table and SVG, from hand-made records whose answers are known."""

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from objsearch.leaderboard.relations import (
    _ci,
    gain_rows,
    owed_rows,
    relations_rows,
    render_gains,
    render_owed,
    render_relations,
)
from objsearch.leaderboard.sweep import (
    SWEEP_ROOMS,
    render_sweep,
    render_sweep_owed,
    sweep_owed_rows,
    sweep_rows,
    sweep_suite,
    sweep_svg,
)


def _entry(
    suite: str, successes: list[bool], seed: int = 1, perception_key: str | None = None, houses: int = 0
) -> dict:
    """A gt (or predicted) entry on ``suite``'s test split: episode i succeeds as ``successes[i]``,
    in 10 steps of a shortest 5 (SPL 0.5); with ``houses``, episode i is in house ``i % houses``
    (else its record names no house, as hand-made records may)."""
    episodes = [
        {"split": "test", "seed": seed, "episode_id": i, "success": ok, "steps": 10, "min_steps": 5, "spl": 0.5 * ok}
        for i, ok in enumerate(successes)
    ]
    for i, r in enumerate(episodes):
        if houses:
            r["task"] = {"house": f"test_{i % houses:06d}"}
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


def test_gains_carry_an_interval_over_houses_beside_the_one_over_episodes():
    # 40 episodes in 4 houses (episode i in house i % 4): the agent's extra successes all sit in
    # houses 0 and 1, so over houses the gain is less certain than over episodes
    extra = [i % 4 in (0, 1) and i < 24 for i in range(40)]
    subs = [
        ("frontier", _entry("house-large", _pattern(0.25), houses=4)),
        ("object_prior_frontier", _entry("house-large", [a or b for a, b in zip(_pattern(0.25), extra)], houses=4)),
    ]
    (row,) = gain_rows(subs)
    low, high = row["sr_ci"]
    house_low, house_high = row["sr_house_ci"]
    assert house_low <= low < row["sr"] < high <= house_high and house_high - house_low > high - low
    table = "\n".join(render_gains([row]))
    assert "| SR gain (95% CI over episodes) | SR gain, 95% CI over houses |" in table
    assert f"| {row['sr']:+.2f} ({low:+.2f} to {high:+.2f}) | {house_low:+.2f} to {house_high:+.2f} |" in table
    # records without houses: no house interval, and the table says so
    (bare,) = gain_rows([(name, _entry("house-large", [r["success"] for r in e["episodes"]])) for name, e in subs])
    assert bare["sr_house_ci"] is None and bare["sr_ci"] == row["sr_ci"]
    assert "| n/a |" in "\n".join(render_gains([bare]))


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
    assert row["sr_house_ci"] is None  # hand-made records without houses
    # in 4 houses of 10 episodes (episode i in house i % 4): the agent solves one more episode
    # of each house than frontier (episodes 5-8 are one a house), +0.1 everywhere, and nothing
    # more when the objects move: it owes exactly +0.1, so the house interval has no width
    base = [i % 10 < 5 for i in range(40)]
    housed = [
        ("frontier", _entry("house-large", base, houses=4)),
        (
            "object_prior_frontier",
            _entry("house-large", [ok or i in (5, 6, 7, 8) for i, ok in enumerate(base)], houses=4),
        ),
        ("frontier", _entry("house-large-shuffled", _pattern(0.5), houses=4)),
        ("object_prior_frontier", _entry("house-large-shuffled", _pattern(0.5), houses=4)),
    ]
    (row,) = owed_rows(housed)
    assert row["sr"] == pytest.approx(0.1) and row["sr_house_ci"] == pytest.approx([0.1, 0.1])
    assert "SR owed, 95% CI over houses" in "\n".join(render_owed([row]))


def test_the_drop_tables_show_the_house_interval_beside_the_episode_one():
    # 5 houses of 8 episodes (episode i in house i % 5): moving the objects turns 2 of each
    # house's failures into successes, -0.25 in every house, so the house interval, which
    # pairs the two placements by house, has no width; the episode one (0 or -1 a task) has
    subs = [
        ("frontier", _entry("house-large", _pattern(0.5), houses=5)),
        ("frontier", _entry("house-large-shuffled", _pattern(0.75), houses=5)),
    ]
    (row,) = [r for r in relations_rows(subs) if r["name"] == "frontier"]
    assert row["sr_drop"] == pytest.approx(-0.25)
    low, high = row["sr_drop_house_ci"]
    assert low == pytest.approx(-0.25) and high == pytest.approx(-0.25)
    assert row["sr_drop_ci"][1] - row["sr_drop_ci"][0] > 0.1
    table = "\n".join(render_relations([row]))
    assert "| SR drop (95% CI over episodes) | SR drop, 95% CI over houses |" in table
    assert f"| {low:+.2f} to {high:+.2f} |" in table


def _sweep_submissions(houses: int = 0) -> list[tuple[str, dict]]:
    """frontier at 0.5 everywhere; a prior gaining 0.05 per size step on functional houses, none shuffled."""
    subs = []
    for k, rooms in enumerate(SWEEP_ROOMS):
        for placement, gain in (("functional", 0.05 * (k + 1)), ("shuffled", 0.0)):
            suite = sweep_suite(rooms, placement)
            subs += [
                ("frontier", _entry(suite, _pattern(0.5), houses=houses)),
                ("object_prior_frontier", _entry(suite, _pattern(0.5 + gain), houses=houses)),
                ("random", _entry(suite, _pattern(0.0), houses=houses)),  # a bound, not a searcher: left out
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


def test_the_sweep_shows_and_plots_its_intervals_over_houses():
    ns = "{http://www.w3.org/2000/svg}"
    bare = sweep_rows(_sweep_submissions())
    assert all(r["sr_gain_house_ci"] is None for r in bare)
    titles = [t.text for t in ET.fromstring(sweep_svg(bare)).findall(f"{ns}text")]
    assert "SR gain over frontier (95% CI over episodes)" in titles  # no houses: the episode bars, said so
    rows = sweep_rows(_sweep_submissions(houses=8))
    table = "\n".join(render_sweep(rows))
    assert "| SR gain (95% CI over episodes) | over houses | SR gain shuffled (95% CI over episodes) |" in table
    fourteen = next(r for r in rows if r["rooms"] == 14 and r["placement"] == "functional")
    low, high = fourteen["sr_gain_house_ci"]
    assert f"| +0.20 ({_ci(fourteen['sr_gain_ci'])}) | {low:+.2f} to {high:+.2f} |" in table
    svg = ET.fromstring(sweep_svg(rows))
    assert "SR gain over frontier (95% CI over houses)" in [t.text for t in svg.findall(f"{ns}text")]
    # the SR panel's bars (functional by size, then shuffled) are as long as the house intervals
    bars = [line for line in svg.findall(f"{ns}line") if line.attrib["x1"] == line.attrib["x2"]][: 2 * len(SWEEP_ROOMS)]
    lengths = np.array([float(b.attrib["y1"]) - float(b.attrib["y2"]) for b in bars])  # y grows downwards
    ordered = sorted(rows, key=lambda r: (r["placement"] != "functional", r["rooms"]))
    widths = np.array([r["sr_gain_house_ci"][1] - r["sr_gain_house_ci"][0] for r in ordered])
    assert widths.max() > 0 and np.allclose(lengths, widths * lengths.max() / widths.max(), atol=0.15)


def test_the_sweep_says_what_each_sizes_gain_owes_to_where_things_are():
    rows = sweep_owed_rows(_sweep_submissions(houses=8))
    assert [(r["name"], r["rooms"]) for r in rows] == [("object_prior_frontier", n) for n in SWEEP_ROOMS]
    # the functional gain (0.05 a size step) minus none shuffled, frontier the same on both
    assert [round(r["sr"], 3) for r in rows] == [0.05, 0.1, 0.15, 0.2]
    assert all(r["sr_house_ci"] is not None and r["suite"] == sweep_suite(r["rooms"], "shuffled") for r in rows)
    assert "| SR owed (95% CI over episodes) | SR owed, 95% CI over houses |" in "\n".join(render_sweep_owed(rows))


def test_the_report_names_the_suites_the_sweep_ships():
    # sweep.py keeps its own copy of the sizes so that the pages import no MuJoCo: it must match
    from objsearch.sim.large_suite import SWEEP

    assert SWEEP_ROOMS == tuple(SWEEP)
    for rooms, tier in SWEEP.items():
        assert tier.names == (sweep_suite(rooms, "functional"), sweep_suite(rooms, "shuffled"))


def test_the_shipped_paper_tables_show_the_large_tiers_intervals_over_houses():
    # the page is the render of the stored entries (test_leaderboard.py checks it is up to date)
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "leaderboard" / "paper_tables.md").read_text()
    sections = {s.split("\n", 1)[0]: s for s in page.split("\n## ")[1:]}
    wanted = {
        "Does it use relations? house-large against house-large-shuffled": "SR drop, 95% CI over houses",
        "The large-house tier: gain over `frontier`": "SR gain, 95% CI over houses",
        "The large-house tier: what each agent owes to where things are, beyond `frontier`": "SR owed, 95% CI over houses",
        "The large-house tier: SR and SPL over houses, by distance, and how it fails": "SR (95% CI over houses)",
        "Gain over `frontier` against house size": "SR gain (95% CI over episodes) | over houses",
        "Gain over `frontier` against house size: what it owes to where things are": "SR owed, 95% CI over houses",
    }
    for heading, column in wanted.items():
        assert column in sections[heading], heading
        assert "n/a" not in sections[heading], f"{heading}: every record of the tier names its house"
