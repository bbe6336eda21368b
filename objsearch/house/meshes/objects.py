"""Mesh builders of lamps and small objects: vessels, plants, panels and screens, slabs, pillows, boxes, baskets
(``objsearch.house.meshes``)."""

from __future__ import annotations

import trimesh

from objsearch.house.meshes.primitives import blob, box, cyl, hcyl, legs, revolve


def lamp(style, rng, arm=False):
    """Floor, table and desk lamps: base, stem and a cylinder, cone or ball shade; ``arm`` adds an arm."""
    shade_h = rng.uniform(0.2, 0.32)
    parts = [cyl(0, 0, 0, 0.04, 0.35 if style != 1 else 0.25, 12), cyl(0, 0, 0.04, 1 - shade_h * 0.7, 0.03, 6)]
    if style == 2:
        parts.append(revolve([(0.5, 1 - shade_h), (0.2, 1.0)], n=12))
    elif style == 1:
        parts.append(blob(0, 0, 1 - shade_h / 2, 0.35, 0.35, shade_h / 2))
    else:
        parts.append(cyl(0, 0, 1 - shade_h, 1.0, 0.5 if style == 0 else 0.4, 12))
    if arm:
        parts.append(box(-0.04, -0.04, 0.5, 0.04, 0.4, 0.56))
    return parts, None


def vessel(style, rng, kind):
    """Revolved things: vases, bottles, cups, pots, bins."""
    w = rng.uniform(0.8, 1.0)
    profiles = {
        "vase": [
            [(0.3, 0), (0.5, 0.35), (0.25 * w, 0.8), (0.3, 1.0)],
            [(0.4, 0), (0.5, 0.5), (0.4, 1.0)],
            [(0.25, 0), (0.5, 0.6), (0.2, 0.9), (0.25, 1.0)],
            [(0.5, 0), (0.5, 1.0)],
        ],
        "bottle": [
            [(0.5, 0), (0.5, 0.6), (0.15, 0.8), (0.15, 1.0)],
            [(0.45, 0), (0.5, 0.5), (0.2, 0.75), (0.15, 1.0)],
            [(0.5, 0), (0.5, 0.7), (0.2, 0.85), (0.2, 1.0)],
            [(0.4, 0), (0.5, 0.4), (0.4, 0.7), (0.15, 1.0)],
        ],
        "cup": [
            [(0.4, 0), (0.5, 1.0)],
            [(0.5, 0), (0.5, 1.0)],
            [(0.3, 0), (0.5, 0.7), (0.5, 1.0)],
            [(0.45, 0), (0.38, 0.5), (0.5, 1.0)],
        ],
        "bowl": [
            [(0.25, 0), (0.45, 0.6), (0.5, 1.0)],
            [(0.3, 0), (0.5, 0.4), (0.5, 1.0)],
            [(0.2, 0), (0.5, 1.0)],
            [(0.35, 0), (0.45, 0.3), (0.5, 1.0)],
        ],
        "bin": [
            [(0.42, 0), (0.5, 1.0)],
            [(0.5, 0), (0.5, 1.0)],
            [(0.45, 0), (0.5, 0.9), (0.45, 1.0)],
            [(0.5, 0), (0.42, 1.0)],
        ],
        "candle": [
            [(0.5, 0), (0.5, 0.85), (0.1, 0.9), (0.05, 1.0)],
            [(0.5, 0), (0.45, 0.8), (0.05, 1.0)],
            [(0.5, 0), (0.5, 0.1), (0.3, 0.15), (0.3, 1.0)],
            [(0.4, 0), (0.5, 0.2), (0.35, 0.9), (0.05, 1.0)],
        ],
    }[kind]
    parts = [revolve([(0.0, 0.0)] + profiles[style % 4] + [(0.0, profiles[style % 4][-1][1])])]
    if kind == "cup" and style % 2 == 0:
        parts.append(box(0.4, -0.05, 0.3, 0.5, 0.05, 0.8))  # handle
    if kind == "bowl" and style == 3:
        parts += [blob(x, y, 0.95, 0.12, 0.12, 0.12) for x, y in ((-0.15, 0), (0.15, 0.05), (0, -0.15))]
    return parts, None


def pot(style, rng):
    """Cooking pots: a body with a rim and a lid knob; styles 0 and 2 add two side handles, style 3 one."""
    parts = [cyl(0, 0, 0, 0.85, 0.4, 14), cyl(0, 0, 0.85, 0.9, 0.42, 14)]
    if style in (0, 2):
        parts += [box(-0.5, -0.04, 0.6, -0.4, 0.04, 0.7), box(0.4, -0.04, 0.6, 0.5, 0.04, 0.7)]
    if style != 2:
        parts.append(cyl(0, 0, 0.9, 1.0, 0.08, 8))
    else:
        parts.append(cyl(0, 0, 0.9, 1.0, 0.2, 10))
    if style == 3:
        parts.append(box(0.38, -0.04, 0.4, 0.5, 0.04, 0.5))
    return parts, None


def kettle(style, rng):
    """Kettles: a straight or tapered body, a lid, a spout and a handle."""
    body = cyl(0, 0, 0, 0.75, 0.35, 14) if style % 2 == 0 else revolve([(0, 0), (0.35, 0), (0.3, 0.75), (0, 0.75)])
    return [
        body,
        cyl(0, 0, 0.75, 0.82, 0.1, 8),
        box(-0.05, 0.1, 0.75, 0.05, 0.5, 1.0) if style < 2 else hcyl(-0.5, -0.3, 0, 0.6, 0.05),
        box(-0.05, -0.5, 0.2, 0.05, -0.3, 0.9),
    ], None


def plant(style, rng):
    """Potted plants: a pot with a bush, stems with leaves, upright leaves or clustered balls."""
    pot_h = rng.uniform(0.25, 0.4)
    parts = [cyl(0, 0, 0, pot_h, 0.3 if style != 2 else 0.22, 10)]
    if style == 0:
        parts.append(blob(0, 0, (1 + pot_h) / 2, 0.5, 0.5, (1 - pot_h) / 2))
    elif style == 1:
        parts += [
            cyl(0, 0, pot_h, 0.7, 0.03, 6),
            blob(0, 0, 0.82, 0.45, 0.45, 0.18),
            blob(0.2, 0.1, 0.62, 0.2, 0.2, 0.12),
        ]
    elif style == 2:
        parts += [box(-0.04 + dx, -0.04, pot_h, 0.04 + dx, 0.04, 1.0 - abs(dx)) for dx in (-0.2, 0.0, 0.2)]
    else:
        parts += [
            blob(dx, dy, pot_h + 0.25, 0.25, 0.25, 0.25) for dx, dy in ((-0.2, -0.2), (0.2, 0.2), (0.2, -0.2))
        ] + [blob(0, 0, 0.75, 0.35, 0.35, 0.25)]
    return parts, None


def panel(style, rng, frame=True):
    """Wall-mounted flat things (painting, mirror, whiteboard): back at y = -0.5."""
    parts = [box(-0.5, -0.5, 0, 0.5, 0.1, 1.0)]
    if frame and style != 1:
        f = 0.06 if style == 0 else 0.1
        parts += [
            box(-0.5, 0.1, 0, 0.5, 0.5, f),
            box(-0.5, 0.1, 1 - f, 0.5, 0.5, 1),
            box(-0.5, 0.1, 0, -0.5 + f, 0.5, 1),
            box(0.5 - f, 0.1, 0, 0.5, 0.5, 1),
        ]
    else:
        parts.append(box(-0.45, 0.1, 0.05, 0.45, 0.5, 0.95))
    if style == 3:
        parts.append(box(-0.3, 0.1, 0.0, 0.3, 0.5, 0.04))  # ledge
    return parts, None


def clock(style, rng):
    """Wall clocks: a round face (style 1: a square one) with hands."""
    if style == 1:
        return [box(-0.5, -0.5, 0, 0.5, 0.3, 1.0), box(-0.05, 0.3, 0.45, 0.05, 0.5, 0.85)], None
    body = trimesh.creation.cylinder(radius=0.5, segment=[[0, -0.5, 0.5], [0, 0.3, 0.5]], sections=16)
    parts = [body, box(-0.03, 0.3, 0.5, 0.03, 0.5, 0.9 if style == 0 else 0.8), box(0.0, 0.3, 0.47, 0.3, 0.5, 0.53)]
    if style == 3:
        parts.append(box(-0.08, -0.5, 0.0, 0.08, 0.0, 0.1))
    return parts, None


def screen(style, rng, stand=True):
    """TV / monitor: a panel with a foot; front +y."""
    foot = 0.1 if stand else 0.0
    parts = [box(-0.5, -0.1, foot, 0.5, 0.1, 1.0)]
    if stand:
        if style in (0, 3):
            parts += [box(-0.15, -0.5, 0, 0.15, 0.5, 0.03), box(-0.04, -0.1, 0.03, 0.04, 0.05, foot + 0.05)]
        else:
            parts += [
                box(-0.45, -0.5, 0, -0.35, 0.5, 0.03),
                box(0.35, -0.5, 0, 0.45, 0.5, 0.03),
                box(-0.42, -0.05, 0, -0.38, 0.05, foot + 0.05),
                box(0.38, -0.05, 0, 0.42, 0.05, foot + 0.05),
            ]
    if style == 2:
        parts.append(box(-0.2, -0.5, foot, 0.2, -0.1, 0.6))  # back box
    if style == 3:
        parts.append(box(-0.5, -0.1, foot, 0.5, 0.2, foot + 0.08))  # sound bar
    return parts, None


def laptop(style, rng):
    """Laptops: a base and an upright lid at the back edge (higher styles move it forward)."""
    return [
        box(-0.5, -0.5, 0, 0.5, 0.5, 0.08),
        box(-0.5, -0.5 + 0.05 * style, 0.08, 0.5, -0.4 + 0.05 * style, 1.0),
    ], None


def slab(style, rng, keys=False):
    """Flat small things: book, keyboard, remote, pillow."""
    parts = [box(-0.5, -0.5, 0, 0.5, 0.5, 0.7 + 0.1 * style)]
    if keys:
        parts += [box(-0.45 + 0.2 * i, -0.4, 0.7, -0.3 + 0.2 * i, 0.4, 1.0) for i in range(5)]
    else:
        parts.append(box(-0.48, -0.48, 0.5, 0.48 - 0.05 * style, 0.48, 1.0))
    return parts, None


def pillow(style, rng):
    """Pillows: a puffed box, a ball, a plain box or two side-by-side rolls."""
    if style == 0:
        return [box(-0.5, -0.5, 0.1, 0.5, 0.5, 0.9), blob(0, 0, 0.5, 0.45, 0.45, 0.5)], None
    if style == 1:
        return [blob(0, 0, 0.5, 0.5, 0.5, 0.5)], None
    if style == 2:
        return [box(-0.5, -0.5, 0, 0.5, 0.5, 1.0)], None
    return [blob(-0.25, 0, 0.5, 0.25, 0.5, 0.5), blob(0.25, 0, 0.5, 0.25, 0.5, 0.5)], None


def small_box(style, rng):
    """Microwave, toaster, printer, alarm clock: a box with a face detail."""
    parts = [box(-0.5, -0.5, 0, 0.5, 0.42, 1.0 if style != 2 else 0.85)]
    if style == 0:
        parts.append(box(-0.45, 0.42, 0.1, 0.2, 0.5, 0.9))
    elif style == 1:
        parts += [box(0.25, 0.42, 0.1, 0.45, 0.5, 0.9), box(-0.3, -0.3, 0.9, 0.3, 0.3, 1.0)]
    elif style == 2:
        parts += [box(-0.4, -0.4, 0.85, 0.4, 0.3, 1.0), box(-0.45, 0.42, 0.2, 0.45, 0.5, 0.4)]
    else:
        parts += legs(0.4, 0.35, 0, 0.06, 0.06) + [box(-0.45, 0.42, 0.5, 0.45, 0.5, 0.6)]
    return parts, None


def basket(style, rng):
    """Laundry baskets: a square or round (style 2) body with a handle bar across the top."""
    parts = [box(-0.5, -0.5, 0, 0.5, 0.5, 0.85 + 0.05 * style)] if style != 2 else [cyl(0, 0, 0, 0.9, 0.5, 12)]
    parts.append(box(-0.5, -0.05, 0.8, 0.5, 0.05, 1.0))
    return parts, None
