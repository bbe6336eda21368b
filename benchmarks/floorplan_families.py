"""How often each floorplan family and feature comes out of a generator: the layout-variety
figures of ``docs/houses.md``, counted on validated houses (``objsearch.house.floorplan_stats``).

    .venv/bin/python benchmarks/floorplan_families.py [--generator house-gen-4] [--seeds 0:100]
        [--split train] [--size-class xlarge] [--json benchmarks/results/floorplan_families.json]
        [--sheet docs/images/house_gen4_families.png]

``--sheet`` also draws a page of plans: the first house of each family, side by side.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

os.environ.setdefault("MUJOCO_GL", "egl")


def main() -> None:
    from objsearch.fileio import write_json
    from objsearch.house.floorplan_stats import describe, shares
    from objsearch.house.generate import generate_house

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--generator", default="house-gen-4")
    p.add_argument("--seeds", default="0:100", help="START:STOP")
    p.add_argument("--split", default="train")
    p.add_argument("--size-class", default=None)
    p.add_argument("--json", default=None, help="write the figures here")
    p.add_argument("--sheet", default=None, help="write a page of plans (one house a family) here")
    a = p.parse_args()
    start, stop = (int(v) for v in a.seeds.split(":"))
    t0 = time.perf_counter()
    specs = [generate_house(s, a.size_class, a.split, generator=a.generator).spec for s in range(start, stop)]
    out = {
        "generator": a.generator,
        "seeds": a.seeds,
        "split": a.split,
        "size_class": a.size_class or "default",
        **shares(specs),
        "mean_attempts": round(float(np.mean([s.attempt for s in specs])), 2),
        "seconds": round(time.perf_counter() - t0, 1),
    }
    print(json.dumps(out, indent=2))
    if a.json:
        write_json(a.json, out)
    if a.sheet:
        write_sheet(specs, describe, Path(a.sheet))


def write_sheet(specs, describe, path: Path) -> None:
    """The first house of each family, side by side, scaled to one height."""
    import cv2

    from objsearch.fileio import atomic_write
    from objsearch.house.preview import render_preview

    firsts: dict[str, object] = {}
    for s in specs:
        firsts.setdefault(describe(s)["family"], s)
    images = [render_preview(s, object_labels=False) for _, s in sorted(firsts.items())]
    height = 900
    images = [cv2.resize(im, (int(im.shape[1] * height / im.shape[0]), height)) for im in images]
    ok, png = cv2.imencode(".png", np.hstack(images))
    with atomic_write(path, "wb") as f:
        f.write(png.tobytes())
    print(f"wrote {path} ({', '.join(sorted(firsts))})")


if __name__ == "__main__":
    main()
