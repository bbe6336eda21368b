"""Parametric low-poly furniture built with trimesh: one builder per shape family.

Every mesh is built in the unit box x, y in [-0.5, 0.5], z in [0, 1] with the object's
front towards +y (backs go against walls), then normalised to exactly that box, so an
instance of size (w, d, h) is the mesh scaled by (w, d, h). Receptacles also report their
support surface ``(z, x0, y0, x1, y1)`` in the same unit frame (where things may stand).

A variant is ``(style, rng)``: the style picks the construction (legs vs. panels, round vs.
square, arms or not), the rng (seeded from the category id and variant index by
``objsearch.house.assets``) jitters proportions. Builders use no other randomness.

Modules: ``primitives`` (the parts), ``furniture``, ``objects`` and ``fixtures`` (the builders
of each shape family), ``catalogue`` (which builder makes each category; ``build``, ``to_obj``).
"""

from objsearch.house.meshes.catalogue import BUILDERS, build, to_obj

__all__ = ["BUILDERS", "build", "to_obj"]
