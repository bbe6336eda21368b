"""``preview.png`` explains itself: room names and areas inside their rooms, a legend of
every object category, doors and the entrance marked, a true-length scale bar; same spec,
same bytes."""

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from objsearch.house.categories import CATEGORY_IDS
from objsearch.house.plan_canvas import PX, ROW_H, entrances, scale_bar_metres
from objsearch.house.plan_legend import draw_scale_bar, footer_top, plan_footer
from objsearch.house.preview import category_numbers, preview_layout, render_preview, room_label, write_preview
from objsearch.house.spec import Door, HouseSpec

GOLDEN = Path(__file__).parent / "golden"


@pytest.fixture(scope="module")
def spec() -> HouseSpec:
    """A golden house without any entrance (whatever the generator now makes)."""
    spec = HouseSpec.from_json(json.loads((GOLDEN / "spec_000000.json").read_text()))
    return dataclasses.replace(spec, doors=tuple(d for d in spec.doors if min(d.rooms) >= 0))


def _with_entrance(spec: HouseSpec) -> tuple[HouseSpec, Door]:
    """``spec`` with an entrance in the south outer wall of a room that touches it."""
    room = next(r for r in spec.rooms if r.bounds[1] == 0.0)
    x0, _, x1, _ = room.bounds
    door = Door(id=len(spec.doors), rooms=(-1, room.id), axis="x", center=((x0 + x1) / 2, 0.0), width=1.0, height=2.1)
    return dataclasses.replace(spec, doors=spec.doors + (door,)), door


def _changed(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.any(a != b, axis=2)


def test_every_room_label_is_drawn_inside_its_room(spec):
    layout = preview_layout(spec)
    changed = _changed(render_preview(spec), render_preview(spec, room_labels=False))
    inside_some_room = np.zeros_like(changed)
    for room in spec.rooms:
        x0, y0, x1, y1 = room.bounds
        (c0, r0), (c1, r1) = layout.pixel(x0, y1), layout.pixel(x1, y0)
        assert changed[r0:r1, c0:c1].sum() > 100, f"no label drawn in room {room.id} ({room.type})"
        inside_some_room[r0:r1, c0:c1] = True
    assert not (changed & ~inside_some_room).any(), "a room label spills out of the rooms"


def test_room_label_names_the_type_and_area(spec):
    room = max(spec.rooms, key=lambda r: r.area)
    name, area = room_label(room)
    assert name == room.type.replace("_", " ")
    assert area == f"{room.area:.1f} m2" and float(area.split()[0]) > 1


def test_the_legend_numbers_every_category_present_in_table_order(spec):
    numbers = category_numbers(spec)
    assert set(numbers) == {o.category for o in spec.objects}
    assert sorted(numbers.values()) == list(range(1, len(numbers) + 1))
    assert sorted(numbers, key=CATEGORY_IDS.__getitem__) == list(numbers)
    with_legend, without = render_preview(spec), render_preview(spec, object_labels=False)
    layout = preview_layout(spec)
    panel = with_legend[:, layout.left + layout.plan_w + 30 :]
    assert panel.shape[1] > 100
    inked_rows = np.flatnonzero(np.any(panel < 128, axis=(1, 2)))
    # the header, then one row of ROW_H pixels per category (in one or more columns)
    rows = min(len(numbers), (layout.plan_h + 80 - 24) // ROW_H)
    assert inked_rows.max() - inked_rows.min() >= (rows - 1) * ROW_H
    assert without.shape[1] < with_legend.shape[1]


def test_the_entrance_is_marked_only_when_the_house_has_one(spec):
    assert not entrances(spec)
    assert "entrance" not in [label for label, _ in plan_footer(spec)]
    with_entrance, door = _with_entrance(spec)
    assert entrances(with_entrance) == [door]
    assert "entrance" in [label for label, _ in plan_footer(with_entrance)]
    layout = preview_layout(spec)
    assert preview_layout(with_entrance).top == layout.top  # the plan stays put; the footer may grow
    # the arrow and its label lie in the white margin outside the door
    cx, cy = layout.pixel(*door.center)
    outside = (slice(cy + 8, cy + 34), slice(cx - 40, cx + 80))
    plain, marked = render_preview(spec), render_preview(with_entrance)
    assert (plain[outside] == 255).all()
    assert np.any(marked[outside] != 255, axis=2).sum() > 100
    green = (marked[..., 1].astype(int) - marked[..., 2] > 60) & (marked[..., 1].astype(int) - marked[..., 0] > 60)
    assert green[outside].sum() > 50


@pytest.mark.parametrize("metres", [1, 2])
def test_scale_bar_is_px_per_metre_long(metres):
    img = np.full((40, 300, 3), 255, np.uint8)
    draw_scale_bar(img, 10, 10, metres)
    dark = np.flatnonzero(img[10, :, 0] < 100)
    run = dark[: np.argmax(np.diff(dark) > 1) + 1] if (np.diff(dark) > 1).any() else dark
    assert run[0] == 10 and len(run) == PX * metres


def test_the_preview_has_its_scale_bar_under_the_plan(spec):
    layout = preview_layout(spec)
    img = render_preview(spec)
    row = img[footer_top(layout) + 6, :, 0]
    dark = np.flatnonzero(row < 100)
    assert dark[0] == layout.left
    assert np.all(row[layout.left : layout.left + PX * scale_bar_metres(spec)] < 100)
    assert row[layout.left + PX * scale_bar_metres(spec)] > 200


def test_doors_are_drawn_in_their_openings(spec):
    layout = preview_layout(spec)
    img = render_preview(spec)
    for door in spec.doors:
        c, r = layout.pixel(*door.center)
        b, g, rr = img[r, c].astype(int)
        assert rr > b + 60, f"door {door.id} is not orange at its centre"


def test_same_spec_same_bytes(spec, tmp_path):
    write_preview(spec, tmp_path / "a.png")
    write_preview(spec, tmp_path / "b.png")
    assert (tmp_path / "a.png").read_bytes() == (tmp_path / "b.png").read_bytes()
    assert np.array_equal(render_preview(spec), render_preview(spec))
