"""Parametric low-poly furniture built with trimesh: one builder per shape family.

Every mesh is built in the unit box x, y in [-0.5, 0.5], z in [0, 1] with the object's
front towards +y (backs go against walls), then normalised to exactly that box, so an
instance of size (w, d, h) is the mesh scaled by (w, d, h). Receptacles also report their
support surface ``(z, x0, y0, x1, y1)`` in the same unit frame (where things may stand).

A variant is ``(style, rng)``: the style picks the construction (legs vs. panels, round vs.
square, arms or not), the rng (seeded from the category id and variant index by
``objsearch.house.assets``) jitters proportions. Builders use no other randomness.
"""

from __future__ import annotations

import numpy as np
import trimesh

Surface = tuple[float, float, float, float, float]
FULL_TOP: Surface = (1.0, -0.5, -0.5, 0.5, 0.5)


def box(x0, y0, z0, x1, y1, z1) -> trimesh.Trimesh:
    """An axis-aligned box with corners (x0, y0, z0) and (x1, y1, z1)."""
    m = trimesh.creation.box(extents=[x1 - x0, y1 - y0, z1 - z0])
    m.apply_translation([(x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2])
    return m


def cyl(cx, cy, z0, z1, r, n=12) -> trimesh.Trimesh:
    """An upright cylinder of radius ``r`` centred at (cx, cy) from z0 to z1, with ``n`` sides."""
    m = trimesh.creation.cylinder(radius=r, height=z1 - z0, sections=n)
    m.apply_translation([cx, cy, (z0 + z1) / 2])
    return m


def hcyl(x0, x1, y, z, r, n=10) -> trimesh.Trimesh:
    """A cylinder lying along x."""
    return trimesh.creation.cylinder(radius=r, segment=[[x0, y, z], [x1, y, z]], sections=n)


def revolve(profile, n=14) -> trimesh.Trimesh:
    """Surface of revolution about the z axis from (radius, z) points, bottom to top."""
    pts = np.asarray(profile, dtype=float)
    return trimesh.creation.revolve(pts, sections=n)


def blob(cx, cy, cz, rx, ry, rz) -> trimesh.Trimesh:
    """An ellipsoid (a coarse icosphere) centred at (cx, cy, cz) with semi-axes rx, ry, rz."""
    m = trimesh.creation.icosphere(subdivisions=1, radius=1.0)
    m.apply_scale([rx, ry, rz])
    m.apply_translation([cx, cy, cz])
    return m


def legs(x, y, z0, z1, t, round_=False):
    """Four legs inset at +-x, +-y."""
    if round_:
        return [cyl(sx * x, sy * y, z0, z1, t / 2, 8) for sx in (-1, 1) for sy in (-1, 1)]
    return [
        box(sx * x - t / 2, sy * y - t / 2, z0, sx * x + t / 2, sy * y + t / 2, z1) for sx in (-1, 1) for sy in (-1, 1)
    ]


# --- families -------------------------------------------------------------------------


def table(style, rng):
    """Tables, desks, benches and stools: a top on four legs, panel ends, a pedestal or legs with a shelf."""
    top = rng.uniform(0.06, 0.12)
    t = rng.uniform(0.06, 0.1)
    z = 1 - top
    parts = [box(-0.5, -0.5, z, 0.5, 0.5, 1.0)]
    if style == 0:
        parts += legs(0.5 - t, 0.5 - t, 0, z, t * 1.4)
    elif style == 1:  # panel ends
        parts += [
            box(-0.46, -0.4, 0, -0.46 + t, 0.4, z),
            box(0.46 - t, -0.4, 0, 0.46, 0.4, z),
            box(-0.46, -0.05, 0.1, 0.46, 0.05, 0.18),
        ]
    elif style == 2:  # pedestal
        parts += [cyl(0, 0, 0.05, z, 0.1), cyl(0, 0, 0, 0.05, 0.35, 16)]
        parts[0] = cyl(0, 0, z, 1.0, 0.5, 20)
    else:  # legs and a lower shelf
        parts += legs(0.5 - t, 0.5 - t, 0, z, t, round_=True) + [box(-0.45, -0.45, 0.2, 0.45, 0.45, 0.24)]
    return parts, FULL_TOP


def cabinet(style, rng, drawers=3, plinth=True):
    """Cabinets, dressers, wardrobes: a carcass with ``drawers`` (varied by style) fronts and handles."""
    depth = 0.46
    base = 0.08 if plinth else 0.0
    parts = [box(-0.5, -0.5, base, 0.5, depth - 0.5 + 0.5, 1.0)]
    if plinth:
        parts.append(box(-0.47, -0.47, 0, 0.47, 0.4, base))
    n = max(1, drawers + (style % 2) - (style // 2))
    gap = (1.0 - base) / n
    for i in range(n):  # fronts with handles
        z0 = base + i * gap + 0.02
        parts.append(box(-0.46, 0.46, z0, 0.46, 0.48, z0 + gap - 0.04))
        if style == 2:
            parts.append(box(-0.2, 0.48, z0 + gap * 0.6, 0.2, 0.5, z0 + gap * 0.7))
        else:
            parts.append(cyl(-0.25 if style == 3 else 0.0, 0.49, z0 + gap * 0.5, z0 + gap * 0.5 + 0.05, 0.012, 6))
    return parts, FULL_TOP


def shelf(style, rng):
    """Open shelving (bookshelf, shoe rack): sides, back and 4-6 boards; style 3 adds a closed bottom."""
    t = rng.uniform(0.03, 0.05)
    n = 3 + style % 3
    parts = [
        box(-0.5, -0.5, 0, -0.5 + t, 0.5, 1),
        box(0.5 - t, -0.5, 0, 0.5, 0.5, 1),
        box(-0.5, -0.5, 0, 0.5, -0.45, 1),
    ]
    for i in range(n + 1):
        z = min(i / n, 1 - t)
        parts.append(box(-0.5, -0.5, z, 0.5, 0.5, z + t))
    if style == 3:
        parts.append(box(-0.5 + t, -0.45, 0, 0.5 - t, 0.5, 0.3))  # closed bottom cupboard
    return parts, FULL_TOP


def seat(style, rng, arms=False, legs_h=0.1, seat_z=0.45, back=0.25):
    """Sofas, armchairs, ottomans: a seat block on legs or a plinth with a back and optional arms.

    ``legs_h``, ``seat_z`` and ``back`` (arm height above the seat) are in the unit frame.
    """
    parts = []
    back_t = rng.uniform(0.12, 0.2) if arms else rng.uniform(0.06, 0.1)
    if style in (0, 2):
        parts += legs(0.44, 0.44, 0, legs_h + 0.02, 0.06, round_=style == 2)
        low = legs_h
    else:
        parts.append(box(-0.48, -0.48, 0, 0.48, 0.48, legs_h))
        low = legs_h
    parts.append(box(-0.5, -0.5, low, 0.5, 0.5, seat_z))
    parts.append(box(-0.5, -0.5, seat_z, 0.5, -0.5 + back_t, 1.0 if style != 3 else 0.9))
    if arms and style != 1:
        a = rng.uniform(0.08, 0.15)
        az = seat_z + back
        parts += [box(-0.5, -0.5, low, -0.5 + a, 0.45, az), box(0.5 - a, -0.5, low, 0.5, 0.45, az)]
    if style == 3:
        parts.append(cyl(0, -0.5 + back_t / 2, 0.9, 1.0, 0.05))
    return parts, None


def chair(style, rng):
    """Dining chairs: legs or panel sides, a seat and a solid or framed back."""
    if style == 1:  # chair with panel sides instead of legs
        t = 0.06
        return [
            box(-0.5, -0.5, 0, -0.5 + t, 0.5, 0.45),
            box(0.5 - t, -0.5, 0, 0.5, 0.5, 0.45),
            box(-0.5, -0.5, 0.4, 0.5, 0.5, 0.47),
            box(-0.5, -0.5, 0.47, 0.5, -0.42, 1.0),
        ], None
    parts = legs(0.45, 0.45, 0, 0.42, 0.07, round_=style == 2)
    parts.append(box(-0.5, -0.5, 0.42, 0.5, 0.5, 0.48))
    if style == 3:
        parts += [
            box(-0.5, -0.5, 0.48, -0.42, -0.42, 1.0),
            box(0.42, -0.5, 0.48, 0.5, -0.42, 1.0),
            box(-0.5, -0.5, 0.8, 0.5, -0.42, 1.0),
        ]
    else:
        parts.append(box(-0.5, -0.5, 0.48, 0.5, -0.42, 1.0))
    return parts, None


def office_chair(style, rng):
    """Office chairs: a cross base, a column, seat and back; styles add arms and a head rest."""
    parts = [box(-0.5, -0.04, 0, 0.5, 0.04, 0.05), box(-0.04, -0.5, 0, 0.04, 0.5, 0.05), cyl(0, 0, 0.05, 0.42, 0.04)]
    parts.append(box(-0.4, -0.4, 0.42, 0.4, 0.4, 0.5))
    parts.append(box(-0.36, -0.42, 0.5, 0.36, -0.34, 1.0 if style != 1 else 0.8))
    if style == 1:
        parts.append(box(-0.01, -0.01, 0.99, 0.01, 0.01, 1.0))
    if style >= 2:
        parts += [box(-0.42, -0.3, 0.5, -0.36, 0.25, 0.68), box(0.36, -0.3, 0.5, 0.42, 0.25, 0.68)]
    if style == 3:
        parts.append(box(-0.2, -0.45, 0.88, 0.2, -0.34, 1.0))  # head rest
    return parts, None


def bed(style, rng):
    """Beds: headboard, frame on legs or a base, mattress; style 2 adds a footboard. Surface: the mattress."""
    mattress = 0.5
    frame = rng.uniform(0.2, 0.3)
    parts = [box(-0.5, -0.5, 0, 0.5, -0.44, 1.0)]  # headboard
    if style in (0, 3):
        parts += legs(0.46, 0.46, 0, frame, 0.06) + [box(-0.5, -0.44, frame, 0.5, 0.5, frame + 0.08)]
    else:
        parts.append(box(-0.5, -0.44, 0, 0.5, 0.5, frame + 0.08))
    parts.append(box(-0.48, -0.44, frame + 0.08, 0.48, 0.48, mattress))
    if style == 2:
        parts.append(box(-0.5, 0.46, 0, 0.5, 0.5, mattress + 0.08))  # footboard
        return parts, (mattress, -0.48, -0.44, 0.48, 0.46)
    return parts, (mattress, -0.48, -0.44, 0.48, 0.48)


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


def rack(style, rng):
    """Coat rack: pole with hooks on a base."""
    parts = [cyl(0, 0, 0, 0.05, 0.45 if style != 1 else 0.3, 10), cyl(0, 0, 0.05, 1.0, 0.05, 8)]
    parts += [
        box(-0.5, -0.04, 0.85 - 0.05 * style, 0.5, 0.04, 0.9 - 0.05 * style),
        box(-0.04, -0.5, 0.8, 0.04, 0.5, 0.85),
    ]
    if style == 1:
        parts += legs(0.4, 0.4, 0, 0.05, 0.1)
    return parts, None


def basket(style, rng):
    """Laundry baskets: a square or round (style 2) body with a handle bar across the top."""
    parts = [box(-0.5, -0.5, 0, 0.5, 0.5, 0.85 + 0.05 * style)] if style != 2 else [cyl(0, 0, 0, 0.9, 0.5, 12)]
    parts.append(box(-0.5, -0.05, 0.8, 0.5, 0.05, 1.0))
    return parts, None


def _cabinet(**kw):
    return lambda style, rng: cabinet(style, rng, **kw)


def _seat(**kw):
    return lambda style, rng: seat(style, rng, **kw)


def _vessel(kind):
    return lambda style, rng: vessel(style, rng, kind)


BUILDERS = {
    "sofa": _seat(arms=True, seat_z=0.45, back=0.2),
    "armchair": _seat(arms=True, seat_z=0.45, back=0.25),
    "coffee_table": table,
    "tv": lambda s, r: screen(s, r),
    "tv_stand": _cabinet(drawers=1),
    "bookshelf": shelf,
    "floor_lamp": lambda s, r: lamp(s, r),
    "side_table": table,
    "plant": plant,
    "painting": lambda s, r: panel(s, r),
    "ottoman": _seat(legs_h=0.08, seat_z=0.95, back=0.0),
    "clock": clock,
    "vase": _vessel("vase"),
    "book": lambda s, r: slab(s, r),
    "remote_control": lambda s, r: slab(s, r, keys=True),
    "counter": counter,
    "kitchen_sink": kitchen_sink,
    "stove": lambda s, r: appliance(s, r, burners=True),
    "fridge": lambda s, r: appliance(s, r, tall=True),
    "microwave": small_box,
    "toaster": small_box,
    "kettle": kettle,
    "dishwasher": lambda s, r: appliance(s, r),
    "trash_can": _vessel("bin"),
    "pot": pot,
    "fruit_bowl": _vessel("bowl"),
    "bottle": _vessel("bottle"),
    "cup": _vessel("cup"),
    "plate": _vessel("bowl"),
    "dining_table": table,
    "chair": chair,
    "sideboard": _cabinet(drawers=2),
    "candle": _vessel("candle"),
    "bed": bed,
    "nightstand": _cabinet(drawers=2),
    "table_lamp": lambda s, r: lamp(s, r),
    "wardrobe": _cabinet(drawers=1, plinth=True),
    "dresser": _cabinet(drawers=3),
    "mirror": lambda s, r: panel(s, r),
    "pillow": pillow,
    "alarm_clock": small_box,
    "laptop": laptop,
    "toilet": toilet,
    "sink": sink,
    "bathtub": bathtub,
    "towel": towel,
    "toilet_paper": toilet_paper,
    "soap": _vessel("bottle"),
    "laundry_basket": basket,
    "desk": table,
    "office_chair": office_chair,
    "computer": lambda s, r: screen(s, r),
    "keyboard": lambda s, r: slab(s, r, keys=True),
    "filing_cabinet": _cabinet(drawers=3, plinth=False),
    "printer": small_box,
    "desk_lamp": lambda s, r: lamp(s, r, arm=True),
    "whiteboard": lambda s, r: panel(s, r),
    "shoe_rack": shelf,
    "coat_rack": rack,
    "bench": table,
    "stool": table,
}


def build(category: str, style: int, rng: np.random.Generator) -> tuple[trimesh.Trimesh, Surface | None]:
    """The mesh of one variant, normalised to the unit box, and its support surface."""
    parts, surface = BUILDERS[category](style, rng)
    mesh = trimesh.util.concatenate(parts)
    lo, hi = mesh.bounds
    scale = 1.0 / (hi - lo)
    offset = np.array([-0.5, -0.5, 0.0]) - lo * scale
    mesh.vertices = mesh.vertices * scale + offset
    if surface is not None:
        z, x0, y0, x1, y1 = surface
        surface = (
            float(z * scale[2] + offset[2]),
            float(x0 * scale[0] + offset[0]),
            float(y0 * scale[1] + offset[1]),
            float(x1 * scale[0] + offset[0]),
            float(y1 * scale[1] + offset[1]),
        )
    return mesh, surface


def to_obj(mesh: trimesh.Trimesh) -> bytes:
    """Wavefront OBJ with fixed formatting (deterministic bytes, no header)."""
    v = np.round(mesh.vertices, 4) + 0.0  # + 0.0 turns -0.0 into 0.0
    lines = [f"v {x:.4f} {y:.4f} {z:.4f}" for x, y, z in v]
    lines += [f"f {a} {b} {c}" for a, b, c in mesh.faces + 1]
    return ("\n".join(lines) + "\n").encode()
