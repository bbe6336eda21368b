"""Generator ``house-gen-2`` (frozen; the default): zoned floorplans (private rooms, an optional
corridor, public rooms) with L-shaped rooms and per-type room sizes, doors by circulation
rules and an entrance, furniture whose amount follows room area, and its own validation rules.

Stages: ``floorplan`` (room program, areas, bands) -> ``doors`` (doors, entrance; walls by
``objsearch.house.walls``) -> ``furnish`` (``objsearch.house.groups`` in rooms of any shape,
topped up by area) -> materials, run once per attempt by ``build.build_spec``; ``rules`` are
the rules ``validate_house`` adds for its houses. Single rooms (``objsearch.house.rooms``) are
a mode of this generator: its stages after the doors (``build.spec_of_plan``) and its rules.
"""

from objsearch.house.gen2.build import VERSION, build_spec
from objsearch.house.gen2.rules import check_rules
from objsearch.house.generators import Generator

GENERATOR = Generator(name=VERSION, build_spec=build_spec, attempts=24, shuffle_key=1, check_rules=check_rules)
