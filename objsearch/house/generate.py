"""The house pipeline: stages -> ``HouseSpec`` -> MJCF -> compile -> validate, with resampling.

``generate_house(seed, generator="house-gen-1")`` runs the stages of this module (footprint
and rooms, room types, doors and walls, furniture, materials) with ``numpy.random.default_rng([seed, attempt, split])`` and
validates the result (``objsearch.house.validate``). Resampling is bounded and documented:
if a stage cannot satisfy its rules (``StageFailure``), the model does not compile, or
validation fails, the next *attempt* starts over from a fresh generator; after
``MAX_ATTEMPTS`` attempts (``GENERATOR_ATTEMPTS`` per generator) ``HouseGenerationError`` lists
what went wrong. The size class
is drawn once per seed (from ``default_rng([seed, SIZE_STREAM])``) so resampling keeps it.
The attempt that succeeded is recorded in the spec, so a spec is reproducible from
(seed, split, size class, version) alone.

``HOUSE_GENERATOR_VERSION`` must be bumped whenever the same seed would give a different
house (then regenerate the golden specs: ``python tests/house/make_golden.py``).

Generators (``GENERATORS``, chosen with ``generate_house(..., generator=NAME)``):
``house-gen-2`` (``DEFAULT_GENERATOR``; ``objsearch.house.generate_v2``: zoned floorplans with
corridors, L-shaped rooms, per-type room sizes, an entrance and fill that follows room area;
its own rules in ``objsearch.house.validate_v2``) and ``house-gen-1`` (the stages of this
module: rooms cut from a rectangle, no entrance). A suite or checkpoint records the
generator of its houses (``HouseRef.generator``; none recorded: ``house-gen-1``), so the
default never changes a shipped house.

Single rooms (``generate_house(..., room=TYPE)``, ``objsearch.house.rooms``): one kitchen,
living room, bedroom or bathroom by ``house-gen-2``'s room rules, no doors, denser in small
objects; the spec records ``size_class`` ``room`` and ``extra["room"]``.

Placements (``HOUSE_PLACEMENTS``, chosen with ``generate_house(..., placement=NAME)``): ``functional``
(the default: objects in functional groups, by room priors) and ``shuffled``: the functional
house that the same arguments give, with every object moved to a random place anywhere in
the house (``objsearch.house.shuffle``), drawn from its own generator
(``default_rng([seed, split, SHUFFLE_STREAM, generator])``, so the functional draws are
unchanged). Every shuffle is validated, ``validate`` or not; a shuffle that fails draws
another, up to ``SHUFFLE_ATTEMPTS``. (``validate=False``, as suites regenerate their houses,
takes the first attempt that compiles, valid or not, so its functional house, and then its
shuffled one, may differ from the validated one of the seed.)
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from pathlib import Path

import mujoco
import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import atomic_directory, full_disk_as_error
from objsearch.house import assets
from objsearch.house.categories import CATEGORY_TABLE_VERSION
from objsearch.house.doors import build_walls, place_doors, rect_edges
from objsearch.house.floorplan import SIZE_CLASSES, StageFailure, assign_types, footprint, room_program, split_rooms
from objsearch.house.furnish import furnish
from objsearch.house.layout import HouseContext
from objsearch.house.materials import EXTERIOR, room_materials
from objsearch.house.mjcf import compile_house
from objsearch.house.shuffle import shuffle_house
from objsearch.house.spec import DEFAULT_GENERATOR, GENERATORS, HOUSE_PLACEMENTS, HouseSpec, Room, r4
from objsearch.house.validate import ValidationReport, validate_house

HOUSE_GENERATOR_VERSION = "house-gen-1"  # the version of this module's stages
MAX_ATTEMPTS = 12
#: Attempts per generator: house-gen-2's stages reject more layouts early (cheaply), so it gets more.
GENERATOR_ATTEMPTS = {"house-gen-1": MAX_ATTEMPTS, "house-gen-2": 24}
WALL_HEIGHT = 2.7
WALL_THICKNESS = 0.12
SPLITS = {"train": 0, "test": 1}
SIZE_STREAM = 7919
SHUFFLE_ATTEMPTS = 32
SHUFFLE_STREAM = 104729


class HouseGenerationError(RuntimeError):
    """No attempt produced a valid house."""


@dataclass
class GeneratedHouse:
    """A generated house: its spec, MJCF text, compiled model and validation report."""

    spec: HouseSpec
    xml: str
    model: mujoco.MjModel
    report: ValidationReport


def house_id(seed: int, split: str = "train") -> str:
    """The id of the house of ``seed`` in ``split``: ``train_000042``."""
    return f"{split}_{seed:06d}"


def size_class_for(seed: int) -> str:
    """The size class drawn for ``seed`` when none is given."""
    names = sorted(SIZE_CLASSES)
    return names[int(np.random.default_rng([seed, SIZE_STREAM]).integers(len(names)))]


def build_spec(seed: int, size_class: str, split: str, attempt: int) -> HouseSpec:
    """Run the stages once; raises ``StageFailure`` when a rule cannot be met."""
    rng = np.random.default_rng([seed, attempt, SPLITS[split]])
    lo, hi = SIZE_CLASSES[size_class]["rooms"]
    n = int(rng.integers(lo, hi + 1))
    types = room_program(n, rng)
    width, depth = footprint(size_class, rng)
    rects = split_rooms(width, depth, n, rng)
    types = assign_types(rects, types, rng)
    doors = place_doors(rects, types, rng, WALL_THICKNESS)
    materials, rooms = [], []
    for i, (rect, t) in enumerate(zip(rects, types)):
        floor, wall = room_materials(i, t, rng)
        materials += [floor, wall]
        x0, y0, x1, y1 = (r4(v) for v in rect)
        rooms.append(Room(i, t, ((x0, y0), (x1, y0), (x1, y1), (x0, y1)), floor.name, wall.name))
    materials.append(EXTERIOR)
    walls = build_walls(
        [rect_edges(r) for r in rects],
        doors,
        (width, depth),
        WALL_THICKNESS,
        WALL_HEIGHT,
        [r.wall_material for r in rooms],
        EXTERIOR.name,
    )
    h = WALL_THICKNESS / 2
    interiors = [(r4(x0 + h), r4(y0 + h), r4(x1 - h), r4(y1 - h)) for x0, y0, x1, y1 in rects]
    objects = furnish(HouseContext(rng, split), rooms, interiors, doors, WALL_HEIGHT)
    return HouseSpec(
        house_id=house_id(seed, split),
        seed=seed,
        split=split,
        size_class=size_class,
        attempt=attempt,
        generator_version=HOUSE_GENERATOR_VERSION,
        category_table_version=CATEGORY_TABLE_VERSION,
        footprint=(width, depth),
        wall_height=WALL_HEIGHT,
        wall_thickness=WALL_THICKNESS,
        rooms=tuple(rooms),
        doors=tuple(doors),
        walls=tuple(walls),
        objects=tuple(objects),
        materials=tuple(materials),
    )


def spec_builder(generator: str, room: str | None = None):
    """The ``build_spec(seed, size_class, split, attempt)`` of generator ``generator`` (``GENERATORS``),
    or of its single rooms of type ``room`` (``objsearch.house.rooms``).

    Raises ``UserError`` for an unknown generator or room type.
    """
    if generator in GENERATORS and room is not None:
        from objsearch.house.rooms import room_builder

        return room_builder(generator, room)
    if generator == "house-gen-1":
        return build_spec
    if generator == "house-gen-2":
        from objsearch.house.generate_v2 import build_spec as build_spec_v2

        return build_spec_v2
    raise UserError(f"unknown house generator {generator!r}; use one of {', '.join(GENERATORS)}")


def generate_house(
    seed: int,
    size_class: str | None = None,
    split: str = "train",
    validate: bool = True,
    generator: str = DEFAULT_GENERATOR,
    placement: str = "functional",
    room: str | None = None,
) -> GeneratedHouse:
    """Generate, compile and (with ``validate``) check the house of ``seed``, retrying up to ``MAX_ATTEMPTS``.

    ``generator`` names the generator version (``GENERATORS``; default ``house-gen-2``),
    ``placement`` how objects are placed (``HOUSE_PLACEMENTS``; default ``functional``);
    ``room`` (``objsearch.house.rooms.ROOM_TYPES``) makes a single room of that type instead of
    a house (its size class is ``room``; give none, or that).
    Raises ``UserError`` for an unknown split, size class, generator, placement or room type,
    ``HouseGenerationError`` if no attempt (no shuffle) is valid.
    """
    build = spec_builder(generator, room)
    if split not in SPLITS:
        raise UserError(f"unknown split {split!r}; use one of {', '.join(SPLITS)}")
    if room is not None:
        from objsearch.house.rooms import ROOM_SIZE_CLASS

        if size_class not in (None, ROOM_SIZE_CLASS):
            raise UserError(f"a single room ({room}) has no size class {size_class!r}; give none")
        size_class = ROOM_SIZE_CLASS
    elif size_class is not None and size_class not in SIZE_CLASSES:
        raise UserError(f"unknown room size {size_class!r}; use one of {', '.join(SIZE_CLASSES)}")
    if placement not in HOUSE_PLACEMENTS:
        raise UserError(f"unknown placement {placement!r}; use one of {', '.join(HOUSE_PLACEMENTS)}")
    size_class = size_class or size_class_for(seed)
    if placement == "shuffled":
        return _shuffled(generate_house(seed, size_class, split, validate, generator, room=room))
    failures = []
    attempts = GENERATOR_ATTEMPTS[generator]
    for attempt in range(attempts):
        house = _checked(partial(build, seed, size_class, split, attempt), validate)
        if isinstance(house, GeneratedHouse):
            return house
        failures.append(f"attempt {attempt}: {house}")
    raise HouseGenerationError(
        f"seed {seed} ({room or size_class}, {split}, {generator}): no valid house in {attempts} attempts:\n  "
        + "\n  ".join(failures)
    )


def _shuffled(house: GeneratedHouse) -> GeneratedHouse:
    """The shuffled house of the functional ``house``: the first valid of ``SHUFFLE_ATTEMPTS`` shuffles."""
    spec = house.spec
    generator = spec.generator_version
    rng = np.random.default_rng([spec.seed, SPLITS[spec.split], SHUFFLE_STREAM, GENERATORS.index(generator)])
    failures = []
    for attempt in range(SHUFFLE_ATTEMPTS):
        shuffled = _checked(partial(shuffle_house, spec, rng), validate=True)
        if isinstance(shuffled, GeneratedHouse):
            return shuffled
        failures.append(f"shuffle {attempt}: {shuffled}")
    raise HouseGenerationError(
        f"seed {spec.seed} ({spec.size_class}, {spec.split}, {generator}, placement shuffled): no valid shuffle "
        f"in {SHUFFLE_ATTEMPTS} tries; use another seed:\n  " + "\n  ".join(failures)
    )


def _checked(build, validate: bool) -> GeneratedHouse | str:
    """The house of the spec ``build()`` returns, compiled and (with ``validate``) checked, or what went wrong."""
    try:
        spec = build()
    except StageFailure as err:
        return str(err)
    try:
        model, xml = compile_house(spec)
    except ValueError as err:  # mujoco compile errors
        return f"MuJoCo compile failed: {err}"
    report = validate_house(spec, model) if validate else ValidationReport()
    if report.ok:
        return GeneratedHouse(spec, xml, model, report)
    return "; ".join(report.problems[:3])


def write_house(house: GeneratedHouse, out_dir: str | Path, preview: bool = True) -> Path:
    """Write ``<out_dir>/<house_id>/`` (house.xml, spec.json, preview.png, meshes/): into a temp
    folder renamed into place, so that an interrupt or a full disk (a ``UserError`` naming the
    house) leaves the whole house, or what was there before, never part of one."""
    d = Path(out_dir) / house.spec.house_id
    with full_disk_as_error(d, "choose another --out"), atomic_directory(d) as tmp:
        for cat, variant in sorted({(o.category, o.variant) for o in house.spec.objects}):
            mesh = tmp / "meshes" / assets.mesh_file(cat, variant)
            mesh.parent.mkdir(parents=True, exist_ok=True)
            mesh.write_bytes(assets.mesh_bytes(cat, variant))
        (tmp / "house.xml").write_text(house.xml)
        (tmp / "spec.json").write_text(house.spec.to_json_text())
        if preview:
            from objsearch.house.preview import write_preview

            write_preview(house.spec, tmp / "preview.png")
    return d
