"""`make leaderboard` is the recipe of the stored leaderboard: every stored entry is one it
writes, so rerunning it reproduces the page rather than dropping entries nobody can remake."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def make_variables() -> dict[str, list[str]]:
    """The Makefile's ``LEADERBOARD_* ?= ...`` lists (continuation lines joined, comments dropped)."""
    text = re.sub(r"\\\n\s*", " ", (ROOT / "Makefile").read_text())
    found = {}
    for line in text.splitlines():
        m = re.match(r"(LEADERBOARD_\w+) \?= ([^#]*)", line)
        if m:
            found[m.group(1)] = m.group(2).split()
    return found


def entries_made_by_make_leaderboard() -> set[str]:
    v = make_variables()
    made = set()
    for pair in v["LEADERBOARD_HOUSE"]:  # evaluated on gt and on predicted observations
        suite, agent = pair.split(":")
        made |= {f"{suite}/{agent}", f"{suite}/{agent}_predicted"}
    for pair in v["LEADERBOARD_HOUSE_TRAINED_PREDICTED"]:
        suite, agent = pair.split(":")
        made.add(f"{suite}/{agent}_predicted_trained")
    for suite in v["LEADERBOARD_SUITES"]:
        for agent in v["LEADERBOARD_AGENTS"]:
            made.add(f"{suite}/{agent}")
        if suite != "gridworld":
            for agent in v["LEADERBOARD_HOUSE_REFERENCE"]:
                made |= {f"{suite}/{agent}", f"{suite}/{agent}_predicted"}
    made |= {f"gridworld/{agent}" for agent in v["LEADERBOARD_GRID_AGENTS"]}
    made |= {f"{suite}/{agent}" for suite in v["LEADERBOARD_SWEEP_SUITES"] for agent in v["LEADERBOARD_SWEEP_AGENTS"]}
    made |= {f"{suite}/{agent}" for suite in v["LEADERBOARD_TIER2_SUITES"] for agent in v["LEADERBOARD_TIER2_AGENTS"]}
    return made


def test_every_stored_entry_is_remade_by_make_leaderboard():
    stored = {f"{p.parent.name}/{p.stem}" for p in (ROOT / "leaderboard" / "submissions").glob("*/*.json")}
    assert stored, "no stored entries found"
    missing = sorted(stored - entries_made_by_make_leaderboard())
    assert not missing, f"stored, but `make leaderboard` does not write them (add them to the Makefile): {missing}"


def test_the_recipe_covers_every_shipped_house_suite():
    from objsearch.sim.suites import SUITE_NAMES

    v = make_variables()  # the size sweep's suites: its own loop (gt, the prior agents and frontier)
    assert set(SUITE_NAMES) <= set(v["LEADERBOARD_SUITES"]) | set(v["LEADERBOARD_SWEEP_SUITES"]) | set(
        v["LEADERBOARD_TIER2_SUITES"]
    )
