"""The one place MJCF is written: ``HouseSpec`` -> ``mujoco.MjSpec`` -> XML.

Why ``MjSpec`` (MuJoCo's own model-editing API) rather than dm_control's ``mjcf``: it is
part of the ``mujoco`` package (no second object model to keep in sync with the
compiler), it compiles in memory without a round-trip through XML text, and its XML
writer is deterministic, which the byte-identical ``house.xml`` needs. Building and
compiling a house this way takes a few milliseconds (``benchmarks/bench_house_gen.py``).

Naming (what a renderer relies on to turn geom ids into segmentation labels):

* every object is a static body named ``<category>_<instance>`` (e.g. ``chair_3``) with one
  mesh geom of the same name, and a mesh asset of the same name;
* structure geoms are ``wall_w<k>`` (category ``wall``), ``floor_r<room>`` (``floor``) and
  ``door_d<k>`` (the lintel over door k, category ``door``; an entrance's lintel spans the
  whole outer wall);
* a room that is not a rectangle (an L, from ``house-gen-2``) gets one floor box over its
  bounding box, ``FLOOR_SINK`` lower than the others: where the box reaches into the
  neighbouring room, that room's floor covers it. One box per room keeps ``floor_r<room>``
  the room's plan box, which the renderer's portal culling reads (it is conservative for an
  L: the box only adds to the room); the floor of the room with the entrance reaches under
  the outer wall on that side, so the outer skin seen through the entrance belongs to it;
* so for every named geom the category is ``name.rsplit("_", 1)[0]`` and its id is
  ``categories.CATEGORY_IDS[category]``; ``geom_labels(model)`` does this for a compiled
  model and returns per-geom category ids and instance numbers (-1 for structure).

Meshes: ``house.xml`` uses ``meshdir="meshes"`` and files ``<category>/<variant>.obj``;
``objsearch generate`` copies the variants a house uses into ``<house dir>/meshes/``, so a
house directory is self-contained and compiles wherever it is moved. In memory the same
files are supplied through ``MjSpec.assets`` (no disk access per house).
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from objsearch.house import assets
from objsearch.house.categories import CATEGORY_IDS
from objsearch.house.spec import OUTSIDE, HouseSpec

FLOOR_THICKNESS = 0.05
FLOOR_SINK = 0.002


def _quat(yaw_deg: int) -> list[float]:
    a = math.radians(yaw_deg) / 2
    return [round(math.cos(a), 6), 0.0, 0.0, round(math.sin(a), 6)]


def _under_entrance(bounds, door, spec: HouseSpec):
    """``bounds`` grown under the outer wall on the entrance's side (a threshold), so that the outer
    skin beside the opening, which is seen through it, overlaps the room's floor box."""
    x0, y0, x1, y1 = bounds
    t = spec.wall_thickness / 2
    cx, cy = door.center
    if door.axis == "x":
        return (x0, y0 - t, x1, y1) if abs(cy - y0) < 1e-6 else (x0, y0, x1, y1 + t)
    return (x0 - t, y0, x1, y1) if abs(cx - x0) < 1e-6 else (x0, y0, x1 + t, y1)


def build_mjspec(spec: HouseSpec) -> mujoco.MjSpec:
    """The ``MjSpec`` of a house: materials, light, floors, walls, doors and one mesh body per object."""
    s = mujoco.MjSpec()
    s.modelname = spec.house_id
    s.meshdir = "meshes"
    s.compiler.degree = False
    s.visual.headlight.ambient = [0.35, 0.35, 0.35]
    s.visual.headlight.diffuse = [0.5, 0.5, 0.5]
    files = {}
    for m in spec.materials:
        if m.texture == "checker":
            tex = s.add_texture(
                name=f"tex_{m.name}",
                type=mujoco.mjtTexture.mjTEXTURE_2D,
                builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
                rgb1=list(m.rgba[:3]),
                rgb2=list(m.rgba2[:3]),
                width=64,
                height=64,
            )
            mat = s.add_material(name=m.name, texrepeat=[m.repeat, m.repeat], texuniform=True)
            mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = tex.name
        else:
            mat = s.add_material(name=m.name, rgba=list(m.rgba))
    world = s.worldbody
    width, depth = spec.footprint
    world.add_light(
        name="sun",
        pos=[width / 2, depth / 2, 6.0],
        dir=[0.3, 0.2, -1.0],
        type=mujoco.mjtLightType.mjLIGHT_DIRECTIONAL,
        diffuse=[0.6, 0.6, 0.6],
        castshadow=False,
    )
    entrance = spec.entrance
    for r in spec.rooms:
        x0, y0, x1, y1 = r.bounds
        if entrance is not None and max(entrance.rooms) == r.id:
            x0, y0, x1, y1 = _under_entrance((x0, y0, x1, y1), entrance, spec)
        sink = 0.0 if len(r.polygon) == 4 else FLOOR_SINK
        world.add_geom(
            name=f"floor_r{r.id}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            material=r.floor_material,
            pos=[(x0 + x1) / 2, (y0 + y1) / 2, -FLOOR_THICKNESS / 2 - sink],
            size=[(x1 - x0) / 2, (y1 - y0) / 2, FLOOR_THICKNESS / 2],
        )
    for w in spec.walls:
        x0, y0, x1, y1 = w.box
        world.add_geom(
            name=f"wall_w{w.id}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            material=w.material,
            pos=[(x0 + x1) / 2, (y0 + y1) / 2, w.height / 2],
            size=[(x1 - x0) / 2, (y1 - y0) / 2, w.height / 2],
        )
    t = spec.wall_thickness / 2
    for d in spec.doors:
        hx, hy = (d.width / 2, t) if d.axis == "x" else (t, d.width / 2)
        hz = (spec.wall_height - d.height) / 2
        world.add_geom(
            name=f"door_d{d.id}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            material=spec.room(max(d.rooms)).wall_material
            if OUTSIDE in d.rooms
            else spec.room(d.rooms[0]).wall_material,
            pos=[d.center[0], d.center[1], d.height + hz],
            size=[hx, hy, hz],
        )
    for o in spec.objects:
        f = assets.mesh_file(o.category, o.variant)
        files[f] = assets.mesh_bytes(o.category, o.variant)
        mesh = s.add_mesh(name=o.name, file=f, scale=list(o.size))
        mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_CONVEX
        body = world.add_body(name=o.name, pos=list(o.position), quat=_quat(o.yaw))
        body.add_geom(name=o.name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=o.name, rgba=list(o.rgba))
    s.assets = files
    return s


def compile_house(spec: HouseSpec) -> tuple[mujoco.MjModel, str]:
    """Compile the house in memory; return the model and its MJCF text."""
    s = build_mjspec(spec)
    model = s.compile()
    return model, s.to_xml()


def geom_labels(model: mujoco.MjModel) -> tuple[np.ndarray, np.ndarray]:
    """Per-geom (category id, instance) from geom names; unnamed geoms are background (0, -1)."""
    cats = np.zeros(model.ngeom, dtype=np.int32)
    inst = np.full(model.ngeom, -1, dtype=np.int32)
    for g in range(model.ngeom):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, g) or ""
        head, _, tail = name.rpartition("_")
        if head in CATEGORY_IDS:
            cats[g] = CATEGORY_IDS[head]
            inst[g] = int(tail) if tail.isdigit() else -1
    return cats, inst
