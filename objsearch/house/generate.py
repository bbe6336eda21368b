"""The attempt loop every generator shares: stages -> ``HouseSpec`` -> MJCF -> compile -> validate,
with resampling.

``generate_house(seed, generator=NAME)`` runs the ``build_spec`` of generator ``NAME``
(``objsearch.house.generators``: ``house-gen-2``, ``DEFAULT_GENERATOR``, or ``house-gen-1``)
with attempt 0, 1, ... and validates the result (``objsearch.house.validate``). Resampling is
bounded and documented: if a stage cannot satisfy its rules (``StageFailure``), the model does
not compile, or validation fails, the next *attempt* starts over from a fresh generator
(``numpy.random.default_rng([seed, attempt, split, ...])``); after the generator's
``attempts`` ``HouseGenerationError`` lists what went wrong. The size class is drawn once per
seed (``stages.size_class_for``) so resampling keeps it. The attempt that succeeded is recorded
in the spec, so a spec is reproducible from (seed, split, size class, version) alone. A
generator version is frozen: a change that would give a seed a different house is a new
version (a package and a line in ``generators.GENERATORS``), with its own golden specs.

A suite or checkpoint records the generator of its houses (``HouseRef.generator``; none
recorded: ``house-gen-1``), so the default never changes a shipped house.

Single rooms (``generate_house(..., room=TYPE)``, ``objsearch.house.rooms``): one kitchen,
living room, bedroom or bathroom by ``house-gen-2``'s room rules, no doors, denser in small
objects; the spec records ``size_class`` ``room`` and ``extra["room"]``.

Placements (``HOUSE_PLACEMENTS``, chosen with ``generate_house(..., placement=NAME)``): ``functional``
(the default: objects in functional groups, by room priors), ``shuffled``: the functional
house that the same arguments give, with every object moved to a random place anywhere in
the house, and ``roomwise``: every object moved to a random place in a room of its room's
type (``objsearch.house.shuffle``), each drawn from its own generator
(``default_rng([seed, split, PLACEMENT_STREAMS[placement], Generator.shuffle_key])``, so the
functional draws are unchanged), and the settings of the fidelity dial, ``anywhere-P`` and
``roomwise-P`` (``objsearch.house.dial``): a share P percent of the objects moved, which objects
drawn from one stream for both families and every P (``default_rng([seed, split,
DIAL_ORDER_STREAM, shuffle_key])``), where they go from the family's stream
(``default_rng([seed, split, DIAL_STREAMS[family], shuffle_key, P])``). Every shuffle is
validated, ``validate`` or not; a shuffle that fails draws another (of the same objects, for the
dial), up to ``SHUFFLE_ATTEMPTS``. (``validate=False``, as suites regenerate their
houses, takes the first attempt that compiles, valid or not, so its functional house, and then
its shuffled one, may differ from the validated one of the seed.)
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import partial
from pathlib import Path

import mujoco
import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import atomic_directory, full_disk_as_error
from objsearch.house import assets
from objsearch.house.dial import dial_house, dial_setting, moving_objects
from objsearch.house.generators import GENERATORS, get_generator
from objsearch.house.mjcf import compile_house
from objsearch.house.shuffle import shuffle_house
from objsearch.house.spec import DEFAULT_GENERATOR, HOUSE_PLACEMENTS, HouseSpec
from objsearch.house.stages import SPLITS, StageFailure
from objsearch.house.validate import ValidationReport, validate_house

SHUFFLE_ATTEMPTS = 32
SHUFFLE_STREAM = 104729
#: The random stream of each placement that moves a functional house's objects (``_moved``).
PLACEMENT_STREAMS = {"shuffled": SHUFFLE_STREAM, "roomwise": 130363}
#: The random stream of which objects the fidelity dial moves (``dial.moving_objects``), shared by
#: its families and settings so the dial is nested; never one of ``PLACEMENT_STREAMS``.
DIAL_ORDER_STREAM = 150001
#: The random stream of where each family of the dial puts the objects it moves (keyed by P too).
DIAL_STREAMS = {"anywhere": 160001, "roomwise": 170003}


class HouseGenerationError(RuntimeError):
    """No attempt produced a valid house."""


@dataclass
class GeneratedHouse:
    """A generated house: its spec, MJCF text, compiled model and validation report."""

    spec: HouseSpec
    xml: str
    model: mujoco.MjModel
    report: ValidationReport


def spec_builder(generator: str, room: str | None = None):
    """The ``build_spec(seed, size_class, split, attempt)`` of generator ``generator`` (``GENERATORS``),
    or of its single rooms of type ``room`` (``objsearch.house.rooms``).

    Raises ``UserError`` for an unknown generator or room type.
    """
    if generator in GENERATORS and room is not None:
        from objsearch.house.rooms import room_builder

        return room_builder(generator, room)
    return get_generator(generator).build_spec


def generate_house(
    seed: int,
    size_class: str | None = None,
    split: str = "train",
    validate: bool = True,
    generator: str = DEFAULT_GENERATOR,
    placement: str = "functional",
    room: str | None = None,
) -> GeneratedHouse:
    """Generate, compile and (with ``validate``) check the house of ``seed``, in up to the generator's ``attempts``.

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
    elif size_class is not None and size_class not in get_generator(generator).size_classes:
        raise UserError(
            f"{generator} has no room size {size_class!r}; use one of {', '.join(get_generator(generator).size_classes)}"
        )
    if placement not in HOUSE_PLACEMENTS:
        raise UserError(f"unknown placement {placement!r}; use one of {', '.join(HOUSE_PLACEMENTS)}")
    size_class = size_class or get_generator(generator).default_size_class(seed)
    if placement != "functional":
        return _moved(generate_house(seed, size_class, split, validate, generator, room=room), placement)
    failures = []
    attempts = get_generator(generator).attempts
    for attempt in range(attempts):
        house = _checked(partial(build, seed, size_class, split, attempt), validate)
        if isinstance(house, GeneratedHouse):
            return house
        failures.append(f"attempt {attempt}: {house}")
    raise HouseGenerationError(
        f"seed {seed} ({room or size_class}, {split}, {generator}): no valid house in {attempts} attempts:\n  "
        + "\n  ".join(failures)
    )


def _moved(house: GeneratedHouse, placement: str) -> GeneratedHouse:
    """The ``placement`` house (``shuffled``, ``roomwise`` or a dial setting) of the functional
    ``house``: the first valid of ``SHUFFLE_ATTEMPTS`` shuffles."""
    spec = house.spec
    generator = spec.generator_version
    key = get_generator(generator).shuffle_key
    stream = [spec.seed, SPLITS[spec.split]]
    if placement in PLACEMENT_STREAMS:
        rng = np.random.default_rng([*stream, PLACEMENT_STREAMS[placement], key])
        shuffle = partial(shuffle_house, spec, rng, placement)
    else:
        family, share = dial_setting(placement)
        moving = moving_objects(spec, share, np.random.default_rng([*stream, DIAL_ORDER_STREAM, key]))
        rng = np.random.default_rng([*stream, DIAL_STREAMS[family], key, share])
        shuffle = partial(dial_house, spec, moving, rng, placement)
    failures = []
    for attempt in range(SHUFFLE_ATTEMPTS):
        moved = _checked(shuffle, validate=True)
        if isinstance(moved, GeneratedHouse):
            return moved
        failures.append(f"shuffle {attempt}: {moved}")
    raise HouseGenerationError(
        f"seed {spec.seed} ({spec.size_class}, {spec.split}, {generator}, placement {placement}): no valid shuffle "
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


def write_house(house: GeneratedHouse, out_dir: str | Path, preview: bool = True, overwrite: bool = False) -> Path:
    """Write ``<out_dir>/<house_id>/`` (house.xml, spec.json, preview.png, meshes/): into a temp
    folder renamed into place, so that an interrupt or a full disk (a ``UserError`` naming the
    house) leaves the whole house, or what was there before, never part of one. A folder there
    already is replaced only as ``house_folder.check_house_folder`` allows: the same house, or
    another one with ``overwrite``, and never one holding files that this did not write."""
    from objsearch.house.house_folder import check_house_folder

    d = Path(out_dir) / house.spec.house_id
    text = {"spec.json": house.spec.to_json_text(), "house.xml": house.xml}
    if not check_house_folder(d, json.loads(text["spec.json"]), text, overwrite):
        return d  # the same house, with the user's files beside it: left as it is
    with full_disk_as_error(d, "choose another --out"), atomic_directory(d) as tmp:
        for cat, variant in sorted({(o.category, o.variant) for o in house.spec.objects}):
            mesh = tmp / "meshes" / assets.mesh_file(cat, variant)
            mesh.parent.mkdir(parents=True, exist_ok=True)
            mesh.write_bytes(assets.mesh_bytes(cat, variant))
        (tmp / "house.xml").write_text(house.xml)
        (tmp / "spec.json").write_text(text["spec.json"])
        if preview:
            from objsearch.house.preview import write_preview

            write_preview(house.spec, tmp / "preview.png")
    return d
