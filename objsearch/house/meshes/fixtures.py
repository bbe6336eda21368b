"""Mesh builders of kitchen and bathroom fixtures: appliances, counters, sinks, toilets, bathtubs, towels
(``objsearch.house.meshes``)."""

from __future__ import annotations

from objsearch.house.meshes.primitives import FULL_TOP, blob, box, cyl, hcyl, legs


def appliance(style, rng, tall=False, burners=False):
    """Fridges, stoves, dishwashers: a box with doors and handles.

    ``tall`` gives two doors split at 0.6-0.8 of the height (fridge); ``burners`` adds four knobs (stove).
    """
    parts = [box(-0.5, -0.5, 0.0, 0.5, 0.45, 1.0)]
    if tall:
        split = 0.6 + 0.1 * (style % 3)
        parts += [box(-0.48, 0.45, 0.02, 0.48, 0.47, split - 0.01), box(-0.48, 0.45, split + 0.01, 0.48, 0.47, 0.98)]
        hx = 0.38 if style != 3 else -0.38
        parts += [
            box(hx - 0.02, 0.47, split - 0.2, hx + 0.02, 0.5, split - 0.02),
            box(hx - 0.02, 0.47, split + 0.02, hx + 0.02, 0.5, split + 0.25),
        ]
    else:
        parts += [
            box(-0.46, 0.45, 0.08, 0.46, 0.47, 0.75),
            box(-0.4, 0.47, 0.7 - 0.05 * style, 0.4, 0.5, 0.73 - 0.05 * style),
        ]
        if burners:
            parts += [box(-0.35 + 0.2 * i, 0.45, 0.85, -0.3 + 0.2 * i, 0.5, 0.9) for i in range(4)]  # knobs
    return parts, FULL_TOP


def counter(style, rng):
    """Kitchen counters: a worktop over a carcass with 1-3 doors; style 3 adds a rail."""
    parts = [
        box(-0.5, -0.5, 0.96, 0.5, 0.5, 1.0),
        box(-0.48, -0.5, 0.1, 0.48, 0.42, 0.96),
        box(-0.46, -0.5, 0, 0.46, 0.36, 0.1),
    ]
    n = 1 + style % 3
    for i in range(n):
        x0 = -0.46 + i * 0.92 / n
        parts.append(box(x0 + 0.01, 0.42, 0.12, x0 + 0.92 / n - 0.01, 0.44, 0.9))
    if style == 3:
        parts.append(box(-0.46, 0.44, 0.5, 0.46, 0.47, 0.53))  # rail
    return parts, FULL_TOP


def kitchen_sink(style, rng):
    """Kitchen sinks (set on a counter): a basin slab with a faucet."""
    parts = [box(-0.5, -0.1, 0, 0.5, 0.5, 0.12)]
    faucet_x = 0.0 if style != 2 else 0.3
    parts += [
        cyl(faucet_x, -0.3, 0, 0.9, 0.04, 8),
        box(faucet_x - 0.03, -0.3, 0.85, faucet_x + 0.03, 0.1 if style != 1 else -0.05, 1.0),
    ]
    if style == 3:
        parts.append(box(-0.5, -0.5, 0, 0.5, -0.4, 0.05))
    return parts, None


def toilet(style, rng):
    """Toilets: a cistern, a round or square base and a seat; style 3 adds a flush button."""
    parts = [box(-0.5, -0.5, 0.45, 0.5, -0.2, 1.0)] if style != 2 else [box(-0.5, -0.5, 0.5, 0.5, -0.3, 0.8)]
    parts.append(box(-0.3, -0.3, 0, 0.3, 0.2, 0.45) if style % 2 else cyl(0, -0.05, 0, 0.45, 0.3, 10))
    if style == 3:
        parts.append(box(-0.2, -0.5, 0.95, 0.2, -0.3, 1.0))  # flush button
    parts.append(blob(0, 0.1, 0.47, 0.5, 0.4, 0.1))
    return parts, None


def sink(style, rng):
    """Bathroom sinks: a vanity, a pedestal or a wall-hung basin with a tap. Surface: the basin top."""
    if style in (0, 3):  # vanity
        parts = [box(-0.5, -0.5, 0, 0.5, 0.42, 0.88), box(-0.5, -0.5, 0.88, 0.5, 0.5, 0.94)]
        if style == 3:
            parts.append(box(-0.45, 0.42, 0.1, 0.45, 0.45, 0.8))
    else:  # pedestal (style 1) or wall-hung with a trap (style 2)
        parts = [
            cyl(0, -0.1, 0, 0.75, 0.12, 8) if style == 1 else cyl(0, -0.3, 0.3, 0.75, 0.05, 6),
            box(-0.5, -0.5, 0.75, 0.5, 0.5, 0.94),
        ]
        if style == 2:
            parts.append(box(-0.05, -0.5, 0, 0.05, -0.45, 0.3))
    parts += [cyl(0, -0.4, 0.94, 1.0, 0.03, 6)]
    return parts, (0.94, -0.5, -0.3, 0.5, 0.5)


def bathtub(style, rng):
    """Bathtubs: a floor and four walls; styles add feet, a tap, an apron and a rim."""
    t = 0.08
    parts = [
        box(-0.5, -0.5, 0, 0.5, 0.5, 0.15),
        box(-0.5, -0.5, 0, -0.5 + t, 0.5, 1),
        box(0.5 - t, -0.5, 0, 0.5, 0.5, 1),
        box(-0.5, -0.5, 0, 0.5, -0.5 + t * 1.5, 1),
        box(-0.5, 0.5 - t * 1.5, 0, 0.5, 0.5, 1),
    ]
    if style == 1:
        parts += legs(0.45, 0.4, 0, 0.1, 0.06)
    if style == 2:
        parts.append(box(0.3, -0.5, 0.85, 0.42, -0.4, 1.0))  # tap
    if style == 3:
        parts.append(box(-0.5, 0.5 - t * 1.5, 0, 0.5, 0.5, 0.2))  # front apron
        parts.append(box(-0.5, -0.5, 0.9, -0.3, 0.5, 1.0))  # rolled rim
    return parts, None


def towel(style, rng):
    """Towels hanging on a rail; style 3 adds a second, shorter towel."""
    parts = [hcyl(-0.5, 0.5, -0.3, 0.95, 0.05), box(-0.45, -0.2, 0.0 if style != 1 else 0.2, 0.45, 0.5, 0.93)]
    if style == 2:
        parts.append(box(-0.5, -0.5, 0.9, -0.45, -0.3, 1.0))
    if style == 3:
        parts.append(box(-0.45, -0.2, 0.0, 0.0, 0.5, 0.5))  # second, shorter towel
    return parts, None


def toilet_paper(style, rng):
    """Toilet-paper holders: a wall plate with a roll."""
    parts = [
        box(-0.5, -0.5, 0.2 if style != 2 else 0.0, 0.5, -0.35, 1.0),
        hcyl(-0.45, 0.45, 0.05, 0.55, 0.42 if style != 1 else 0.35),
    ]
    if style == 3:
        parts.append(box(-0.5, -0.5, 0.95, 0.5, 0.5, 1.0))
    return parts, None
