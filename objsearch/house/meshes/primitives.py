"""The parts every mesh builder assembles (boxes, cylinders, solids of revolution, blobs, legs)
and the support surface type (``objsearch.house.meshes``)."""

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
