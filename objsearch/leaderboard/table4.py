"""The paper's Table 4 (AI2-THOR): each method's improvement over Random in single rooms,
beside ours on the ``rooms`` suite (``docs/rooms.md``).

The paper reports Scene Priors and HRL-GRG as SR and SPL minus Random's on the same episode
files, in four cells: seen / unseen environments crossed with seen / unseen goals. Ours is
each stored ``rooms`` entry minus ``random``'s gt entry on the same episodes and seeds (Random
ignores what it sees, so one row serves both observations), with the 95% bootstrap interval
of the difference (``objsearch.eval.metrics.difference_ci``: the two sets resampled
independently, which is wider than a paired interval).
Below it, the paper's ordering itself: HRL-GRG minus Scene Priors, SR and SPL, per cell.
"""

from __future__ import annotations

from objsearch.eval.metrics import difference_ci, spl, success_rate
from objsearch.leaderboard.paper import PAPER_NAMES, PREDICTED_SUFFIX

ROOMS_SUITE = "rooms"
TABLE4_SPLITS = ("seen-env-seen-goals", "seen-env-unseen-goals", "unseen-env-seen-goals", "unseen-env-unseen-goals")
# (SR, SPL) improvement over Random in TABLE4_SPLITS' order (tbl:ros_ai2thor of the paper).
_PAPER = {
    "scene_priors": ((0.25, 0.16), (0.08, 0.07), (0.18, 0.11), (0.12, 0.06)),
    "hrl_grg": ((0.37, 0.24), (0.33, 0.23), (0.33, 0.21), (0.38, 0.23)),
}
TABLE4_METHODS = ("a3c", "scene_priors", "hrl_grg", "frontier", "oracle")
"""Table 4's rows (the paper has Scene Priors and HRL-GRG), then rows the paper did not have."""


def _rooms_entries(submissions: list[tuple[str, dict]]) -> dict[str, dict]:
    """The stored entries of the ``rooms`` suite, by name."""
    return {name: results for name, results in submissions if results["suite"] == ROOMS_SUITE}


def _by_split(results: dict) -> dict[str, list[dict]]:
    """An entry's episode records, by ``TABLE4_SPLITS`` split."""
    return {split: [r for r in results["episodes"] if r["split"] == split] for split in TABLE4_SPLITS}


def _difference(mine: list[dict], other: list[dict]) -> dict:
    """SR and SPL of ``mine`` minus those of ``other``, each with its 95% interval."""
    return {
        key: (measure(mine) - measure(other), difference_ci(mine, other, measure))
        for key, measure in (("sr", success_rate), ("spl", spl))
    }


def _header(*columns: str) -> list[str]:
    """A markdown table's header: ``columns``, then one column per ``TABLE4_SPLITS`` split."""
    names = [*columns, *TABLE4_SPLITS]
    cells = [f" {name} " if name else " " for name in names]  # an empty name: "| |"
    return ["|" + "|".join(cells) + "|", "|---" * len(names) + "|"]


def table4_rows(submissions: list[tuple[str, dict]], runs_of) -> list[dict]:
    """For every ``TABLE4_METHODS`` entry stored on ``rooms`` (gt and ``_predicted``), per split:
    SR and SPL minus Random's, their intervals and the paper's figures; [] without Random's
    entry. ``runs_of(results)``: the label of an entry's training runs."""
    ours = _rooms_entries(submissions)
    if "random" not in ours:
        return []
    base = _by_split(ours["random"])
    rows = []
    for method in TABLE4_METHODS:
        for observation, entry in (("gt", method), ("predicted", method + PREDICTED_SUFFIX)):
            if entry not in ours:
                continue
            row = {"method": method, "observation": observation, "runs": runs_of(ours[entry])}
            mine = _by_split(ours[entry])
            for i, split in enumerate(TABLE4_SPLITS):
                if not mine[split] or not base[split]:
                    row[split] = None
                    continue
                row[split] = _difference(mine[split], base[split])
                paper = _PAPER.get(method)
                row[split]["paper"] = None if paper is None or observation != "gt" else paper[i]
            rows.append(row)
    return rows


def ordering_cells(submissions: list[tuple[str, dict]]) -> dict | None:
    """The paper's ordering on ``rooms``, gt: per split, HRL-GRG's SR and SPL minus Scene
    Priors' on the same episodes, each with its 95% interval, and the paper's difference;
    None unless both entries are stored. (Random's share of the two improvements cancels.)"""
    ours = _rooms_entries(submissions)
    if "hrl_grg" not in ours or "scene_priors" not in ours:
        return None
    grg, priors = _by_split(ours["hrl_grg"]), _by_split(ours["scene_priors"])
    cells = {}
    for i, split in enumerate(TABLE4_SPLITS):
        if not grg[split] or not priors[split]:
            return None
        cells[split] = _difference(grg[split], priors[split])
        cells[split]["paper"] = tuple(round(g - p, 2) for g, p in zip(_PAPER["hrl_grg"][i], _PAPER["scene_priors"][i]))
    return cells


def render_ordering(cells: dict | None) -> list[str]:
    """The markdown of ``ordering_cells`` (nothing without them)."""
    if cells is None:
        return []
    lines = [
        "",
        "The paper's ordering: HRL-GRG minus Scene Priors on the same episodes (gt), **ours** [95% interval]",
        "(paper). Above zero in a cell means HRL-GRG's improvement over Random is the larger there.",
        "",
        *_header(""),
    ]
    for i, (key, label) in enumerate((("sr", "SR"), ("spl", "SPL"))):
        texts = []
        for split in TABLE4_SPLITS:
            value, (lo, hi) = cells[split][key]
            texts.append(f"**{value:+.2f}** [{lo:+.2f} to {hi:+.2f}] ({cells[split]['paper'][i]:+.2f})")
        lines.append(f"| {label} | " + " | ".join(texts) + " |")
    return lines


def render_table4(rows: list[dict]) -> list[str]:
    """The markdown of Table 4 (nothing without rows)."""
    if not rows:
        return []
    lines = [
        "",
        "## Table 4: AI2-THOR's single rooms, beside our rooms suite",
        "",
        "Each cell is the improvement over Random, SR / SPL: **ours** [95% interval of the SR difference] (paper).",
        "Ours: the `rooms` suite (120 single rooms of house-gen-2, 250 episodes per room type a split, 100 steps",
        "and 200 in living rooms, no STOP; `docs/rooms.md`), seeds 1, 5, 13, 45, 99, minus `random` on the same",
        "episodes. The paper's: AI2-THOR's 120 rooms, its own Random on its own episode files, one seed.",
        "",
        *_header("Method", "observation", "runs"),
    ]
    for row in rows:
        cells = []
        for split in TABLE4_SPLITS:
            cell = row[split]
            if cell is None:
                cells.append("not run")
                continue
            (sr, sr_ci), (pl, _) = cell["sr"], cell["spl"]
            text = f"**{sr:+.2f} / {pl:+.2f}** [{sr_ci[0]:+.2f} to {sr_ci[1]:+.2f}]"
            if cell["paper"] is not None:
                text += f" ({cell['paper'][0]:+.2f} / {cell['paper'][1]:+.2f})"
            cells.append(text)
        name = PAPER_NAMES.get(row["method"], row["method"])
        lines.append(f"| {name} | {row['observation']} | {row['runs']} | " + " | ".join(cells) + " |")
    return lines
