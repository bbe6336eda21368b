"""HouseRenderer: shapes, exact segmentation, depth against ray casts, batching, culling, backends."""

import ctypes.util
import json
import math
import os
import subprocess
import sys

import mujoco
import numpy as np
import pytest

from objsearch.errors import UserError
from objsearch.house.categories import BACKGROUND_ID, CATEGORY_IDS, FIRST_OBJECT_ID
from objsearch.house.generate import generate_house
from objsearch.house.mjcf import geom_labels
from objsearch.house.occupancy import occupancy_grid
from objsearch.sim.camera import RenderSettings
from objsearch.sim.glbackend import RenderBackendError, requested_backends
from objsearch.sim.renderer import Frames, HouseRenderer

SIZE = 24  # tiny frames keep the module at a few seconds on llvmpipe


@pytest.fixture(scope="module")
def house():
    return generate_house(3, generator="house-gen-1")  # small house, 76 geoms


@pytest.fixture(scope="module")
def poses(house):
    grid = occupancy_grid(house.spec, 0.05)
    xs, ys = grid.centers()
    rows, cols = np.nonzero(grid.free)
    rng = np.random.default_rng(5)
    pick = rng.integers(len(rows), size=12)
    return np.stack([xs[cols[pick]], ys[rows[pick]], rng.uniform(-math.pi, math.pi, 12)], axis=1)


@pytest.fixture(scope="module")
def renderer(house):
    with HouseRenderer(house.model, RenderSettings(width=SIZE, height=SIZE)) as r:
        yield r


@pytest.fixture(scope="module")
def frames(renderer, poses):
    return renderer.render(poses)


def pixel_rays(settings: RenderSettings, yaw: float) -> np.ndarray:
    """Unit world directions (H, W, 3) through pixel centres; row 0 is the top."""
    t = math.tan(math.radians(settings.fovy) / 2)
    u = ((np.arange(settings.width) + 0.5) / settings.width * 2 - 1) * t * settings.width / settings.height
    v = (1 - (np.arange(settings.height) + 0.5) / settings.height * 2) * t
    uu, vv = np.meshgrid(u, v)
    fwd = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    right = np.array([math.sin(yaw), -math.cos(yaw), 0.0])
    d = fwd + uu[..., None] * right + vv[..., None] * np.array([0.0, 0.0, 1.0])
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def ray_cast(model, pose, settings, rows, cols):
    """(geom id or -1, planar depth) for the given pixels, by mj_ray from the camera."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    dirs = pixel_rays(settings, pose[2])
    origin = np.array([pose[0], pose[1], settings.camera_height])
    fwd = np.array([math.cos(pose[2]), math.sin(pose[2]), 0.0])
    geomid = np.zeros(1, np.int32)
    out = []
    for r, c in zip(rows, cols):
        dist = mujoco.mj_ray(model, data, origin, dirs[r, c], None, 1, -1, geomid)
        out.append((int(geomid[0]) if dist >= 0 else -1, dist * float(dirs[r, c] @ fwd)))
    return out


def test_shapes_and_dtypes(frames, poses):
    n = len(poses)
    assert isinstance(frames, Frames) and len(frames) == n
    assert frames.rgb.shape == (n, SIZE, SIZE, 3) and frames.rgb.dtype == np.uint8
    assert frames.depth.shape == (n, SIZE, SIZE) and frames.depth.dtype == np.float32
    assert frames.semantic.shape == (n, SIZE, SIZE) and frames.semantic.dtype == np.uint8
    assert frames.instance.shape == (n, SIZE, SIZE) and frames.instance.dtype == np.int16


def test_labels_are_those_of_real_geoms(house, frames):
    cats, inst = geom_labels(house.model)
    allowed = {(int(c), int(i)) for c, i in zip(cats, inst)} | {(CATEGORY_IDS["ceiling"], -1), (BACKGROUND_ID, -1)}
    pairs = set(zip(frames.semantic.ravel().tolist(), frames.instance.ravel().tolist()))
    assert pairs <= allowed
    objects = frames.semantic >= FIRST_OBJECT_ID
    assert (frames.instance[objects] >= 0).all() and (frames.instance[~objects] == -1).all()
    assert {CATEGORY_IDS["wall"], CATEGORY_IDS["floor"]} <= set(np.unique(frames.semantic).tolist())


def test_segmentation_matches_ray_casts_exactly_off_edges(house, renderer, poses, frames):
    """Every pixel's label is the geom a ray through its centre hits; where they differ the
    pixel is on an edge and the ray's label is a neighbour's (no blended ids)."""
    cats, inst = geom_labels(house.model)
    s = renderer.settings
    rows, cols = np.meshgrid(np.arange(SIZE), np.arange(SIZE), indexing="ij")
    mismatched = total = 0
    for k in range(4):
        hits = ray_cast(house.model, poses[k], s, rows.ravel(), cols.ravel())
        for (geom, _), r, c in zip(hits, rows.ravel(), cols.ravel()):
            want = (CATEGORY_IDS["ceiling"], -1) if geom < 0 else (int(cats[geom]), int(inst[geom]))
            got = (int(frames.semantic[k, r, c]), int(frames.instance[k, r, c]))
            total += 1
            if got != want:
                mismatched += 1
                near = frames.semantic[k, max(r - 1, 0) : r + 2, max(c - 1, 0) : c + 2]
                near_inst = frames.instance[k, max(r - 1, 0) : r + 2, max(c - 1, 0) : c + 2]
                assert ((near == want[0]) & (near_inst == want[1])).any(), (k, r, c, got, want)
    assert mismatched / total < 0.05


def test_depth_agrees_with_ray_cast(house, renderer, poses, frames):
    s = renderer.settings
    c = SIZE // 2
    for k in range(len(poses)):
        # the centre pixel and its neighbours; skip pixels on an edge (depth jumps there)
        ((geom, expected),) = ray_cast(house.model, poses[k], s, [c], [c])
        patch = frames.depth[k, c - 1 : c + 2, c - 1 : c + 2]
        if geom >= 0 and np.ptp(patch) < 0.05:
            assert frames.depth[k, c, c] == pytest.approx(expected, abs=2e-3, rel=1e-3)


def test_rgb_is_lit_and_varies(frames):
    means = frames.rgb.reshape(len(frames), -1).mean(axis=1)
    assert (means > 40).all() and (means < 230).all()
    assert frames.rgb.std() > 15
    assert len({f.tobytes() for f in frames.rgb}) == len(frames)


def test_batch_equals_single_renders(renderer, poses, frames):
    for k in range(3):
        one = renderer.render(poses[k])
        for name in ("rgb", "depth", "semantic", "instance"):
            assert np.array_equal(getattr(one, name)[0], getattr(frames, name)[k]), name


def test_culling_changes_no_pixel(house, poses, frames):
    with HouseRenderer(house.model, RenderSettings(width=SIZE, height=SIZE), cull=False) as full:
        everything = full.render(poses)
    for name in ("rgb", "depth", "semantic", "instance"):
        assert np.array_equal(getattr(everything, name), getattr(frames, name)), name


def test_tiled_reads_put_each_pose_in_its_place(house, poses, frames):
    # several poses per read-back: same labels and depth; RGB may differ by 1 where textures
    # are interpolated at another buffer position
    with HouseRenderer(house.model, RenderSettings(width=SIZE, height=SIZE), tiles_per_read=5) as tiled:
        f = tiled.render(poses)
    assert np.array_equal(f.semantic, frames.semantic) and np.array_equal(f.instance, frames.instance)
    assert np.allclose(f.depth, frames.depth, atol=1e-4)
    assert np.abs(f.rgb.astype(int) - frames.rgb).max() <= 2


def test_two_byte_ids_decode_like_one_byte_ids(house, poses, frames):
    # houses with more than 253 geoms need the green channel too
    with HouseRenderer(house.model, RenderSettings(width=SIZE, height=SIZE)) as r:
        r._one_byte_ids = False
        f = r.render(poses[:4])
    assert np.array_equal(f.semantic, frames.semantic[:4]) and np.array_equal(f.instance, frames.instance[:4])


def test_without_ceiling_the_sky_is_background_at_zfar(house, poses):
    s = RenderSettings(width=SIZE, height=SIZE, ceiling=False)
    with HouseRenderer(house.model, s) as r:
        f = r.render(poses[:4])
    sky = f.semantic == BACKGROUND_ID
    assert sky.any() and (f.depth[sky] == pytest.approx(s.zfar)) and (f.rgb[sky] == 0).all()
    assert not (f.semantic == CATEGORY_IDS["ceiling"]).any()


def test_opposite_headings_see_different_things(renderer, poses):
    x, y, _ = poses[0]
    f = renderer.render([[x, y, 0.0], [x, y, math.pi]])
    assert not np.array_equal(f.depth[0], f.depth[1])
    assert not np.array_equal(f.rgb[0], f.rgb[1])


def test_renderer_does_not_modify_the_model(house):
    before = (house.model.vis.global_.offwidth, house.model.vis.quality.offsamples, house.model.geom_group.copy())
    with HouseRenderer(house.model, RenderSettings(width=8, height=8)) as r:
        r.render([[1.0, 1.0, 0.0]])
    after = (house.model.vis.global_.offwidth, house.model.vis.quality.offsamples, house.model.geom_group)
    assert before[:2] == after[:2] and np.array_equal(before[2], after[2])


def test_close_is_idempotent_and_final(house):
    r = HouseRenderer(house.model, RenderSettings(width=8, height=8))
    r.close()
    r.close()
    with pytest.raises(UserError, match="closed"):
        r.render([[1.0, 1.0, 0.0]])


def test_bad_poses_and_settings(renderer):
    with pytest.raises(UserError, match="shape"):
        renderer.render(np.zeros((2, 2)))
    with pytest.raises(UserError, match="NaN"):
        renderer.render([[np.nan, 0.0, 0.0]])
    with pytest.raises(UserError):
        RenderSettings(width=0)
    with pytest.raises(UserError):
        RenderSettings(znear=2.0, zfar=1.0)


def test_settings_key_and_json():
    s = RenderSettings(width=32, height=24)
    assert s.key() == RenderSettings(width=32, height=24).key()
    assert s.key() != RenderSettings(width=32, height=24, fovy=60.0).key()
    assert s.to_json() == {
        "width": 32,
        "height": 24,
        "fovy": 90.0,
        "camera_height": 1.0,
        "znear": 0.05,
        "zfar": 30.0,
        "ceiling": True,
    }  # JSON-ready data (objsearch.configs.JsonConfig), not text
    assert RenderSettings.from_json(s.to_json()) == s
    assert RenderSettings.from_json(json.loads(s.to_json_text())) == s  # text only at the file edge
    assert json.loads(s.to_json_text()) == s.to_json() and list(json.loads(s.to_json_text())) == sorted(s.to_json())
    with pytest.raises(UserError, match=r"camera.json is not camera settings \(RenderSettings\): unknown key 'colour'"):
        RenderSettings.from_json({"width": 8, "colour": "red"}, source="camera.json")
    with pytest.raises(UserError, match="must be an integer"):
        RenderSettings.from_json({"width": "8"})


def test_requested_backends():
    assert requested_backends("") == ("egl", "osmesa")
    assert requested_backends("EGL") == ("egl",)
    assert requested_backends("glx") == ("glfw",)
    assert requested_backends("osmesa") == ("osmesa",)
    with pytest.raises(RenderBackendError, match="disables"):
        requested_backends("disable")


def _python(code: str, mujoco_gl: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "MUJOCO_GL": mujoco_gl}
    return subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)


FIRST_RENDER = (
    "import objsearch.sim.renderer\n"  # importing is fine: a value import mujoco fails on was set aside
    "from objsearch.house.generate import generate_house\n"
    "from objsearch.sim.renderer import HouseRenderer\n"
    "from objsearch.errors import UserError\n"
    "model = generate_house(3, generator='house-gen-1').model\n"
    "try:\n"
    "    HouseRenderer(model)\n"
    "except UserError as err:\n"
    "    print(type(err).__name__, err)\n"
)


@pytest.mark.skipif(ctypes.util.find_library("OSMesa") is not None, reason="OSMesa is installed here")
def test_missing_osmesa_is_a_one_line_error_at_the_first_render():
    proc = _python(FIRST_RENDER, "osmesa")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("RenderBackendError") and "libOSMesa is not installed" in proc.stdout
    assert len(proc.stdout.strip().splitlines()) == 1


def test_bogus_backend_is_a_one_line_error_at_the_first_render():
    # mujoco itself would reject the value at import with a bare RuntimeError ...
    proc = _python(FIRST_RENDER, "bogus")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("RenderBackendError") and "MUJOCO_GL='bogus'" in proc.stdout and "egl" in proc.stdout
    assert len(proc.stdout.strip().splitlines()) == 1
    # ... and a value changed after the import is read when the renderer is created
    code = FIRST_RENDER.replace("try:", "import os\nos.environ['MUJOCO_GL'] = 'nosuchgl'\ntry:")
    proc = _python(code, "egl")
    assert proc.returncode == 0, proc.stderr
    assert "RenderBackendError" in proc.stdout and "nosuchgl" in proc.stdout and "osmesa" in proc.stdout
