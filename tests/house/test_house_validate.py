"""Validation catches the faults it is there for."""

import dataclasses

import numpy as np

from objsearch.house.generate import generate_house
from objsearch.house.mjcf import compile_house
from objsearch.house.occupancy import occupancy_grid
from objsearch.house.validate import check_interpenetration, validate_house


def test_overlapping_object_is_reported():
    spec = generate_house(3, generator="house-gen-1").spec
    sofa = next(o for o in spec.objects if o.category == "sofa")
    other = next(
        o for o in spec.objects if o.room == sofa.room and o.placement in ("wall", "corner") and o.name != sofa.name
    )
    moved = dataclasses.replace(other, position=sofa.position)
    bad = dataclasses.replace(spec, objects=tuple(moved if o is other else o for o in spec.objects))
    assert any(f"{other.name} intersects" in p or f"intersects {other.name}" in p for p in check_interpenetration(bad))


def test_object_in_a_wall_is_reported():
    spec = generate_house(3, generator="house-gen-1").spec
    obj = next(o for o in spec.objects if o.placement == "wall")
    wall = spec.walls[0]
    x = (wall.box[0] + wall.box[2]) / 2
    y = (wall.box[1] + wall.box[3]) / 2
    bad = dataclasses.replace(
        spec, objects=tuple(dataclasses.replace(o, position=(x, y, 0.0)) if o is obj else o for o in spec.objects)
    )
    assert f"{obj.name} intersects a wall" in check_interpenetration(bad)


def test_closed_door_makes_a_room_unreachable():
    spec = generate_house(3, generator="house-gen-1").spec
    leaf = next(r for r in spec.rooms if sum(r.id in d.rooms for d in spec.doors) == 1)
    door = next(d for d in spec.doors if leaf.id in d.rooms)
    t = spec.wall_thickness / 2
    x0, y0, x1, y1 = door.span
    plug = dataclasses.replace(spec.walls[0], id=999, box=(x0 - t, y0 - t, x1 + t, y1 + t))
    bad = dataclasses.replace(spec, walls=spec.walls + (plug,))
    model, _ = compile_house(bad)
    problems = validate_house(bad, model).problems
    assert any("is not reachable" in p for p in problems)


def test_occupancy_grid_keeps_agent_radius_from_walls():
    spec = generate_house(3, generator="house-gen-1").spec
    grid = occupancy_grid(spec, resolution=0.05, agent_radius=0.2)
    xs, ys = grid.centers()
    rr, cc = np.nonzero(grid.free)
    assert len(rr) > 0
    for w in spec.walls:
        x0, y0, x1, y1 = w.box
        dx = np.maximum(np.maximum(x0 - xs[cc], 0), xs[cc] - x1)
        dy = np.maximum(np.maximum(y0 - ys[rr], 0), ys[rr] - y1)
        assert np.hypot(dx, dy).min() >= 0.2 - 1e-9
    coarse = occupancy_grid(spec, resolution=0.2)
    assert coarse.free.shape == (int(np.ceil(spec.footprint[1] / 0.2)), int(np.ceil(spec.footprint[0] / 0.2)))
    assert coarse.free.sum() > 0
