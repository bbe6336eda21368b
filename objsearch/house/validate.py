"""Checks every generated house must pass (``validate_house``).

1. **Compiles** (done by the caller: the model is an argument).
2. **No interpenetration**: object boxes (the exact bounds of their scaled meshes) overlap
   no wall or door lintel and no other object by more than ``TOL``, except an object
   standing on its ``parent``, which must lie inside the parent's support surface, at or
   above its height; every object is above the floor and below the wall top.
3. **Rooms reachable**: on the 0.05 m occupancy grid for an agent of radius 0.2 m, one
   connected free region (the largest) touches every room.
4. **Objects reachable**: the agent's body (a cylinder of radius 0.2 m centred on a cell of
   that region) comes within ``REACH`` (1 m) of each object's footprint, i.e. some cell
   centre is within 1.2 m of it.
5. **Objects visible**: from some cell of that region within ``VIEW_RANGE`` of the object,
   a ray from eye height ``EYE_HEIGHT`` to one of a few points on the object hits the
   object first (``mujoco.mj_ray`` on the compiled model, so occlusion by any geom counts;
   MuJoCo tests rays against a mesh's convex hull, so the ray ignores the object's parent,
   whose hull would enclose it, and otherwise errs towards "occluded").
6. **Generator rules**: the rules of the house's generator version (``Generator.check_rules``,
   ``objsearch.house.generators``; ``house-gen-2``: circulation, sizes, entrance and fill,
   ``objsearch.house.gen2.rules``; ``house-gen-1`` has none); for a single room
   (``objsearch.house.rooms``) its own rules.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from objsearch.house.generators import GENERATORS, get_generator
from objsearch.house.layout import surface_rect
from objsearch.house.occupancy import OccupancyGrid, components, occupancy_grid
from objsearch.house.spec import HouseSpec

TOL = 1e-3
REACH = 1.0
VIEW_RANGE = 3.0
EYE_HEIGHT = 1.2
VIEW_CANDIDATES = 8
GRID_RESOLUTION = 0.05


@dataclass
class ValidationReport:
    """What ``validate_house`` found: its problems and the occupancy grid it used."""

    problems: list[str] = field(default_factory=list)
    grid: OccupancyGrid | None = None

    @property
    def ok(self) -> bool:
        """Whether no problem was found."""
        return not self.problems


def _pair_overlaps(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(len(a), len(b)) bool: boxes (x0, y0, z0, x1, y1, z1) overlap by more than TOL."""
    lo = np.maximum(a[:, None, :3], b[None, :, :3])
    hi = np.minimum(a[:, None, 3:], b[None, :, 3:])
    return np.all(hi - lo > TOL, axis=2)


def check_interpenetration(spec: HouseSpec) -> list[str]:
    """Problems of overlap: objects in walls, below the floor or above the walls, in each other, off their support."""
    problems = []
    objs = spec.objects
    boxes = np.array([o.box for o in objs], dtype=float).reshape(-1, 6)
    walls = [(*w.box[:2], 0.0, *w.box[2:], w.height) for w in spec.walls]
    t = spec.wall_thickness / 2
    for d in spec.doors:
        x0, y0, x1, y1 = d.span
        walls.append(
            (
                x0 - (t if d.axis == "y" else 0),
                y0 - (t if d.axis == "x" else 0),
                d.height,
                x1 + (t if d.axis == "y" else 0),
                y1 + (t if d.axis == "x" else 0),
                spec.wall_height,
            )
        )
    hit = _pair_overlaps(boxes, np.array(walls, dtype=float))
    for i in np.flatnonzero(hit.any(axis=1)):
        problems.append(f"{objs[i].name} intersects a wall")
    if len(objs):
        if (boxes[:, 2] < -TOL).any() or (boxes[:, 5] > spec.wall_height + TOL).any():
            problems.append("an object is below the floor or above the walls")
    hit = np.triu(_pair_overlaps(boxes, boxes), k=1)
    index = {o.name: k for k, o in enumerate(objs)}
    for i, j in zip(*np.nonzero(hit)):
        a, b = objs[i], objs[j]
        child, parent = (a, b) if a.parent == b.name else (b, a) if b.parent == a.name else (None, None)
        if child is None:
            problems.append(f"{a.name} intersects {b.name}")
            continue
        z, sx0, sy0, sx1, sy1 = surface_rect(parent)
        cx0, cy0, cz0, cx1, cy1, _ = boxes[index[child.name]]
        if cz0 < z - TOL or cx0 < sx0 - TOL or cy0 < sy0 - TOL or cx1 > sx1 + TOL or cy1 > sy1 + TOL:
            problems.append(f"{child.name} is not on the support surface of {parent.name}")
    return problems


def _dist_to_box(xs: np.ndarray, ys: np.ndarray, fp) -> np.ndarray:
    x0, y0, x1, y1 = fp
    dx = np.maximum(np.maximum(x0 - xs[None, :], 0), xs[None, :] - x1)
    dy = np.maximum(np.maximum(y0 - ys[:, None], 0), ys[:, None] - y1)
    return np.hypot(dx, dy)


def check_reachability(spec: HouseSpec, model: mujoco.MjModel | None, grid: OccupancyGrid) -> list[str]:
    """Problems of access: rooms the agent cannot reach, objects not within reach, objects not visible.

    Visibility is checked with MuJoCo rays from reachable cells; ``model`` None skips it.
    """
    problems = []
    n, labels = components(grid.free)
    if n <= 1:
        return ["no free space for the agent"]
    sizes = np.bincount(labels.ravel(), minlength=n)
    sizes[0] = 0
    main = labels == int(np.argmax(sizes))
    xs, ys = grid.centers()
    res = grid.resolution
    for r in spec.rooms:
        # a rectangle is its own bounds; an L is its rectangles, not its bounding box
        if not any(
            main[int(y0 / res) : int(np.ceil(y1 / res)), int(x0 / res) : int(np.ceil(x1 / res))].any()
            for x0, y0, x1, y1 in r.rects()
        ):
            problems.append(f"room {r.id} ({r.type}) is not reachable")
    data = mujoco.MjData(model) if model is not None else None
    if data is not None:
        mujoco.mj_kinematics(model, data)
    geomid = np.zeros(1, dtype=np.int32)
    for o in spec.objects:
        fp = o.footprint
        c0 = max(int((fp[0] - VIEW_RANGE) / res), 0)
        c1 = min(int(np.ceil((fp[2] + VIEW_RANGE) / res)), main.shape[1])
        r0 = max(int((fp[1] - VIEW_RANGE) / res), 0)
        r1 = min(int(np.ceil((fp[3] + VIEW_RANGE) / res)), main.shape[0])
        window = main[r0:r1, c0:c1]
        dist = _dist_to_box(xs[c0:c1], ys[r0:r1], fp)
        if not (window & (dist <= REACH + grid.agent_radius)).any():
            problems.append(f"{o.name} is not reachable within {REACH} m")
            continue
        if data is None:
            continue
        rx0, ry0, rx1, ry1 = spec.room(o.room).bounds
        in_room = ((xs[c0:c1] > rx0) & (xs[c0:c1] < rx1))[None, :] & ((ys[r0:r1] > ry0) & (ys[r0:r1] < ry1))[:, None]
        near = window & (dist <= VIEW_RANGE)
        # candidates from the object's own room first (rays from next door mostly hit walls)
        rr, cc = np.nonzero(near & in_room) if (near & in_room).any() else np.nonzero(near)
        order = np.argsort(dist[rr, cc], kind="stable")
        picks = order[np.linspace(0, len(order) - 1, min(VIEW_CANDIDATES, len(order))).astype(int)]
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, o.name)
        # MuJoCo rays test a mesh's convex hull, which for a bed or a shelf encloses what
        # stands on it: rays ignore the parent (its parts above the surface are outside it).
        exclude = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, o.parent) if o.parent else -1
        x0, y0, z0, x1, y1, z1 = o.box
        targets = [((x0 + x1) / 2, (y0 + y1) / 2, z0 + f * (z1 - z0)) for f in (0.5, 0.85, 0.2)]
        seen = False
        for k in picks:
            eye = np.array([xs[c0 + cc[k]], ys[r0 + rr[k]], EYE_HEIGHT])
            for tgt in targets:
                vec = np.asarray(tgt) - eye
                if (
                    mujoco.mj_ray(model, data, eye, vec, None, 1, exclude, geomid) >= 0
                    and geomid[0] >= 0
                    and model.geom_bodyid[geomid[0]] == body
                ):
                    seen = True
                    break
            if seen:
                break
        if not seen:
            problems.append(f"{o.name} is not visible from any reachable position")
    return problems


def validate_house(spec: HouseSpec, model: mujoco.MjModel | None) -> ValidationReport:
    """All checks; ``model`` None skips the visibility rays."""
    report = ValidationReport()
    report.problems += check_interpenetration(spec)
    report.grid = occupancy_grid(spec, GRID_RESOLUTION)
    report.problems += check_reachability(spec, model, report.grid)
    if spec.single_room is not None:
        from objsearch.house.rooms import check_rules

        report.problems += check_rules(spec)
    elif spec.generator_version in GENERATORS:
        report.problems += get_generator(spec.generator_version).check_rules(spec)
    return report
