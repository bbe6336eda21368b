"""Which builder makes each category (``BUILDERS``), and a variant's mesh normalised to the unit
box (``build``) and written as OBJ (``to_obj``) (``objsearch.house.meshes``)."""

from __future__ import annotations

import numpy as np
import trimesh

from objsearch.house.meshes.fixtures import appliance, bathtub, counter, kitchen_sink, sink, toilet, toilet_paper, towel
from objsearch.house.meshes.furniture import bed, cabinet, chair, office_chair, rack, seat, shelf, table
from objsearch.house.meshes.objects import (
    basket,
    clock,
    kettle,
    lamp,
    laptop,
    panel,
    pillow,
    plant,
    pot,
    screen,
    slab,
    small_box,
    vessel,
)
from objsearch.house.meshes.primitives import Surface


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
