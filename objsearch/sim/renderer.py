"""What an agent sees in a house: RGB, depth and semantic/instance segmentation, in batches.

``HouseRenderer(model, settings).render(poses)`` renders N agent poses ``(x, y, yaw)`` at
once and returns ``Frames``. The camera stands at ``settings.camera_height`` and looks
horizontally along ``(cos yaw, sin yaw, 0)`` (yaw 0 looks along +x, counter-clockwise
positive) with a vertical field of view ``settings.fovy``.

How it is fast on a CPU (Mesa llvmpipe) and on a GPU (figures in benchmarks/RESULTS.md):

* only geoms that may be visible are drawn (``objsearch.sim.culling``: conservative portal
  culling through door openings; images are identical without it). On llvmpipe a frame
  costs mostly a fixed amount per drawn geom, and a pose sees ~12 of ~110 geoms;
* the house is static: per pose the scene's geom list is rebuilt in C
  (``mjv_updateScene``, a few microseconds) and the camera and the headlight that follows
  it are written straight into ``mjvScene``;
* agent cameras need no shadows, reflections, skybox, fog or multisampling
  (``offsamples=0``, which also keeps segmentation exact at edges: nothing is blended);
* RGB and depth come from one lit pass; the id-colour pass (``mjRND_SEGMENT |
  mjRND_IDCOLOR``, flat, unlit) is drawn beside it in the same buffer, and both are read
  back together; id colours are decoded with numpy lookup tables (scene geom -> category
  / instance), depth linearised with numpy;
* every pose is drawn at the same place in the buffer, so a pose looks exactly the same
  alone or in any batch (live and cached observations agree bit for bit); drawing many
  poses side by side before one read-back (``tiles_per_read``) is not faster once
  culling is on, and would break that.

An optional ceiling (``settings.ceiling``, on by default) closes the rooms for agent
cameras: houses are generated without one (so a top-down view sees in), but a camera at
1 m with a 90 degree field of view would otherwise look at the black void above the walls.
It is labelled with the ``ceiling`` structure class.

Threads: one renderer is one GL context; use it from one thread at a time.

The camera itself is pure data: ``objsearch.sim.camera.RenderSettings`` (and
``RENDERER_VERSION``, which cache keys hash), importable without MuJoCo.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import mujoco  # importable whatever MUJOCO_GL holds: objsearch/sim/__init__.py (objsearch.mujoco_gl)
import numpy as np

from objsearch.errors import UserError
from objsearch.house.categories import BACKGROUND_ID, CATEGORY_IDS
from objsearch.house.mjcf import geom_labels
from objsearch.sim.camera import AGENT_CAMERA, MAX_SHEET, RENDERER_VERSION, RenderSettings  # noqa: F401
from objsearch.sim.culling import PortalCuller
from objsearch.sim.glbackend import RenderBackendError, create_gl_context

# RenderSettings and RENDERER_VERSION live in objsearch.sim.camera (pure data, no MuJoCo);
# they stay importable from here for existing code.
__all__ = ["Frames", "HouseRenderer", "RenderBackendError"]

CEILING_ID = CATEGORY_IDS["ceiling"]
HIDDEN_GROUP = 5  # geom group culled geoms are moved to (not drawn)
CATEGORIES = int(mujoco.mjtCatBit.mjCAT_STATIC | mujoco.mjtCatBit.mjCAT_DYNAMIC)
CEILING_EMISSION = 0.4
_CEILING_RGBA = np.array([0.92, 0.91, 0.88, 1.0], np.float32)
_EYE9 = np.eye(3).ravel()


@dataclass
class Frames:
    """A batch of N rendered views (row 0 of every image is the top).

    Attributes:
        rgb: uint8 (N, H, W, 3).
        depth: float32 (N, H, W), metres: planar z-depth along the optical axis (not the
            distance along the pixel's ray). Pixels that see nothing are ``settings.zfar``.
        semantic: uint8 (N, H, W), category id per pixel from
            ``objsearch.house.categories.CATEGORY_IDS`` (structure classes wall / floor /
            door / ceiling included; ``BACKGROUND_ID`` (0) where nothing is hit).
        instance: int16 (N, H, W), the object's instance number as in
            ``objsearch.house.mjcf.geom_labels``; -1 for structure and background.
    """

    rgb: np.ndarray
    depth: np.ndarray
    semantic: np.ndarray
    instance: np.ndarray

    def __len__(self) -> int:
        return len(self.rgb)


def _as_poses(poses) -> np.ndarray:
    arr = np.asarray(poses, dtype=np.float64)
    if arr.ndim == 1 and arr.shape == (3,):
        arr = arr[None]
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise UserError(f"poses must be an array of shape (N, 3) of (x, y, yaw), got shape {np.shape(poses)}")
    if not np.isfinite(arr).all():
        raise UserError("poses contain NaN or infinite values")
    return arr


class HouseRenderer:
    """Renders RGB, depth and segmentation of a static house model for batches of poses.

    Args:
        model: The compiled house (``GeneratedHouse.model``); it is not modified (the
            renderer keeps a copy).
        settings: The camera (default ``objsearch.sim.camera.AGENT_CAMERA``).
        cull: Draw only geoms that may be visible (``objsearch.sim.culling``); the images
            are identical either way. Off only to measure what it buys.
        tiles_per_read: Poses drawn side by side before one ``mjr_readPixels`` (default 1).
            More tiles per read save read-backs but make images depend on where a pose
            lands in the buffer (llvmpipe's texture interpolation: RGB off by 1 in about
            0.05% of pixels), so a pose would not look the same alone and in a batch. With
            culling on, one read per pose is as fast on llvmpipe. For benchmarks.

    Raises:
        RenderBackendError: No OpenGL backend works (see ``objsearch.sim.glbackend``).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        settings: RenderSettings = AGENT_CAMERA,
        *,
        cull: bool = True,
        tiles_per_read: int = 1,
    ):
        self._gl = None
        self._con = None
        self.settings = settings
        w, h = settings.width, settings.height
        # Buffer: RGB tiles on the left half, the same poses' id colours on the right half.
        per = max(1, int(tiles_per_read))
        self.cols = min(per, max(1, (MAX_SHEET // 2) // w))
        self.rows = min(-(-per // self.cols), max(1, MAX_SHEET // h))
        self.sheet_w, self.sheet_h = 2 * self.cols * w, self.rows * h
        # A private copy: per pose, culled geoms are moved to a hidden geom group.
        self.model = copy.deepcopy(model)
        self.model.vis.global_.offwidth, self.model.vis.global_.offheight = self.sheet_w, self.sheet_h
        self.model.vis.quality.offsamples = 0  # no multisampling: exact segmentation, cheaper fill
        self.model.vis.quality.shadowsize = 0  # no shadow map to allocate

        self._gl, self.backend = create_gl_context(self.sheet_w, self.sheet_h)
        try:
            self._con = mujoco.MjrContext(self.model, mujoco.mjtFontScale.mjFONTSCALE_50)
        except Exception as err:
            self.close()
            raise RenderBackendError(
                f"MuJoCo could not create its render context with the {self.backend} backend: {err}"
            ) from err
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self._con)
        self._con.readDepthMap = mujoco.mjtDepthMap.mjDEPTH_ZEROFAR
        half_fov = math.atan(math.tan(math.radians(settings.fovy) / 2) * w / h)
        self._culler = PortalCuller(self.model, half_fov) if cull else None
        self._build_scene()

    # ------------------------------------------------------------------ scene

    def _build_scene(self) -> None:
        model, s = self.model, self.settings
        self._data = mujoco.MjData(model)
        mujoco.mj_kinematics(model, self._data)
        opt = mujoco.MjvOption()
        for flag in range(mujoco.mjtVisFlag.mjNVISFLAG):
            opt.flags[flag] = 0  # no joints, lights, cameras, contact points ...
        opt.flags[mujoco.mjtVisFlag.mjVIS_TEXTURE] = 1
        opt.flags[mujoco.mjtVisFlag.mjVIS_STATIC] = 1  # the house is all static bodies
        opt.sitegroup[:] = 0
        opt.geomgroup[:] = 1
        opt.geomgroup[HIDDEN_GROUP] = 0
        self._opt = opt
        self._cam = mujoco.MjvCamera()
        mujoco.mjv_defaultFreeCamera(model, self._cam)
        self._groups = model.geom_group.copy()
        self._scn = scn = mujoco.MjvScene(model, maxgeom=model.ngeom + 8)
        self._update_scene(None)
        if [scn.geoms[i].objid for i in range(model.ngeom)] != list(range(model.ngeom)):
            raise RuntimeError("mjv_updateScene did not add the geoms in model order; the id decoding relies on it")
        for flag in (
            mujoco.mjtRndFlag.mjRND_SHADOW,
            mujoco.mjtRndFlag.mjRND_REFLECTION,
            mujoco.mjtRndFlag.mjRND_SKYBOX,
            mujoco.mjtRndFlag.mjRND_FOG,
            mujoco.mjtRndFlag.mjRND_HAZE,
            mujoco.mjtRndFlag.mjRND_WIREFRAME,
            mujoco.mjtRndFlag.mjRND_SEGMENT,
            mujoco.mjtRndFlag.mjRND_IDCOLOR,
            mujoco.mjtRndFlag.mjRND_DEPTH,
        ):
            scn.flags[flag] = 0
        scn.flags[mujoco.mjtRndFlag.mjRND_CULL_FACE] = 1

        # Per geom labels; scene geom i (id colour i + 1) is the i-th drawn model geom.
        cats, inst = geom_labels(model)
        self._cats = cats.astype(np.uint8)
        self._inst = inst.astype(np.int16)
        self._ceiling = self._ceiling_box() if s.ceiling else None
        self._one_byte_ids = model.ngeom + 2 < 256  # ids fit in the red channel

        # Camera frustum (the same for every pose); both eyes identical (mono).
        top = s.znear * math.tan(math.radians(s.fovy) / 2)
        self._frustum = dict(
            frustum_near=s.znear,
            frustum_far=s.zfar,
            frustum_top=top,
            frustum_bottom=-top,
            frustum_center=0.0,
            frustum_width=top * s.width / s.height,
            orthographic=0,
        )

    def _ceiling_box(self):
        """(size, pos) of a slab over the house footprint, on top of the walls."""
        model = self.model
        world_boxes = (model.geom_type == mujoco.mjtGeom.mjGEOM_BOX) & (model.geom_bodyid == 0)
        if not world_boxes.any():
            return None
        lo = (self._data.geom_xpos[world_boxes] - model.geom_size[world_boxes]).min(axis=0)
        hi = (self._data.geom_xpos[world_boxes] + model.geom_size[world_boxes]).max(axis=0)
        t = 0.05
        return np.array([(hi[0] - lo[0]) / 2, (hi[1] - lo[1]) / 2, t]), np.array(
            [(hi[0] + lo[0]) / 2, (hi[1] + lo[1]) / 2, hi[2] + t]
        )

    def _update_scene(self, visible: np.ndarray | None) -> None:
        """Rebuild the scene's geom list: only ``visible`` model geoms (all if None), plus the ceiling."""
        groups = self.model.geom_group
        if visible is None:
            groups[:] = self._groups
        else:
            np.copyto(groups, np.where(visible, self._groups, HIDDEN_GROUP))
        scn = self._scn
        mujoco.mjv_updateScene(self.model, self._data, self._opt, None, self._cam, CATEGORIES, scn)
        if getattr(self, "_ceiling", None) is not None:
            geom = scn.geoms[scn.ngeom]
            mujoco.mjv_initGeom(
                geom, mujoco.mjtGeom.mjGEOM_BOX, self._ceiling[0], self._ceiling[1], _EYE9, _CEILING_RGBA
            )
            geom.objtype, geom.objid, geom.category, geom.segid = (
                mujoco.mjtObj.mjOBJ_UNKNOWN,
                -1,
                mujoco.mjtCatBit.mjCAT_STATIC,
                scn.ngeom,
            )
            geom.emission = CEILING_EMISSION  # lit from below only by the ambient term otherwise: too dark
            scn.ngeom += 1

    def _set_camera(self, pose: np.ndarray) -> None:
        x, y, yaw = pose
        pos = (x, y, self.settings.camera_height)
        fwd = (math.cos(yaw), math.sin(yaw), 0.0)
        for eye in self._scn.camera:
            eye.pos[:] = pos
            eye.forward[:] = fwd
            eye.up[:] = (0.0, 0.0, 1.0)
            for k, v in self._frustum.items():
                setattr(eye, k, v)
        scn = self._scn
        for i in range(scn.nlight):
            light = scn.lights[i]
            if light.headlight:
                light.pos[:] = pos
                light.dir[:] = fwd

    # ------------------------------------------------------------------ rendering

    def render(self, poses) -> Frames:
        """Render the views from ``poses``.

        Args:
            poses: Array-like (N, 3) of (x, y, yaw) in world metres / radians (or one pose
                of shape (3,)).

        Returns:
            ``Frames`` with N images each.
        """
        if self._con is None:
            raise UserError("this HouseRenderer is closed; create a new one")
        poses = _as_poses(poses)
        n, s = len(poses), self.settings
        out = Frames(
            rgb=np.empty((n, s.height, s.width, 3), np.uint8),
            depth=np.empty((n, s.height, s.width), np.float32),
            semantic=np.empty((n, s.height, s.width), np.uint8),
            instance=np.empty((n, s.height, s.width), np.int16),
        )
        self._gl.make_current()
        w, h = s.width, s.height
        raw = np.empty((n, h, 2 * w, 3), np.uint8)  # bottom-up rows; RGB | id colour
        zbuf = np.empty((n, h, w), np.float32)
        drawn = []  # per pose: the model geoms drawn, in scene order (None: all)
        per = self.cols * self.rows
        for chunk in range(0, n, per):
            self._render_chunk(poses[chunk : chunk + per], raw[chunk : chunk + per], zbuf[chunk : chunk + per], drawn)
        raw, zbuf = raw[:, ::-1], zbuf[:, ::-1]  # OpenGL rows run bottom-up
        out.rgb[:] = raw[:, :, :w]
        out.depth[:] = self._linear_depth(zbuf)
        if self._one_byte_ids:
            ids = raw[:, :, w:, 0].astype(np.intp)
        else:
            ids = raw[:, :, w:, 0].astype(np.intp) | (raw[:, :, w:, 1].astype(np.intp) << 8)
        # Per-pose tables: id colour (scene index + 1; 0 = nothing drawn) -> category / instance.
        width = self.model.ngeom + 2
        sem_lut = np.full((n, width), BACKGROUND_ID, np.uint8)
        inst_lut = np.full((n, width), -1, np.int16)
        everything = np.arange(self.model.ngeom)
        for k, geoms in enumerate(drawn):
            geoms = everything if geoms is None else geoms
            sem_lut[k, 1 : len(geoms) + 1] = self._cats[geoms]
            inst_lut[k, 1 : len(geoms) + 1] = self._inst[geoms]
            if self._ceiling is not None:
                sem_lut[k, len(geoms) + 1] = CEILING_ID
        flat = ids + (np.arange(n) * width)[:, None, None]
        out.semantic[:] = sem_lut.ravel()[flat]
        out.instance[:] = inst_lut.ravel()[flat]
        return out

    def _render_chunk(self, poses: np.ndarray, raw: np.ndarray, zbuf: np.ndarray, drawn: list) -> None:
        """Draw up to cols * rows poses as tiles, read them into raw / zbuf (rows bottom-up)."""
        scn, con = self._scn, self._con
        h, w = zbuf.shape[1:]
        n = len(poses)
        cols = min(self.cols, n)
        rows = -(-n // cols)
        half = cols * w
        segment, idcolor = mujoco.mjtRndFlag.mjRND_SEGMENT, mujoco.mjtRndFlag.mjRND_IDCOLOR
        for k in range(n):
            visible = self._culler.visible(*poses[k]) if self._culler is not None else None
            self._update_scene(visible)
            drawn.append(np.flatnonzero(visible) if visible is not None else None)
            self._set_camera(poses[k])
            left, bottom = (k % cols) * w, (k // cols) * h
            mujoco.mjr_render(mujoco.MjrRect(left, bottom, w, h), scn, con)  # lit colour + depth
            scn.flags[segment] = scn.flags[idcolor] = 1
            mujoco.mjr_render(mujoco.MjrRect(half + left, bottom, w, h), scn, con)  # flat id colours
            scn.flags[segment] = scn.flags[idcolor] = 0
        if n == 1:  # straight into the output buffers (contiguous slices are written in place)
            mujoco.mjr_readPixels(raw[0], None, mujoco.MjrRect(0, 0, 2 * w, h), con)
            mujoco.mjr_readPixels(None, zbuf[0], mujoco.MjrRect(0, 0, w, h), con)
            return
        rgb = np.empty((rows * h, 2 * half, 3), np.uint8)
        z = np.empty((rows * h, half), np.float32)
        mujoco.mjr_readPixels(rgb, None, mujoco.MjrRect(0, 0, 2 * half, rows * h), con)
        mujoco.mjr_readPixels(None, z, mujoco.MjrRect(0, 0, half, rows * h), con)
        raw[:, :, :w] = self._untile(rgb[:, :half], n, cols)
        raw[:, :, w:] = self._untile(rgb[:, half:], n, cols)
        zbuf[:] = self._untile(z, n, cols)

    def _linear_depth(self, z: np.ndarray) -> np.ndarray:
        # Reverse-Z depth buffer (near -> 1, far -> 0, cleared to 0): invert the projection.
        n, f = np.float32(self.settings.znear), np.float32(self.settings.zfar)
        return (f * n) / (z * (f - n) + n)

    def _untile(self, sheet: np.ndarray, n: int, cols: int) -> np.ndarray:
        """(rows*H, cols*W, ...) sheet -> (n, H, W, ...) tiles in tile order (rows stay bottom-up)."""
        h, w = self.settings.height, self.settings.width
        rows = sheet.shape[0] // h
        tiles = sheet.reshape(rows, h, cols, w, *sheet.shape[2:])
        tiles = np.swapaxes(tiles, 1, 2).reshape(rows * cols, h, w, *sheet.shape[2:])
        return tiles[:n]

    # ------------------------------------------------------------------ lifetime

    def close(self) -> None:
        """Free the GL resources; calling it again does nothing."""
        if self._con is not None and self._gl is not None:
            self._gl.make_current()
            self._con.free()
        self._con = None
        if self._gl is not None:
            self._gl.free()
        self._gl = None

    def __enter__(self) -> "HouseRenderer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass
