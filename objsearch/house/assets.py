"""The generated mesh library under ``assets/meshes`` and its manifest.

Build (deterministic: the same bytes on every run)::

    objsearch data rebuild assets [--out DIR]   # writes DIR/meshes/<category>/v<k>.obj + manifest.json

Every category has ``VARIANTS_PER_CATEGORY`` shape variants; variant ``v3`` is reserved for
*test* houses (``objsearch generate --split test``), so test houses contain instances never
seen in training houses. ``manifest.json`` records each variant's split and, for
receptacles, its support surface in the unit frame (see ``objsearch.house.meshes``).

The library is found at ``$OBJSEARCH_ASSETS`` if set, else at ``assets/`` beside the
``objsearch`` package (the repository checkout, also for editable installs).
"""

from __future__ import annotations

import functools
import json
import os
from pathlib import Path

import numpy as np

from objsearch.errors import UserError

ASSETS_VERSION = "meshes-v1"
VARIANTS_PER_CATEGORY = 4
TEST_VARIANTS = ("v3",)


def assets_dir() -> Path:
    """The assets folder: ``$OBJSEARCH_ASSETS``, else the repository's ``assets/``."""
    env = os.environ.get("OBJSEARCH_ASSETS")
    return Path(env) if env else Path(__file__).resolve().parents[2] / "assets"


def build_assets(out: Path) -> dict:
    """Write every variant's OBJ and the manifest under ``out/meshes``; return the manifest."""
    from objsearch.fileio import atomic_write, write_json
    from objsearch.house.categories import CATEGORIES
    from objsearch.house.meshes import build, to_obj

    manifest = {"version": ASSETS_VERSION, "categories": {}}
    for cat in CATEGORIES:
        variants = {}
        for k in range(VARIANTS_PER_CATEGORY):
            name = f"v{k}"
            rng = np.random.default_rng([cat.id, k])
            mesh, surface = build(cat.name, k, rng)
            with atomic_write(out / "meshes" / cat.name / f"{name}.obj", "wb") as f:
                f.write(to_obj(mesh))
            entry = {"split": "test" if name in TEST_VARIANTS else "train", "faces": int(len(mesh.faces))}
            if cat.receptacle:
                entry["surface"] = [round(v, 4) for v in (surface or (1.0, -0.5, -0.5, 0.5, 0.5))]
            variants[name] = entry
        manifest["categories"][cat.name] = variants
    write_json(out / "meshes" / "manifest.json", manifest)
    return manifest


@functools.lru_cache(maxsize=1)
def load_manifest() -> dict:
    """The mesh library's ``manifest.json`` (read once); ``UserError`` if the library is not built."""
    path = assets_dir() / "meshes" / "manifest.json"
    if not path.exists():
        raise UserError(
            f"mesh library not found at {path}; build it with `objsearch data rebuild assets` or set OBJSEARCH_ASSETS"
        )
    with open(path) as f:
        return json.load(f)


def variants(category: str, split: str) -> list[str]:
    """Variant names of ``category`` usable in houses of ``split`` (train or test)."""
    entries = load_manifest()["categories"][category]
    return sorted(v for v, e in entries.items() if e["split"] == split)


def surface(category: str, variant: str) -> tuple[float, float, float, float, float]:
    """Support surface ``(z, x0, y0, x1, y1)`` of a receptacle variant, unit frame."""
    return tuple(load_manifest()["categories"][category][variant]["surface"])


def mesh_file(category: str, variant: str) -> str:
    """Path of a variant relative to the mesh directory (as written into MJCF)."""
    return f"{category}/{variant}.obj"


@functools.lru_cache(maxsize=None)
def mesh_bytes(category: str, variant: str) -> bytes:
    """The OBJ file bytes of one category's variant (read once)."""
    return (assets_dir() / "meshes" / mesh_file(category, variant)).read_bytes()


if __name__ == "__main__":  # `python -m` of this module, a command until 2026-12-02: name its replacement
    raise SystemExit("python -m objsearch.house.assets is now: objsearch data rebuild assets [--out DIR]")
