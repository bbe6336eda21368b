"""Live RGB-D-segmentation frames per second: HouseRenderer against a naive mujoco.Renderer loop.

    MUJOCO_GL=egl python benchmarks/bench_render.py [--seed 0] [--poses 256] [--json]
    MUJOCO_GL=egl python benchmarks/bench_render.py --ablation      # what each trick buys
    MUJOCO_GL=egl python benchmarks/bench_render.py --samples docs/images/render_samples.png
    MUJOCO_GL=egl python benchmarks/bench_render.py --frames cpu.npz        # on one machine
    python benchmarks/bench_render.py --compare cpu.npz gpu.npz             # do two machines agree?

A typical generated house (seed 0: medium, 5 rooms, 113 geoms), random poses on free
space (0.05 m occupancy grid, random yaw). One "frame" is RGB + depth + semantic +
instance for one pose. The naive loop is what a first attempt with ``mujoco.Renderer``
looks like: default visual settings (4x multisampling, all flags), a free camera, and
three renders per pose (RGB, depth, segmentation), ids mapped to categories per frame.
Both are timed in the same run; each figure is the median of ``--repeats`` timed runs
after a warm-up.
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import statistics
import time

import mujoco
import numpy as np

from objsearch.house.generate import generate_house
from objsearch.house.mjcf import geom_labels
from objsearch.house.occupancy import occupancy_grid
from objsearch.house.spec import HouseSpec
from objsearch.sim.camera import RenderSettings
from objsearch.sim.renderer import HouseRenderer


def random_free_poses(spec: HouseSpec, n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, 3) poses (x, y, yaw) at random free cells of a 0.05 m occupancy grid."""
    grid = occupancy_grid(spec, 0.05)
    xs, ys = grid.centers()
    rows, cols = np.nonzero(grid.free)
    pick = rng.integers(len(rows), size=n)
    return np.stack([xs[cols[pick]], ys[rows[pick]], rng.uniform(-math.pi, math.pi, n)], axis=1)


def _median_seconds(fn, repeats: int) -> float:
    fn()  # warm-up: shader variants, caches
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def measure_live_fps(
    model: mujoco.MjModel, settings: RenderSettings, poses: np.ndarray, repeats: int = 3, **renderer_kwargs
) -> float:
    """Frames (RGB + depth + semantic + instance) per second of ``HouseRenderer.render(poses)``."""
    with HouseRenderer(model, settings, **renderer_kwargs) as renderer:
        return len(poses) / _median_seconds(lambda: renderer.render(poses), repeats)


def measure_naive_fps(
    model: mujoco.MjModel, settings: RenderSettings, poses: np.ndarray, repeats: int = 3, offsamples: int | None = None
) -> float:
    """Frames per second of a naive ``mujoco.Renderer`` loop: three renders per pose.

    The model's default visual settings are kept (``offsamples`` overrides multisampling
    for the ablation); only the field of view is set to ``settings.fovy`` so both views match.
    """
    model = copy.deepcopy(model)
    model.vis.global_.fovy = settings.fovy
    if offsamples is not None:
        model.vis.quality.offsamples = offsamples
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    cats, inst = geom_labels(model)
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    cam.distance, cam.elevation = 1.0, 0.0

    def loop():
        for x, y, yaw in poses:
            cam.lookat[:] = (x + math.cos(yaw), y + math.sin(yaw), settings.camera_height)
            cam.azimuth = math.degrees(yaw)
            renderer.update_scene(data, cam)
            renderer.render()
            renderer.enable_depth_rendering()
            renderer.render()
            renderer.disable_depth_rendering()
            renderer.enable_segmentation_rendering()
            seg = renderer.render()
            renderer.disable_segmentation_rendering()
            geom = np.where(seg[..., 1] == mujoco.mjtObj.mjOBJ_GEOM, seg[..., 0], -1)
            _ = cats[geom], inst[geom]

    with mujoco.Renderer(model, settings.height, settings.width) as renderer:
        return len(poses) / _median_seconds(loop, repeats)


def save_frames(model: mujoco.MjModel, spec: HouseSpec, path: str) -> None:
    """Frames of 64 fixed poses (seed 7) at 64x64 and 128x128, for ``compare_frames``."""
    poses = random_free_poses(spec, 64, np.random.default_rng(7))
    arrays = {"poses": poses}
    for size in (64, 128):
        with HouseRenderer(model, RenderSettings(width=size, height=size)) as renderer:
            frames = renderer.render(poses)
        arrays.update({f"{key}_{size}": getattr(frames, key) for key in ("rgb", "depth", "semantic", "instance")})
    np.savez_compressed(path, **arrays)


def compare_frames(path_a: str, path_b: str) -> dict[str, float]:
    """How far two ``--frames`` files (two machines, two backends) disagree, image by image:
    the fraction of pixels that differ, and for RGB those off by more than 2 levels, for
    depth the largest difference in metres."""
    a, b = np.load(path_a), np.load(path_b)
    if not np.array_equal(a["poses"], b["poses"]):
        raise SystemExit(f"{path_a} and {path_b} hold frames of different poses: make both with --frames")
    out = {}
    for key in sorted(set(a.files) - {"poses"}):
        x, y = a[key], b[key]
        out[f"{key}_differ"] = float((x != y).mean())
        if key.startswith("rgb"):
            out[f"{key}_off_by_3_plus"] = float((np.abs(x.astype(int) - y.astype(int)) > 2).mean())
        if key.startswith("depth"):
            out[f"{key}_max_m"] = float(np.abs(x - y).max())
    return out


def ablation(model, poses, naive_poses, repeats) -> list[tuple[str, int, float]]:
    """The tricks one at a time: (label, size, fps)."""
    rows = []
    for size in (64, 128):
        s = RenderSettings(width=size, height=size)
        rows.append(
            (
                "naive mujoco.Renderer, 3 passes, default visuals (4x MSAA)",
                size,
                measure_naive_fps(model, s, naive_poses, repeats),
            )
        )
        rows.append(
            (
                "naive mujoco.Renderer, 3 passes, offsamples=0",
                size,
                measure_naive_fps(model, s, naive_poses, repeats, offsamples=0),
            )
        )
        rows.append(
            (
                "HouseRenderer, no culling, one read per pose",
                size,
                measure_live_fps(model, s, naive_poses, repeats, cull=False),
            )
        )
        rows.append(
            (
                "HouseRenderer, no culling, one read per 256-pose tiled sheet",
                size,
                measure_live_fps(model, s, poses, repeats, cull=False, tiles_per_read=256),
            )
        )
        rows.append(
            (
                "HouseRenderer, portal culling, one read per 256-pose tiled sheet",
                size,
                measure_live_fps(model, s, poses, repeats, tiles_per_read=256),
            )
        )
        rows.append(
            (
                "HouseRenderer (default: portal culling, one read per pose)",
                size,
                measure_live_fps(model, s, poses, repeats),
            )
        )
    return rows


def write_samples(model, poses, path: str, size: int = 128) -> None:
    """A grid: one row per pose, columns RGB | depth (inferno, 0 to 6 m) | semantic (false colour)."""
    import cv2

    from objsearch.fileio import atomic_write

    with HouseRenderer(model, RenderSettings(width=size, height=size)) as renderer:
        f = renderer.render(poses)
    palette = np.random.default_rng(7).integers(40, 256, size=(256, 3)).astype(np.uint8)
    palette[0] = 0
    rows = []
    for k in range(len(poses)):
        depth = (255 * (1 - np.clip(f.depth[k] / 6.0, 0, 1))).astype(np.uint8)
        depth = cv2.applyColorMap(depth, cv2.COLORMAP_INFERNO)[..., ::-1]
        rows.append(np.concatenate([f.rgb[k], depth, palette[f.semantic[k]]], axis=1))
    ok, png = cv2.imencode(".png", np.concatenate(rows, axis=0)[..., ::-1])
    with atomic_write(path, "wb") as fh:
        fh.write(png.tobytes())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0, help="house seed (0: medium, 5 rooms)")
    parser.add_argument("--poses", type=int, default=256, help="poses per HouseRenderer batch")
    parser.add_argument("--naive-poses", type=int, default=64, help="poses in the (slow) naive loop")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument("--ablation", action="store_true", help="measure the tricks one at a time")
    parser.add_argument("--samples", metavar="PNG", help="write sample frames (rgb | depth | semantic) and exit")
    parser.add_argument("--frames", metavar="NPZ", help="write the frames of 64 fixed poses and exit")
    parser.add_argument("--compare", nargs=2, metavar="NPZ", help="compare two --frames files and exit")
    args = parser.parse_args()
    if args.compare:
        print(json.dumps(compare_frames(*args.compare)))
        return

    house = generate_house(args.seed, generator="house-gen-1")  # the house of the recorded figures
    rng = np.random.default_rng(args.seed)
    poses = random_free_poses(house.spec, args.poses, rng)
    if args.samples:
        write_samples(house.model, random_free_poses(house.spec, 3, np.random.default_rng(1)), args.samples)
        return
    if args.frames:
        save_frames(house.model, house.spec, args.frames)
        return
    naive_poses = poses[: args.naive_poses]
    if args.ablation:
        for label, size, fps in ablation(house.model, poses, naive_poses, args.repeats):
            print(f"{size:4d}x{size:<4d} {fps:8.0f} fps  {label}")
        return
    out = {"house": house.spec.house_id, "geoms": int(house.model.ngeom), "poses": len(poses)}
    with HouseRenderer(house.model) as probe:
        out["backend"] = probe.backend
    for size in (64, 128):
        settings = RenderSettings(width=size, height=size)
        out[f"live_fps_{size}"] = round(measure_live_fps(house.model, settings, poses, args.repeats), 1)
        out[f"naive_fps_{size}"] = round(measure_naive_fps(house.model, settings, naive_poses, args.repeats), 1)
        out[f"speedup_{size}"] = round(out[f"live_fps_{size}"] / out[f"naive_fps_{size}"], 2)
    if args.json:
        print(json.dumps(out))
    else:
        for key, value in out.items():
            print(f"{key:>14}: {value}")


if __name__ == "__main__":
    main()
