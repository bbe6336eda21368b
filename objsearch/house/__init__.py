"""Procedural MuJoCo houses: ``HouseSpec`` (pure data) -> generator stages -> MJCF.

Pipeline: ``floorplan`` (footprint, rooms, types) -> ``doors`` (doors, walls) -> ``furnish``
(functional groups, then per-room priors; placement primitives in ``layout``) ->
``materials`` -> ``mjcf`` (the one MJCF writer) -> ``validate`` (uses ``occupancy``).
``generate.generate_house(seed)`` runs it with bounded resampling (``generator="house-gen-2"``,
the default: the ``*_v2`` stages, ``generate_v2``, checked by ``validate_v2`` too;
``generator="house-gen-1"``: the stages named above alone; ``placement="shuffled"``:
the functional house's objects moved anywhere, ``shuffle``); ``cli`` is ``objsearch generate``. Categories: ``categories``; meshes: ``meshes`` + ``assets``.
"""
