"""Appearance variety of training frames (``objsearch.perception.variety``, ``perception
dataset --variety``): objects change shape and colour but stay where they were and keep
their labels; validation and test frames never change; same seed, same frames."""

import json

import mujoco
import numpy as np
import pytest
from conftest import LOW_RES

from objsearch.errors import UserError
from objsearch.perception.dataset import build_dataset, load_split, read_shard
from objsearch.perception.variety import vary_model
from objsearch.sim.renderer import HouseRenderer
from objsearch.sim.world import HouseRef, World


@pytest.fixture(scope="module")
def world():
    return World.load(HouseRef(seed=1000))


def _object_extents(model):
    """Per mesh geom: world (min, max) of its vertices, shape (G, 2, 3)."""
    data = mujoco.MjData(model)
    mujoco.mj_kinematics(model, data)
    out = []
    for g in np.flatnonzero(model.geom_type == mujoco.mjtGeom.mjGEOM_MESH):
        m = model.geom_dataid[g]
        v = model.mesh_vert[model.mesh_vertadr[m] : model.mesh_vertadr[m] + model.mesh_vertnum[m]]
        w = data.geom_xpos[g] + v @ data.geom_xmat[g].reshape(3, 3).T
        out.append((w.min(axis=0), w.max(axis=0)))
    return np.array(out)


def test_objects_change_shape_and_colour_but_not_place(world):
    before = _object_extents(world.model)
    varied = vary_model(world.model, np.random.default_rng(3))
    after = _object_extents(varied)
    assert np.allclose(after[:, 0, 2], before[:, 0, 2], atol=1e-4)  # lowest points stay: nothing sinks or floats
    centres = lambda e: (e[:, 0, :2] + e[:, 1, :2]) / 2  # noqa: E731
    assert np.allclose(centres(after), centres(before), atol=1e-3)  # stretched about their footprint's centre
    sizes, new_sizes = before[:, 1] - before[:, 0], after[:, 1] - after[:, 0]
    ratio = new_sizes / sizes
    assert ratio.min() >= 0.7 - 1e-3 and ratio.max() <= 1.4 + 1e-3 and ratio.std() > 0.05
    assert not np.allclose(varied.geom_rgba, world.model.geom_rgba)
    assert np.array_equal(_object_extents(world.model), before)  # the input model is untouched
    again = vary_model(world.model, np.random.default_rng(3))
    assert np.array_equal(again.mesh_vert, varied.mesh_vert) and np.array_equal(again.geom_rgba, varied.geom_rgba)
    same = vary_model(world.model, np.random.default_rng(3), strength=0.0)
    assert np.array_equal(same.mesh_vert, world.model.mesh_vert) and np.array_equal(same.mat_rgba, world.model.mat_rgba)
    with pytest.raises(ValueError, match="strength"):
        vary_model(world.model, np.random.default_rng(0), 1.5)


def test_varied_frames_keep_their_labels(world):
    poses = world.graph.world_poses(np.arange(0, world.graph.num_poses, 97))
    with HouseRenderer(world.model, LOW_RES) as r:
        plain = r.render(poses)
    with HouseRenderer(vary_model(world.model, np.random.default_rng(1)), LOW_RES) as r:
        varied = r.render(poses)
    assert (varied.rgb != plain.rgb).any(axis=-1).mean() > 0.05
    changed = varied.semantic != plain.semantic
    assert 0 < changed.mean() < 0.15  # objects change outline; walls and floors are where they were
    # every labelled object pixel is a stretched object of that category, never a new category
    assert set(np.unique(varied.semantic)) <= set(np.unique(plain.semantic)) | {0}


def test_dataset_variety_changes_training_frames_only(tmp_path):
    def build(out, variety):
        houses = {"train": 1, "val": 1, "test": 0}
        kw = dict(settings=LOW_RES, poses_per_house=8, eval_poses_per_house=8, houses=houses, progress=False)
        return build_dataset(tmp_path / out, variety=variety, **kw)

    plain, varied = build("plain", 0.0), build("varied", 1.0)
    assert "variety" not in plain and varied["variety"] == 1.0
    a, b = load_split(tmp_path / "plain", "train"), load_split(tmp_path / "varied", "train")
    assert not np.array_equal(a.rgb, b.rgb)
    assert np.array_equal(load_split(tmp_path / "plain", "val").rgb, load_split(tmp_path / "varied", "val").rgb)
    shard = next((tmp_path / "varied" / "train").glob("*.npz"))
    assert read_shard(shard)["meta"]["variety"] == 1.0
    assert json.loads((tmp_path / "varied" / "manifest.json").read_text())["variety"] == 1.0
    rebuilt = build("again", 1.0)  # same seed, same frames
    assert np.array_equal(load_split(tmp_path / "again", "train").rgb, b.rgb) and rebuilt["splits"] == varied["splits"]
    with pytest.raises(UserError, match="variety must be between 0 and 1"):
        build("bad", 2.0)
