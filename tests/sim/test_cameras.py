"""The two named cameras (agent, goal), the light module they live in, and the one camera
check every entry point that pairs a checkpoint with a camera goes through."""

import subprocess
import sys

import pytest

from objsearch.errors import UserError
from objsearch.sim.camera import AGENT_CAMERA, CameraMismatchError, RenderSettings, check_camera
from objsearch.sim.goals import GOAL_CAMERA

# Cache keys of existing caches (~/.cache/objsearch) and the suite files' goal_camera depend on these.
KEY_64 = "f733eaddf306a059"
CAMERA_64 = {
    "width": 64,
    "height": 64,
    "fovy": 90.0,
    "camera_height": 1.0,
    "znear": 0.05,
    "zfar": 30.0,
    "ceiling": True,
}


def test_agent_and_goal_cameras_are_named_and_unchanged():
    assert AGENT_CAMERA.to_json() == GOAL_CAMERA.to_json() == RenderSettings().to_json() == CAMERA_64
    assert AGENT_CAMERA.key() == GOAL_CAMERA.key() == RenderSettings().key() == KEY_64
    assert RenderSettings(width=32, height=32).key() == "7066b65770c63b5d"


def test_camera_module_is_light_and_the_renderer_still_exports_settings():
    code = (
        "import sys; import objsearch.sim.camera, objsearch.sim.goals; "
        "heavy = [m for m in ('mujoco', 'torch', 'OpenGL') if m in sys.modules]; assert not heavy, heavy"
    )
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)
    from objsearch.sim import renderer

    assert renderer.RenderSettings is RenderSettings and renderer.HouseRenderer.__init__.__defaults__[0] is AGENT_CAMERA


def test_house_env_defaults_to_the_agent_camera():
    import inspect

    from objsearch.sim.env import HouseEnv

    assert inspect.signature(HouseEnv).parameters["settings"].default is AGENT_CAMERA


def test_one_check_one_error():
    small = RenderSettings(width=32, height=32)
    assert check_camera(AGENT_CAMERA.to_json(), AGENT_CAMERA, source="x", expected_name="y", fix="z") == AGENT_CAMERA
    with pytest.raises(CameraMismatchError) as err:
        check_camera(small, AGENT_CAMERA, source="checkpoint c.pt", expected_name="the agent camera", fix="retrain it")
    text = str(err.value)
    assert isinstance(err.value, UserError)
    assert text.startswith("checkpoint c.pt was made for camera [width=32 height=32 ")
    assert (
        "the agent camera is [width=64 height=64 " in text
        and "differ in width, height" in text
        and text.endswith("retrain it")
    )
    for record in (None, {"width": 64}, {**CAMERA_64, "colour": "red"}, "64x64"):  # missing, incomplete, unknown keys
        with pytest.raises(CameraMismatchError, match="camera record is missing, incomplete or unreadable"):
            check_camera(record, AGENT_CAMERA, source="c", expected_name="e", fix="f")


@pytest.fixture(scope="module")
def small_checkpoint(tmp_path_factory):
    """A tiny perception network trained (untrained, really) on 32x32 frames."""
    import torch

    from objsearch.perception.inference import save_checkpoint
    from objsearch.perception.model import ModelConfig, SegDepthNet
    from objsearch.perception.train import init_weights

    model = SegDepthNet(ModelConfig(stem=8, mid=8, deep=8, aspp=8, aspp_rates=(2,), skip=8, decoder=8))
    init_weights(model, torch.Generator().manual_seed(0))
    path = tmp_path_factory.mktemp("small-camera") / "small.pt"
    save_checkpoint(path, model, RenderSettings(width=32, height=32))
    return path


def test_a_checkpoints_camera_is_checked_without_building_the_network(small_checkpoint):
    from objsearch.perception.inference import check_checkpoint_camera

    small = RenderSettings(width=32, height=32)
    assert check_checkpoint_camera(small_checkpoint, small, "a 32x32 camera") == small
    with pytest.raises(CameraMismatchError) as err:
        check_checkpoint_camera(small_checkpoint)  # against the agent camera
    _assert_camera_error(str(err.value), small_checkpoint)


def _assert_camera_error(text: str, checkpoint) -> None:
    assert f"perception checkpoint {checkpoint} was made for camera [width=32 height=32 " in text, text
    assert "the agent camera (objsearch.sim.camera.AGENT_CAMERA) is [width=64 height=64 " in text, text
    assert "objsearch perception train" in text, text  # the fix


def test_eval_with_a_perception_checkpoint_of_another_camera_exits_2(small_checkpoint, cache_dir, capsys):
    from objsearch.cli import main

    code = main(
        [
            "eval",
            "--agent",
            "random",
            "--suite",
            "house-single",
            "--seeds",
            "1",
            "--cache-dir",
            cache_dir,
            "--observation",
            "predicted",
            "--perception",
            str(small_checkpoint),
            "--quiet",
        ]
    )
    assert code == 2
    _assert_camera_error(capsys.readouterr().err, small_checkpoint)


def test_cache_build_with_a_perception_checkpoint_of_another_camera_exits_2(small_checkpoint, tmp_path, capsys):
    from objsearch.cli import main

    empty = tmp_path / "cache"
    code = main(
        [
            "cache",
            "build",
            "--suite",
            "house-single",
            "--cache-dir",
            str(empty),
            "--observation",
            "predicted",
            "--perception",
            str(small_checkpoint),
        ]
    )
    assert code == 2
    _assert_camera_error(capsys.readouterr().err, small_checkpoint)
    assert not empty.exists() or not any(empty.iterdir())  # refused before any house was rendered


def test_a_checkpoint_with_an_incomplete_camera_record_is_refused(small_checkpoint, tmp_path):
    """A missing field would take today's default, which need not be the training camera: refused."""
    from objsearch import torchfile
    from objsearch.perception.inference import check_checkpoint_camera, load_checkpoint

    state = load_checkpoint(small_checkpoint)
    del state["settings"]["ceiling"]
    torchfile.save(tmp_path / "old.pt", state)
    with pytest.raises(
        UserError, match=r"old.pt records no readable camera settings \(missing camera fields ceiling\)"
    ):
        check_checkpoint_camera(tmp_path / "old.pt", RenderSettings(width=32, height=32))
    state["settings"] = {**RenderSettings(width=32, height=32).to_json(), "colour": "red"}
    torchfile.save(tmp_path / "odd.pt", state)
    with pytest.raises(UserError, match=r"records no readable camera settings \(.*unknown key 'colour'"):
        check_checkpoint_camera(tmp_path / "odd.pt", RenderSettings(width=32, height=32))


def test_perception_predictions_of_another_camera_are_refused_by_the_cache(small_checkpoint, small_world, tmp_path):
    """The backstop under every entry point: a predicted cache pairs a network with a camera."""
    from objsearch.perception.inference import Predictor
    from objsearch.sim.cache import PredictedCache

    predictor = Predictor.from_checkpoint(small_checkpoint, device="cpu")
    with pytest.raises(
        CameraMismatchError, match=r"the agent camera \(objsearch.sim.camera.AGENT_CAMERA\) is \[width=64 "
    ):
        PredictedCache.open(small_world, AGENT_CAMERA, predictor, tmp_path, progress=False)
    with pytest.raises(CameraMismatchError, match=r"the camera of these observations \(cache key \w+\) is \[width=16 "):
        PredictedCache.open(small_world, RenderSettings(width=16, height=16), predictor, tmp_path, progress=False)
    assert not any(tmp_path.iterdir())  # refused before anything was rendered
