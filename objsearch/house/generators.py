"""The registry of house generator versions, and the record each version exports.

Every generator version is a package (``objsearch.house.gen1``, ``objsearch.house.gen2``),
frozen once shipped so that a seed gives the same house forever, which exports one
``Generator`` record as ``GENERATOR``: its build function, its validation rules and its
attempt budget. Versions share the modules of ``objsearch.house`` (``stages``, ``walls``,
``groups``, ``clearances``, ``layout``, ``materials``), never each other.

``generate_house`` (``objsearch.house.generate``), ``validate_house``
(``objsearch.house.validate``), the ``objsearch generate`` CLI and the suites read versions
from ``GENERATORS`` by name, and a package is imported only when its generator is asked for
(``get_generator``), so reading the names costs nothing. Adding ``house-gen-3``: a package
``objsearch/house/gen3/`` whose ``GENERATOR`` names it, and one line in ``GENERATORS``.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from objsearch.errors import UserError
from objsearch.house.stages import SIZE_CLASSES, size_class_for

if TYPE_CHECKING:
    from objsearch.house.spec import HouseSpec

#: Every generator version by name: the package that exports its ``GENERATOR`` record.
GENERATORS: dict[str, str] = {
    "house-gen-1": "objsearch.house.gen1",
    "house-gen-2": "objsearch.house.gen2",
    "house-gen-3": "objsearch.house.gen3",
    "house-gen-4": "objsearch.house.gen4",
}


def no_rules(spec: HouseSpec) -> list[str]:
    """The rules of a generator without rules of its own: no problem, ever."""
    return []


@dataclass(frozen=True)
class Generator:
    """One generator version, as its package exports it.

    Attributes:
        name: the version, as a spec records it (``HouseSpec.generator_version``): ``house-gen-2``.
        build_spec: ``build_spec(seed, size_class, split, attempt) -> HouseSpec``: the stages run
            once with attempt ``attempt``; raises ``stages.StageFailure`` when a rule cannot be met.
        check_rules: ``check_rules(spec) -> [problem]``: the version's own rules, which
            ``validate_house`` checks beside the compile, overlap, reachability and visibility
            checks every house gets.
        attempts: how many attempts ``generate_house`` makes before it gives up on a seed.
        shuffle_key: keys the random stream of the version's shuffled and roomwise houses
            (``generate.PLACEMENT_STREAMS``); never reused by another version.
        size_classes: the size classes ``build_spec`` takes (``stages.SIZE_CLASSES``: small,
            medium, large; ``house-gen-3``: ``stages.ROOM_COUNT_CLASSES``).
        default_size_class: ``default_size_class(seed)``: the size class of a seed given none.
    """

    name: str
    build_spec: Callable[[int, str, str, int], HouseSpec]
    attempts: int
    shuffle_key: int
    check_rules: Callable[[HouseSpec], list[str]] = no_rules
    size_classes: tuple[str, ...] = tuple(SIZE_CLASSES)
    default_size_class: Callable[[int], str] = size_class_for


def get_generator(name: str) -> Generator:
    """The ``Generator`` of version ``name`` (``GENERATORS``); ``UserError`` naming the versions if unknown."""
    if name not in GENERATORS:
        raise UserError(f"unknown house generator {name!r}; use one of {', '.join(GENERATORS)}")
    record = importlib.import_module(GENERATORS[name]).GENERATOR
    if record.name != name:
        raise RuntimeError(f"{GENERATORS[name]}.GENERATOR is {record.name!r}, registered as {name!r}")
    return record
