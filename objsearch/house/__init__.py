"""Procedural MuJoCo houses: ``HouseSpec`` (pure data) -> generator stages -> MJCF.

Generator versions are packages, each frozen and exporting one ``Generator`` record:
``gen2`` (``house-gen-2``, the default) and ``gen1`` (``house-gen-1``), each with its own
floorplan, doors, furnishing and rules; ``generators`` is their registry, which
``generate.generate_house(seed, generator=...)`` (the attempt loop, shared), ``validate``
(the checks every house gets, then the version's rules), ``cli`` (``objsearch generate``)
and the suites read by name. A version never imports another; what they share lives here:
``stages`` (splits, size classes, wall sizes, house ids, ``StageFailure``), ``walls``,
``groups`` (furniture groups), ``clearances`` (door keep-outs, passages), ``layout``
(placement primitives), ``materials``, ``mjcf`` (the one MJCF writer), ``occupancy``.
``rooms``: single rooms, a mode of ``house-gen-2``; ``shuffle``: shuffled placement of any
version's house. Categories: ``categories``; meshes: ``meshes`` + ``assets``; previews:
``preview``, ``plan_canvas``, ``plan_legend``.
"""

from objsearch.mujoco_gl import import_mujoco

import_mujoco()  # before this package imports MuJoCo, whatever MUJOCO_GL holds (objsearch.mujoco_gl)
