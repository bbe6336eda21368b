"""Mesh builders of furniture: tables, cabinets and shelves, seats, chairs, beds, racks (``objsearch.house.meshes``)."""

from __future__ import annotations

from objsearch.house.meshes.primitives import FULL_TOP, box, cyl, legs


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
