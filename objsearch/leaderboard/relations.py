""" "Does it use relations?": each agent on a suite and on the same houses with its objects
moved, and the large-house tier's gains over ``frontier`` (``leaderboard/paper_tables.md``,
``docs/large_houses.md``).

* ``COMPARISONS``: a suite and the suite of the same houses with objects moved
  (``house-gen-v2`` / ``-shuffled``; ``house-large`` / ``-roomwise`` / ``-shuffled``). For
  every gt entry stored on both, per split: SR and SPL on each and the drop, with its 95%
  bootstrap interval: paired (``metrics.paired_difference_ci``) where the two suites play the
  same episodes (the large tier: the same starts and targets), else the two sets resampled
  independently (``metrics.difference_ci``).
* ``gain_rows``: on each suite of the large tier, every gt entry minus ``frontier`` on the
  same episodes (paired), SR and SPL; ``owed_rows``: that gain on ``house-large`` minus the
  same gain on a moved placement, per episode (what the agent owes to where things are,
  with the move's own effect on difficulty cancelled).
* ``breakdown_rows``: the large tier's entries by distance to the target (the episodes'
  ``geodesic`` in the suite file) and how they failed (STOP away from the target, or out of
  steps).
"""

from __future__ import annotations

from dataclasses import dataclass

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
            "*drop*: house-gen-v2 minus shuffled, with its 95% bootstrap interval (tasks, and training runs where",
            "there are several); an interval that holds 0 is no measured drop. gt observations, seeds 1, 5, 13, 45, 99.",
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
            "interval over the episodes. gt observations.",
        ),
    ),
    Comparison(
        "house-large",
        "house-large-shuffled",
        ("test",),
        paired=True,
        text=("The same, with every object anywhere in the house (`house-large-shuffled`: room priors broken too).",),
    ),
)
LARGE_SUITES = ("house-large", "house-large-roomwise", "house-large-shuffled")
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


def relations_rows(submissions: list[tuple[str, dict]], runs_label=lambda results: "1") -> list[dict]:
    """For every comparison of ``COMPARISONS`` and every gt entry stored on both of its suites,
    per split: SR and SPL on each and the drop from the first to the second, with its 95%
    bootstrap interval (``comparison``: the comparison's index)."""
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
            f"| Method | runs | split | SR | SR {comparison.label} | SR drop (95% CI) | SPL | SPL {comparison.label} "
            "| SPL drop (95% CI) |",
            "|---|---|---|---|---|---|---|---|---|",
        ]
        for r in mine:
            cells = [
                f"{_num(r[k][0])} | {_num(r[k][1])} | {r[k + '_drop']:+.2f} "
                f"({r[k + '_drop_ci'][0]:+.2f} to {r[k + '_drop_ci'][1]:+.2f})"
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
    interval (``sr``, ``sr_ci``, ``spl``, ``spl_ci``); None unless both hold the same episodes
    and seeds (other seeds: not the same records to pair)."""
    if {(r["episode_id"], r["seed"]) for r in mine} != {(r["episode_id"], r["seed"]) for r in ref}:
        return None
    gain = {}
    for key, measure in (("sr", success_rate), ("spl", spl)):
        gain[key] = measure(mine) - measure(ref)
        gain[key + "_ci"] = paired_difference_ci(mine, ref, measure)
    return gain


def _interval_table(heading: str, text: tuple[str, ...], column: str, measure: str, rows: list[dict]) -> list[str]:
    """A section of one row per entry: its name, ``column`` (``r["suite"]``) and SR and SPL
    values (``r["sr"]``, ``r["spl"]``) with their intervals (``r["sr_ci"]``, ``r["spl_ci"]``)."""
    if not rows:
        return []
    lines = ["", f"## {heading}", "", *text, ""]
    lines += [f"| Method | {column} | SR {measure} (95% CI) | SPL {measure} (95% CI) |", "|---|---|---|---|"]
    for r in rows:
        cells = [f"{r[k]:+.2f} ({r[k + '_ci'][0]:+.2f} to {r[k + '_ci'][1]:+.2f})" for k in ("sr", "spl")]
        lines.append(f"| {_name(r['name'])} | {r['suite']} | " + " | ".join(cells) + " |")
    return lines


def render_gains(rows: list[dict]) -> list[str]:
    """The markdown of ``gain_rows``."""
    text = (
        f"Each agent minus `{REFERENCE}` on the same test episodes and seeds, with the paired 95% bootstrap interval.",
        "A prior that helps shows above zero on `house-large`; one that uses relations loses that gain on the",
        "moved placements. gt observations.",
    )
    return _interval_table(f"The large-house tier: gain over `{REFERENCE}`", text, "suite", "gain", rows)


def owed_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """What each agent owes to where things are, beyond what moving them does to ``REFERENCE``:
    for every gt entry stored on ``house-large`` and a moved suite of the tier, with
    ``REFERENCE`` on both, its gain over ``REFERENCE`` on ``house-large`` minus its gain on the
    moved suite (per task, so placement's own effect on difficulty, which ``REFERENCE`` shows,
    cancels), SR and SPL, with the paired 95% interval over the tasks."""
    base = _gt(submissions, LARGE_SUITES[0])
    rows = []
    for moved_suite in LARGE_SUITES[1:]:
        moved = _gt(submissions, moved_suite)
        if REFERENCE not in base or REFERENCE not in moved:
            continue
        for name in _ordered(n for n in base if n in moved and n not in (REFERENCE, *BOUNDS)):
            sets = [_split(results[key], split) for results in (base, moved) for key in (name, REFERENCE)]
            row = {"suite": moved_suite, "name": name}
            for key, measure in (("sr", success_rate), ("spl", spl)):
                a, ref, a_moved, ref_moved = (per_task(records, measure) for records in sets)
                if not a.keys() == ref.keys() == a_moved.keys() == ref_moved.keys():
                    break
                values = [(a[k] - ref[k]) - (a_moved[k] - ref_moved[k]) for k in sorted(a)]
                row[key], row[key + "_ci"] = float(sum(values) / len(values)), mean_ci(values)
            else:
                rows.append(row)
    return rows


def render_owed(rows: list[dict]) -> list[str]:
    """The markdown of ``owed_rows``."""
    text = (
        f"Moving the objects changes how hard they are to see (`{REFERENCE}`, which ignores where things are,",
        "scores differently on the three placements). So each agent's gain over it on `house-large` minus the same",
        "gain on the moved placement, per test episode, with the paired 95% interval: above zero, the agent used",
        "what the move broke (object relations for roomwise; room priors too for shuffled). gt observations.",
    )
    heading = f"The large-house tier: what each agent owes to where things are, beyond `{REFERENCE}`"
    return _interval_table(heading, text, "moved suite", "owed", rows)


def breakdown_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """Each gt entry of ``LARGE_SUITES`` on ``split``: SR and SPL by distance bin (``DISTANCE_BINS``,
    metres walked to the nearest goal pose), and its failures: STOP away from the target, out of steps."""
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
            for lo, hi in DISTANCE_BINS:
                inside = [r for r in records if lo <= geodesic[r["episode_id"]] < hi]
                row["bins"].append((success_rate(inside), spl(inside), len(inside)) if inside else None)
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
        "## The large-house tier by distance, and how it fails",
        "",
        "SR / SPL on test episodes by the walking distance from the start to the nearest goal pose, and the",
        "share of episodes that end in a STOP away from the target or run out of the 500 steps. gt observations.",
        "",
        "| Method | suite | " + " | ".join(bins) + " | STOP away | out of steps |",
        "|---" * (4 + len(bins)) + "|",
    ]
    for r in rows:
        cells = [f"{b[0]:.2f} / {b[1]:.2f} ({b[2]})" if b else "-" for b in r["bins"]]
        lines.append(
            f"| {_name(r['name'])} | {r['suite']} | "
            + " | ".join(cells)
            + f" | {r['stop_away']:.2f} | {r['out_of_steps']:.2f} |"
        )
    return lines
