"""The fidelity curve: SR and the gain over ``frontier`` against the share p of objects moved
out of their functional places (``docs/large_houses.md``).

The tier's second version has a suite for each p (``FIDELITY``: ``house-large-v2`` at p = 0,
then ``-p25``, ``-p50``, ``-p75`` and ``-shuffled``, objects moved anywhere), the same houses,
starts and targets in all. ``fidelity_rows`` gives every gt entry's SR on each with its 95%
interval over houses, and its SR gain over ``frontier`` on the same episodes (paired, over
houses); ``render_fidelity`` is its table for ``paper_tables.md`` and ``fidelity_svg`` its plot
(``leaderboard/fidelity.svg``), both written by ``objsearch leaderboard render``.
"""

from __future__ import annotations

from objsearch.eval.house_bootstrap import house_ci
from objsearch.eval.metrics import success_rate
from objsearch.leaderboard.relations import (
    BOUNDS,
    REFERENCE,
    _gt,
    _house_interval,
    _name,
    _ordered,
    _range,
    _split,
    paired_gain,
)
from objsearch.leaderboard.sweep import COLOURS, GAP, HEIGHT, MARGIN, WIDTH, _tick_label, _ticks, legend

#: (p, suite): the share of objects moved anywhere and the suite that has it
#: (``objsearch.sim.large_suite.LARGE_V2``'s placements; a copy, kept the same by a test).
FIDELITY = (
    (0.0, "house-large-v2"),
    (0.25, "house-large-v2-p25"),
    (0.5, "house-large-v2-p50"),
    (0.75, "house-large-v2-p75"),
    (1.0, "house-large-v2-shuffled"),
)
SVG_FILE = "fidelity.svg"


def fidelity_rows(submissions: list[tuple[str, dict]], split: str = "test") -> list[dict]:
    """Every gt entry of a ``FIDELITY`` suite but the bounds, by method and p: its SR with the
    95% interval over houses (``sr_house_ci``) and, but for ``REFERENCE``, its SR gain over
    ``REFERENCE`` on the same episodes with the paired interval over houses (``gain``,
    ``gain_house_ci``; None where ``REFERENCE`` is not stored or the episodes differ)."""
    rows = []
    for p, suite in FIDELITY:
        entries = _gt(submissions, suite)
        ref = _split(entries[REFERENCE], split) if REFERENCE in entries else None
        for name in _ordered(n for n in entries if n not in BOUNDS):
            records = _split(entries[name], split)
            gain = paired_gain(records, ref) if ref is not None and name != REFERENCE else None
            rows.append(
                {
                    "name": name,
                    "p": p,
                    "suite": suite,
                    "sr": success_rate(records),
                    "sr_house_ci": _house_interval(house_ci, [records], success_rate),
                    "gain": None if gain is None else gain["sr"],
                    "gain_house_ci": None if gain is None else gain["sr_house_ci"],
                }
            )
    return rows


def render_fidelity(rows: list[dict]) -> list[str]:
    """The markdown of ``fidelity_rows``: a row per method, a column per p (SR and its house
    interval, then the gain over ``REFERENCE`` and its paired house interval)."""
    if not rows:
        return []
    shares = [p for p, _ in FIDELITY]
    lines = [
        "",
        "## The large-house tier, version 2: SR against placement fidelity",
        "",
        "`house-large-v2` with a share p of its objects moved anywhere in the house, onto a receptacle's surface",
        "(`anywhere-P`: `-p25`, `-p50`, `-p75`, and `-shuffled` at p = 1; the moved sets nested as p grows): the same",
        "test houses (50), starts and targets at every p. Each cell: SR on test with its 95% interval over houses;",
        f"below it, the SR gain over `{REFERENCE}` on the same episodes with its paired 95% interval over houses. A",
        f"prior that uses where things are loses its gain as p grows; `{REFERENCE}` should not get easier. gt",
        f"observations, seed 1. The plot: [`{SVG_FILE}`]({SVG_FILE}).",
        "",
        "| Method | " + " | ".join(f"p = {p:g}" for p in shares) + " |",
        "|---" * (1 + len(shares)) + "|",
    ]
    cells = {(r["name"], r["p"]): r for r in rows}
    for name in _ordered({r["name"] for r in rows}):
        out = []
        for p in shares:
            r = cells.get((name, p))
            if r is None:
                out.append("-")
                continue
            text = f"{r['sr']:.2f} ({_range(r['sr_house_ci'])})"
            if r["gain"] is not None:
                low, high = r["gain_house_ci"] or (float("nan"), float("nan"))
                text += f"<br>{r['gain']:+.2f} ({low:+.2f} to {high:+.2f})"
            out.append(text)
        lines.append(f"| {_name(name)} | " + " | ".join(out) + " |")
    return lines


def fidelity_svg(rows: list[dict]) -> str:
    """``fidelity_rows`` as an SVG: SR against p (every method) and SR gain over ``REFERENCE``
    against p (every other method), a line a method with its 95% intervals over houses as bars."""
    names = _ordered({r["name"] for r in rows})
    panels = (
        ("sr", "sr_house_ci", "SR (95% CI over houses)", [r for r in rows if r["sr_house_ci"] is not None]),
        (
            "gain",
            "gain_house_ci",
            f"SR gain over {REFERENCE} (95% CI over houses)",
            [r for r in rows if r["gain_house_ci"] is not None],
        ),
    )
    total_w = 2 * (WIDTH + MARGIN) + GAP + MARGIN // 2
    legend_h = 18 * (len(names) + 2)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{total_w}" height="{HEIGHT + 2 * MARGIN + legend_h}" '
        'font-family="sans-serif" font-size="12">',
        f'<rect width="{total_w}" height="{HEIGHT + 2 * MARGIN + legend_h}" fill="white"/>',
    ]
    for panel, (key, bar, title, mine) in enumerate(panels):
        left = MARGIN + panel * (WIDTH + MARGIN + GAP)
        low = min([-0.05 if key == "gain" else 0.0] + [r[bar][0] for r in mine])
        high = max([0.05 if key == "gain" else 1.0] + [r[bar][1] for r in mine])
        low, high = _floor10(low), -_floor10(-high)

        def x(p: float) -> float:
            return left + p * WIDTH

        def y(value: float) -> float:
            return MARGIN + (high - value) / (high - low) * HEIGHT

        out.append(
            f'<text x="{left + WIDTH / 2}" y="{MARGIN - 16}" text-anchor="middle" font-weight="bold">{title}</text>'
        )
        out.append(f'<rect x="{left}" y="{MARGIN}" width="{WIDTH}" height="{HEIGHT}" fill="none" stroke="#888"/>')
        for tick in _ticks(low, high):
            label = _tick_label(tick) if key == "gain" else f"{tick:.1f}"
            colour = "#444" if tick == 0 and key == "gain" else "#ddd"
            out.append(
                f'<line x1="{left}" x2="{left + WIDTH}" y1="{y(tick):.1f}" y2="{y(tick):.1f}" stroke="{colour}"/>'
            )
            out.append(f'<text x="{left - 6}" y="{y(tick) + 4:.1f}" text-anchor="end">{label}</text>')
        for p, _ in FIDELITY:
            out.append(f'<text x="{x(p):.1f}" y="{MARGIN + HEIGHT + 16}" text-anchor="middle">{p:g}</text>')
        out.append(
            f'<text x="{left + WIDTH / 2}" y="{MARGIN + HEIGHT + 34}" text-anchor="middle">'
            "share of objects moved anywhere (p)</text>"
        )
        for m, name in enumerate(names):
            colour = COLOURS[m % len(COLOURS)]
            line = sorted((r for r in mine if r["name"] == name), key=lambda r: r["p"])
            if not line:  # the reference in the gain panel
                continue
            shift = (m - (len(names) - 1) / 2) * 0.012  # methods side by side
            points = " ".join(f"{x(r['p'] + shift):.1f},{y(r[key]):.1f}" for r in line)
            out.append(f'<polyline points="{points}" fill="none" stroke="{colour}" stroke-width="2"/>')
            for r in line:
                cx, (ci_low, ci_high) = x(r["p"] + shift), r[bar]
                out.append(
                    f'<line x1="{cx:.1f}" x2="{cx:.1f}" y1="{y(ci_low):.1f}" y2="{y(ci_high):.1f}" stroke="{colour}"/>'
                )
                out.append(f'<circle cx="{cx:.1f}" cy="{y(r[key]):.1f}" r="3.5" fill="{colour}"/>')
    out += legend(names, "house-large-v2, objects moved anywhere onto surfaces; gt observations, test episodes.")
    out.append("</svg>")
    return "\n".join(out) + "\n"


def _floor10(value: float) -> float:
    """``value`` rounded down to a tenth."""
    import math

    return math.floor(value * 10) / 10
