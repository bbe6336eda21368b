"""Generator ``house-gen-3``: large houses where search decides.

``house-gen-2``'s zoned stages (floorplan bands, doors by circulation rules, an entrance,
furniture and fill), run with a room program for 4 to 14 rooms that repeats room types
(2-5 bedrooms, 2-3 bathrooms, 1-2 offices from 9 rooms on), a private band as long as the
house needs (so large houses have a long corridor with rooms on both sides), and small
objects kept rare: at most ``MAX_TARGET_INSTANCES`` of each of the ``SMALL_TARGETS`` per
house (one), so that a small target is in one place and must be searched for.

Size classes (``stages.ROOM_COUNT_CLASSES``): ``xlarge`` (the default, 9-14 rooms drawn per
house) and ``rooms-4`` ... ``rooms-14`` (``objsearch generate --rooms N``), the size knob of
the large-house tier's size sweep. A newer version may build on an older, frozen version's
stages (never the reverse): ``house-gen-2``'s functions take their limits as arguments, with
``house-gen-2``'s values as defaults.
"""

from objsearch.house.gen3.build import VERSION, build_spec, default_size_class
from objsearch.house.gen3.rules import check_rules
from objsearch.house.generators import Generator
from objsearch.house.stages import ROOM_COUNT_CLASSES

GENERATOR = Generator(
    name=VERSION,
    build_spec=build_spec,
    attempts=24,
    shuffle_key=3,
    check_rules=check_rules,
    size_classes=tuple(ROOM_COUNT_CLASSES),
    default_size_class=default_size_class,
)
