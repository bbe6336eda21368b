""" "Does it use relations?": each agent on a suite and on the same houses with its objects
moved, and the large-house tier's gains over ``frontier`` (``leaderboard/paper_tables.md``,
``docs/large_houses.md``).

* ``COMPARISONS``: a suite and the suite of the same houses with objects moved
  (``house-gen-v2`` / ``-shuffled``; ``house-large`` / ``-roomwise`` / ``-shuffled``). For
  every gt entry stored on both, per split: SR and SPL on each and the drop, with its 95%
  bootstrap interval over episodes: paired (``metrics.paired_difference_ci``) where the two
  suites play the same episodes (the large tier: the same starts and targets), else the two
  sets resampled independently (``metrics.difference_ci``); and beside it its interval over
  houses (``house_bootstrap.house_difference_ci``: the same houses drawn for both suites).
* ``gain_rows``: on each suite of the large tier, every gt entry minus ``frontier`` on the
  same episodes (paired), SR and SPL; ``owed_rows``: that gain on ``house-large`` minus the
  same gain on a moved placement, per episode (what the agent owes to where things are,
  with the move's own effect on difficulty cancelled).
* ``breakdown_rows``: the large tier's entries' SR and SPL, and SR by distance to the target
  (the episodes' ``geodesic`` in the suite file), and how they failed (STOP away from the
  target, or out of steps).

Every interval comes twice: over episodes (``objsearch.eval.metrics``; other episodes of the
same houses) and over houses (``objsearch.eval.house_bootstrap``: a house and all its
episodes resampled together; what a generated benchmark samples, so the interval a claim
must hold on). The house interval is None (``n/a`` in the tables) for records that name no
house.
"""

from __future__ import annotations

from dataclasses import dataclass

from objsearch.eval.house_bootstrap import (
    has_houses,
    house_ci,
    house_contrast_ci,
    house_difference_ci,
    house_paired_difference_ci,
)
from objsearch.eval.metrics import difference_ci, mean_ci, paired_difference_ci, per_task, spl, success_rate
from objsearch.leaderboard.markdown import markdown_text
from objsearch.leaderboard.paper import PAPER_NAMES


@dataclass(frozen=True)
class Comparison:
    """A suite (``base``) against the same houses with the objects moved (``moved``)."""

    base: str
    moved: str
    splits: tuple[str, ...]
    paired: bool
    text: tuple[str, ...]

    @property
    def label(self) -> str:
        """The moved suite's placement, as its columns are headed: ``shuffled``, ``roomwise``."""
        return self.moved.rsplit("-", 1)[1]


COMPARISONS = (
    Comparison(
        "house-gen-v2",
        "house-gen-v2-shuffled",
        ("test-seen", "test-unseen"),
        paired=False,
        text=(
            "The same floorplans, rooms and objects, but in `house-gen-v2-shuffled` every object stands at a random",
            "valid place anywhere in the house (`objsearch generate --placement shuffled`): a toilet may be in the",
            "kitchen. An agent that uses where things usually are should lose more there than a pure explorer.",
            "*drop*: house-gen-v2 minus shuffled, with its 95% bootstrap interval over episodes (tasks, and training",
            "runs where there are several) and over houses (the same houses drawn for both suites, with all their",
            "episodes, and the runs); an interval that holds 0 is no measured drop. gt observations, seeds 1, 5, 13,",
            "45, 99.",
        ),
    ),
    Comparison(
        "house-large",
        "house-large-roomwise",
        ("test",),
        paired=True,
        text=(
            "The large-house tier (`docs/large_houses.md`): the same houses, starts and targets, but in",
            "`house-large-roomwise` every object stands at a random place in a room of its usual type (object",
            "relations broken, room priors kept). *drop*: house-large minus roomwise, with its paired 95% bootstrap",
            "intervals over the episodes and over the houses (a house and all its episodes drawn together: the",
            "interval that says whether the drop would hold on other houses). gt observations.",
        ),
    ),
    Comparison(
        "house-large",
        "house-large-shuffled",
        ("test",),
        paired=True,
        text=("The same, with every object anywhere in the house (`house-large-shuffled`: room priors broken too).",),
    ),
    Comparison(
        "house-large-v2",
        "house-large-v2-roomwise",
        ("test",),
        paired=True,
        text=(
            "The tier's second version (`house-gen-4` test houses in floorplan families, 50 of them): every object moved",
            "within room types, onto a receptacle's surface (`roomwise-100`). Paired intervals as above.",
        ),
    ),
    Comparison(
        "house-large-v2",
        "house-large-v2-shuffled",
        ("test",),
        paired=True,
        text=("The same, with every object moved anywhere in the house (`anywhere-100`).",),
    ),
)
#: The large-house tier's versions, each its base suite first, then its moved placements
#: (``objsearch.sim.large_suite``'s ``LARGE`` and ``LARGE_V2``; a copy, so that the pages import
#: no MuJoCo, kept the same by a test).
TIER_VERSIONS = (
    ("house-large", "house-large-roomwise", "house-large-shuffled"),
    (
        "house-large-v2",
        "house-large-v2-roomwise",
        "house-large-v2-shuffled",
        "house-large-v2-p25",
        "house-large-v2-p50",
        "house-large-v2-p75",
    ),
)
LARGE_SUITES = tuple(suite for version in TIER_VERSIONS for suite in version)
REFERENCE = "frontier"
ORDER = (
    "random",
    "oracle",
    "frontier",
    "grg_frontier",
    "room_prior_frontier",
    "object_prior_frontier",
    "a3c",
    "hrl_grg",
)
DISTANCE_BINS = ((8.0, 12.0), (12.0, 16.0), (16.0, float("inf")))
#: Entries whose gain over ``REFERENCE`` only mirrors it (a bound, not a searcher): not in ``owed_rows``.
BOUNDS = ("random", "oracle")


def _gt(submissions: list[tuple[str, dict]], suite: str) -> dict[str, dict]:
    """The gt entries stored on ``suite`` (no perception network's key), by name."""
    return {
        name: results
        for name, results in submissions
        if results["suite"] == suite and not results["config"].get("suite_config", {}).get("perception_key")
    }


def _name(name: str) -> str:
    return PAPER_NAMES.get(name, markdown_text(name))


def _ordered(names) -> list[str]:
    return sorted(names, key=lambda n: (ORDER.index(n) if n in ORDER else len(ORDER), n))


def _split(results: dict, split: str) -> list[dict]:
    return [r for r in results["episodes"] if r["split"] == split]


def _num(value: float) -> str:
    return f"{value:.2f}"


def _ci(interval: list[float] | None) -> str:
    """An interval as a table cell: ``+0.13 to +0.37``, or ``n/a`` (no house interval)."""
    return "n/a" if interval is None else f"{interval[0]:+.2f} to {interval[1]:+.2f}"


def _range(interval: list[float] | None) -> str:
    """An interval of a score (not a difference) as a cell: ``0.56-0.83``, or ``n/a``."""
    return "n/a" if interval is None else f"{interval[0]:.2f}-{interval[1]:.2f}"


def _house_interval(function, sets: list[list[dict]], measure):
    """``function(*sets, measure)`` (a house interval), or None where a record names no house."""
    return function(*sets, measure) if all(has_houses(records) for records in sets) else None


def relations_rows(submissions: list[tuple[str, dict]], runs_label=lambda results: "1") -> list[dict]:
    """For every comparison of ``COMPARISONS`` and every gt entry stored on both of its suites,
    per split: SR and SPL on each and the drop from the first to the second, with its 95%
    bootstrap intervals over episodes (``sr_drop_ci``) and over houses (``sr_drop_house_ci``;
    None for records without houses) (``comparison``: the comparison's index)."""
    rows = []
    for index, comparison in enumerate(COMPARISONS):
        base, moved = _gt(submissions, comparison.base), _gt(submissions, comparison.moved)
        for name in _ordered(n for n in base if n in moved):
            for split in comparison.splits:
                a, b = _split(base[name], split), _split(moved[name], split)
                if not a or not b:
                    continue
                row = {"comparison": index, "name": name, "split": split, "runs": runs_label(base[name])}
                interval = paired_difference_ci if comparison.paired else difference_ci
                for key, measure in (("sr", success_rate), ("spl", spl)):
                    row[key] = [measure(a), measure(b)]
                    row[key + "_drop"] = measure(a) - measure(b)
                    row[key + "_drop_ci"] = interval(a, b, measure)
                    row[key + "_drop_house_ci"] = _house_interval(house_difference_ci, [a, b], measure)
                rows.append(row)
    return rows


def render_relations(rows: list[dict]) -> list[str]:
    """The markdown of ``relations_rows``: one table per comparison that has rows."""
    lines = []
    for index, comparison in enumerate(COMPARISONS):
        mine = [r for r in rows if r["comparison"] == index]
        if not mine:
            continue
        lines += [
            "",
            f"## Does it use relations? {comparison.base} against {comparison.moved}",
            "",
            *comparison.text,
            "",
            f"| Method | runs | split | SR | SR {comparison.label} | SR drop (95% CI over episodes) "
            f"| SR drop, 95% CI over houses | SPL | SPL {comparison.label} | SPL drop (95% CI over episodes) "
            "| SPL drop, 95% CI over houses |",
            "|---" * 11 + "|",
        ]
        for r in mine:
            cells = [
                f"{_num(r[k][0])} | {_num(r[k][1])} | {r[k + '_drop']:+.2f} ({_ci(r[k + '_drop_ci'])}) "
                f"| {_ci(r[k + '_drop_house_ci'])}"
                for k in ("sr", "spl")
            ]
            lines.append(f"| {_name(r['name'])} | {r['runs']} | {r['split']} | " + " | ".join(cells) + " |")
    return lines


def gain_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """On each suite of ``LARGE_SUITES``: every gt entry but ``REFERENCE`` minus ``REFERENCE``'s
    on ``split``, SR and SPL, each with its paired 95% interval."""
    rows = []
    for suite in LARGE_SUITES:
        entries = _gt(submissions, suite)
        if REFERENCE not in entries:
            continue
        ref = _split(entries[REFERENCE], split)
        for name in _ordered(n for n in entries if n != REFERENCE):
            gain = paired_gain(_split(entries[name], split), ref)
            if gain is not None:
                rows.append({"suite": suite, "name": name, **gain})
    return rows


def paired_gain(mine: list[dict], ref: list[dict]) -> dict | None:
    """SR and SPL of the records ``mine`` minus those of ``ref``, each with its paired 95%
    interval over episodes (``sr``, ``sr_ci``, ``spl``, ``spl_ci``) and over houses
    (``sr_house_ci``, ``spl_house_ci``; None for records without houses); None unless both
    hold the same episodes and seeds (other seeds: not the same records to pair)."""
    if {(r["episode_id"], r["seed"]) for r in mine} != {(r["episode_id"], r["seed"]) for r in ref}:
        return None
    gain = {}
    for key, measure in (("sr", success_rate), ("spl", spl)):
        gain[key] = measure(mine) - measure(ref)
        gain[key + "_ci"] = paired_difference_ci(mine, ref, measure)
        gain[key + "_house_ci"] = _house_interval(house_paired_difference_ci, [mine, ref], measure)
    return gain


def _interval_table(heading: str, text: tuple[str, ...], column: str, measure: str, rows: list[dict]) -> list[str]:
    """A section of one row per entry: its name, ``column`` (``r["suite"]``) and SR and SPL
    values (``r["sr"]``, ``r["spl"]``) with their intervals over episodes (``r["sr_ci"]``,
    ``r["spl_ci"]``) and over houses (``r["sr_house_ci"]``, ``r["spl_house_ci"]``)."""
    if not rows:
        return []
    lines = ["", f"## {heading}", "", *text, ""]
    lines += [
        f"| Method | {column} | SR {measure} (95% CI over episodes) | SR {measure}, 95% CI over houses "
        f"| SPL {measure} (95% CI over episodes) | SPL {measure}, 95% CI over houses |",
        "|---" * 6 + "|",
    ]
    for r in rows:
        cells = [f"{r[k]:+.2f} ({_ci(r[k + '_ci'])}) | {_ci(r[k + '_house_ci'])}" for k in ("sr", "spl")]
        lines.append(f"| {_name(r['name'])} | {r['suite']} | " + " | ".join(cells) + " |")
    return lines


def render_gains(rows: list[dict]) -> list[str]:
    """The markdown of ``gain_rows``."""
    text = (
        f"Each agent minus `{REFERENCE}` on the same test episodes and seeds, with the paired 95% bootstrap intervals",
        "over the episodes and over the houses (a house and all its episodes drawn together; `house-large` has 10",
        "test houses and `house-large-v2` 50, so this is the interval a claim must hold on). A prior that helps",
        "shows above zero on a base suite; one that uses relations loses that gain on the moved placements. gt",
        "observations.",
    )
    return _interval_table(f"The large-house tier: gain over `{REFERENCE}`", text, "suite", "gain", rows)


def owed_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """What each agent owes to where things are, beyond what moving them does to ``REFERENCE``:
    for every gt entry stored on a tier version's base suite and one of its moved suites
    (``TIER_VERSIONS``), with ``REFERENCE`` on both, ``owed_row``."""
    rows = []
    for base_suite, *moved_suites in TIER_VERSIONS:
        base = _gt(submissions, base_suite)
        for moved_suite in moved_suites:
            moved = _gt(submissions, moved_suite)
            if REFERENCE not in base or REFERENCE not in moved:
                continue
            for name in _ordered(n for n in base if n in moved and n not in (REFERENCE, *BOUNDS)):
                row = owed_row(base, moved, name, split)
                if row is not None:
                    rows.append({"suite": moved_suite, **row})
    return rows


def owed_row(base: dict[str, dict], moved: dict[str, dict], name: str, split: str = "test") -> dict | None:
    """``name``'s gain over ``REFERENCE`` on a suite (``base``: its gt entries by name) minus
    its gain on the same episodes with the objects moved (``moved``), per task, so
    placement's own effect on difficulty, which ``REFERENCE`` shows, cancels: SR and SPL
    (``sr``, ``spl``), with the paired 95% intervals over the tasks (``sr_ci``) and over the
    houses (``sr_house_ci``, the four sets' records in the drawn houses pooled; None without
    houses). None unless the four sets hold the same tasks."""
    sets = [_split(results[key], split) for results in (base, moved) for key in (name, REFERENCE)]
    row = {"name": name}
    for key, measure in (("sr", success_rate), ("spl", spl)):
        a, ref, a_moved, ref_moved = (per_task(records, measure) for records in sets)
        if not a or not a.keys() == ref.keys() == a_moved.keys() == ref_moved.keys():
            return None
        values = [(a[k] - ref[k]) - (a_moved[k] - ref_moved[k]) for k in sorted(a)]
        row[key], row[key + "_ci"] = float(sum(values) / len(values)), mean_ci(values)
        row[key + "_house_ci"] = _house_interval(_owed_house_ci, sets, measure)
    return row


def _owed_house_ci(a: list[dict], ref: list[dict], a_moved: list[dict], ref_moved: list[dict], measure) -> list[float]:
    """The house interval of ``(a - ref) - (a_moved - ref_moved)``, the same houses drawn for all four."""
    return house_contrast_ci([a, ref, a_moved, ref_moved], (1.0, -1.0, -1.0, 1.0), measure)


def render_owed(rows: list[dict]) -> list[str]:
    """The markdown of ``owed_rows``."""
    text = (
        f"Moving the objects changes how hard they are to see (`{REFERENCE}`, which ignores where things are,",
        "scores differently on each placement). So each agent's gain over it on the base suite minus the same",
        "gain on the moved placement, per test episode, with the paired 95% intervals over episodes and over houses:",
        "above zero, the agent used what the move broke (object relations for roomwise; room priors too for",
        "shuffled). gt observations.",
    )
    heading = f"The large-house tier: what each agent owes to where things are, beyond `{REFERENCE}`"
    return _interval_table(heading, text, "moved suite", "owed", rows)


def breakdown_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """Each gt entry of ``LARGE_SUITES`` on ``split``: SR and SPL with their 95% intervals over
    houses (``sr_house_ci``, ``spl_house_ci``; None without houses), SR and SPL by distance bin
    (``DISTANCE_BINS``, metres walked to the nearest goal pose; each bin ``(SR, SPL, episodes,
    SR's house interval)``), and its failures: STOP away from the target, out of steps."""
    from objsearch.sim.suites import load_suite_file

    rows = []
    for suite in LARGE_SUITES:
        entries = _gt(submissions, suite)
        if not entries:
            continue
        data = load_suite_file(suite)
        geodesic = [e["geodesic"] for e in data["splits"][split]]
        for name in _ordered(entries):
            records = _split(entries[name], split)
            limit = entries[name]["config"].get("suite_config", {}).get("max_steps") or data["max_steps"]
            row = {"suite": suite, "name": name, "episodes": len(records), "bins": []}
            for key, measure in (("sr", success_rate), ("spl", spl)):
                row[key], row[key + "_house_ci"] = measure(records), _house_interval(house_ci, [records], measure)
            for lo, hi in DISTANCE_BINS:
                inside = [r for r in records if lo <= geodesic[r["episode_id"]] < hi]
                sr_house = _house_interval(house_ci, [inside], success_rate)
                row["bins"].append((success_rate(inside), spl(inside), len(inside), sr_house) if inside else None)
            failed = [r for r in records if not r["success"]]
            row["stop_away"] = sum(r["steps"] < limit for r in failed) / len(records)
            row["out_of_steps"] = sum(r["steps"] >= limit for r in failed) / len(records)
            rows.append(row)
    return rows


def render_breakdown(rows: list[dict]) -> list[str]:
    """The markdown of ``breakdown_rows``."""
    if not rows:
        return []
    bins = [f"{lo:g}-{hi:g} m" if hi != float("inf") else f"{lo:g}+ m" for lo, hi in DISTANCE_BINS]
    lines = [
        "",
        "## The large-house tier: SR and SPL over houses, by distance, and how it fails",
        "",
        "SR and SPL on test episodes with their 95% bootstrap intervals over houses (a house and all its episodes",
        "drawn together); SR [its 95% interval over houses] / SPL (episodes) by the walking distance from the start",
        "to the nearest goal pose; and the share of episodes that end in a STOP away from the target or run out of",
        "the 500 steps. gt observations.",
        "",
        "| Method | suite | SR (95% CI over houses) | SPL (95% CI over houses) | "
        + " | ".join(bins)
        + " | STOP away | out of steps |",
        "|---" * (6 + len(bins)) + "|",
    ]
    for r in rows:
        whole = [f"{r[k]:.2f} ({_range(r[k + '_house_ci'])})" for k in ("sr", "spl")]
        cells = [f"{b[0]:.2f} [{_range(b[3])}] / {b[1]:.2f} ({b[2]})" if b else "-" for b in r["bins"]]
        lines.append(
            f"| {_name(r['name'])} | {r['suite']} | "
            + " | ".join(whole + cells)
            + f" | {r['stop_away']:.2f} | {r['out_of_steps']:.2f} |"
        )
    return lines
