"""Generator ``house-gen-4``: houses whose layouts vary as homes do.

Every ``house-gen-3`` house is one rectangle with one straight corridor. ``house-gen-4``
builds a house from a hub of public rooms and one to three wings of private rooms, in five
floorplan families (``gen4.floorplan.FAMILIES``): ``bar`` (a rectangle, one straight
hallway), ``bar2`` (two hallways, the hub between them), ``L``, ``U`` (a courtyard between two
wings) and ``T``; wings with hallways on one side or both, rooms across a hallway's end,
rows of rooms entered from the hub's rooms, en-suite bathrooms and open-plan hubs. The
room program, size classes (``xlarge``: 9-14 rooms; ``rooms-4`` ... ``rooms-14``), small
targets (one a category) and every rule of ``house-gen-3`` hold, with the footprint rule
read on the house's outline (``gen4.rules``). The family is recorded in the spec's
``extra["floorplan"]``; ``objsearch.house.floorplan_stats`` measures what a plan is.
"""

from objsearch.house.gen4.build import VERSION, build_spec, default_size_class
from objsearch.house.gen4.rules import check_rules
from objsearch.house.generators import Generator
from objsearch.house.stages import ROOM_COUNT_CLASSES

GENERATOR = Generator(
    name=VERSION,
    build_spec=build_spec,
    attempts=32,
    shuffle_key=4,
    check_rules=check_rules,
    size_classes=tuple(ROOM_COUNT_CLASSES),
    default_size_class=default_size_class,
)
