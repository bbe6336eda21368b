"""Generator ``house-gen-1`` (frozen): a 6-16 m footprint cut into 3-9 rectangle rooms, typed
by size, joined by a spanning tree of doors; no entrance, and no rules beyond the checks
every house gets.

Stages: ``floorplan`` (footprint, rooms, types) -> ``doors`` (doors; walls by
``objsearch.house.walls``) -> ``furnish`` (``objsearch.house.groups`` per room) -> materials,
run once per attempt by ``build.build_spec``. The golden specs (``tests/house/golden``) pin it.
"""

from objsearch.house.gen1.build import VERSION, build_spec
from objsearch.house.generators import Generator

GENERATOR = Generator(name=VERSION, build_spec=build_spec, attempts=12, shuffle_key=0)
