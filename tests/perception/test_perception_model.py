import dataclasses

import numpy as np
import pytest
import torch

from objsearch.errors import UserError
from objsearch.house.categories import CATEGORY_IDS, CATEGORY_NAMES, FIRST_OBJECT_ID, STRUCTURE
from objsearch.perception.inference import Predictor, checkpoint_key, load_checkpoint, save_checkpoint
from objsearch.perception.model import NUM_CLASSES, ModelConfig, SegDepthNet, count_parameters, depth_from_log
from objsearch.perception.train import init_weights
from objsearch.sim.camera import RenderSettings
from objsearch.sim.env import NUM_CATEGORY_IDS

TINY_MODEL = ModelConfig(stem=16, mid=32, deep=48, aspp=32, aspp_rates=(2, 4), skip=16, decoder=32)  # trains in seconds


def test_one_segmentation_channel_per_category_id():
    assert NUM_CLASSES == max(CATEGORY_IDS.values()) + 1 == NUM_CATEGORY_IDS
    assert all(0 <= i < NUM_CLASSES for i in CATEGORY_IDS.values())
    assert (
        STRUCTURE["background"] == 0
        and min(i for n, i in CATEGORY_IDS.items() if n not in STRUCTURE) == FIRST_OBJECT_ID
    )
    assert SegDepthNet(TINY_MODEL).seg_head.out_channels == 4 * NUM_CLASSES  # before the 2x2 pixel shuffle
    with pytest.raises(UserError, match="category table"):
        ModelConfig(num_classes=NUM_CLASSES - 1)


@pytest.mark.parametrize("separable", [False, True])
@pytest.mark.parametrize("size", [(32, 32), (64, 64), (48, 80)])
def test_output_shapes(size, separable):
    model = SegDepthNet(dataclasses.replace(TINY_MODEL, separable=separable)).eval()
    logits, log_depth = model(torch.rand(2, 3, *size))
    assert logits.shape == (2, NUM_CLASSES, *size) and log_depth.shape == (2, *size)
    with pytest.raises(ValueError, match="multiple of 8"):
        model(torch.rand(1, 3, 30, 32))


def test_predicted_labels_are_category_ids_and_depth_is_in_range(tmp_path):
    model = SegDepthNet(TINY_MODEL)
    init_weights(model, torch.Generator().manual_seed(0))
    sofa = CATEGORY_IDS["sofa"]
    with torch.no_grad():  # make channel `sofa` win everywhere: channel index == category id
        model.seg_head.bias.zero_()
        model.seg_head.bias[4 * sofa : 4 * sofa + 4] = 100.0  # pixel shuffle: channel c*4+k -> class c
    predictor = Predictor(model, RenderSettings(width=32, height=32), key="k", device="cpu")
    rgb = np.random.default_rng(0).integers(0, 256, (3, 32, 32, 3), dtype=np.uint8)
    semantic, depth = predictor.predict(rgb)
    assert semantic.dtype == np.uint8 and semantic.shape == (3, 32, 32) and (semantic == sofa).all()
    assert CATEGORY_NAMES[int(semantic[0, 0, 0])] == "sofa"
    assert depth.dtype == np.float32 and depth.shape == (3, 32, 32) and (depth >= 0.05).all() and (depth <= 30.0).all()
    assert torch.allclose(depth_from_log(torch.tensor([-10.0, 10.0]), 0.05, 30.0), torch.tensor([0.05, 30.0]))


def test_separable_convolutions_are_depthwise_and_need_a_boolean():
    plain, separable = SegDepthNet(TINY_MODEL), SegDepthNet(dataclasses.replace(TINY_MODEL, separable=True))
    depthwise = [m for m in separable.modules() if isinstance(m, torch.nn.Conv2d) and m.groups > 1]
    assert depthwise and all(m.groups == m.in_channels == m.out_channels for m in depthwise)
    assert not any(isinstance(m, torch.nn.Conv2d) and m.groups > 1 for m in plain.modules())
    assert count_parameters(separable) < count_parameters(plain) / 2
    assert ModelConfig.from_json(TINY_MODEL.to_json() | {"separable": False}) == TINY_MODEL
    with pytest.raises(UserError, match="separable must be true or false"):
        dataclasses.replace(TINY_MODEL, separable=1)


def test_predict_labels_is_the_argmax_of_forward_exactly():
    """The inference path (argmax before the pixel shuffle) gives forward's ids and depth bit
    for bit, ties included: the predicted caches and the leaderboard's replays rely on it."""
    model = SegDepthNet(TINY_MODEL).eval()
    init_weights(model, torch.Generator().manual_seed(1))
    x = torch.rand(3, 3, 48, 80, generator=torch.Generator().manual_seed(2))
    with torch.no_grad():
        logits, log_depth = model(x)
        labels, log_depth2 = model.predict_labels(x)
        assert torch.equal(labels, logits.argmax(dim=1)) and torch.equal(log_depth, log_depth2)
        assert len(labels.unique()) > 5  # not one class everywhere: the layout is exercised
        model.seg_head.weight.zero_()
        model.seg_head.bias.zero_()  # every class ties at every pixel: both take the first, id 0
        assert not model.predict_labels(x)[0].any() and not model(x)[0].argmax(dim=1).any()


FAST_TINY = dataclasses.replace(TINY_MODEL, decoder_stride=4, separable=True)  # the fast layout


@pytest.mark.parametrize("batch", [1, 3])
@pytest.mark.parametrize("size", [(32, 32), (64, 64), (48, 80)])
def test_decoder_stride_4_shapes_and_predict_labels_is_the_argmax_of_forward(size, batch):
    """Skip, decoder and heads at 1/4, pixel shuffle x4, the segmentation head one frame at a
    time: full-resolution outputs, and predict_labels gives forward's ids and depth bit for bit."""
    model = SegDepthNet(FAST_TINY).eval()
    init_weights(model, torch.Generator().manual_seed(1))
    assert model.seg_head.out_channels == 16 * NUM_CLASSES and model.depth_head.out_channels == 16
    x = torch.rand(batch, 3, *size, generator=torch.Generator().manual_seed(2))
    with torch.no_grad():
        logits, log_depth = model(x)
        assert logits.shape == (batch, NUM_CLASSES, *size) and log_depth.shape == (batch, *size)
        labels, log_depth2 = model.predict_labels(x)
        assert torch.equal(labels, logits.argmax(dim=1)) and torch.equal(log_depth, log_depth2)
        assert len(labels.unique()) > 5
    with pytest.raises(ValueError, match="multiple of 8"):
        model(torch.rand(1, 3, 30, 32))


def test_decoder_stride_4_pixel_layout_and_ties():
    """Channel c * 16 + 4 * i + j is class c at pixel (4y + i, 4x + j), in both paths; at a tie
    both take the first class."""
    model = SegDepthNet(FAST_TINY).eval()
    init_weights(model, torch.Generator().manual_seed(0))
    sofa = CATEGORY_IDS["sofa"]
    x = torch.rand(2, 3, 32, 48, generator=torch.Generator().manual_seed(3))
    with torch.no_grad():
        model.seg_head.weight.zero_()
        model.seg_head.bias.zero_()  # every class ties everywhere: id 0
        assert not model.predict_labels(x)[0].any() and not model(x)[0].argmax(dim=1).any()
        model.seg_head.bias[16 * sofa + 4 * 1 + 2] = 1.0  # sofa at sub-pixel (1, 2) of every 4 x 4 block
        expected = torch.zeros(2, 32, 48, dtype=torch.long)
        expected[:, 1::4, 2::4] = sofa
        assert torch.equal(model.predict_labels(x)[0], expected) and torch.equal(model(x)[0].argmax(dim=1), expected)


def test_decoder_stride_is_2_or_4_and_defaults_to_the_shipped_layout():
    assert ModelConfig().decoder_stride == 2  # the shipped network
    data = FAST_TINY.to_json()
    del data["decoder_stride"]  # a checkpoint written before the field
    assert ModelConfig.from_json(data).decoder_stride == 2
    plain = SegDepthNet(TINY_MODEL)
    assert plain.seg_head.out_channels == 4 * NUM_CLASSES and plain.layer1.conv1.stride == (1, 1)
    assert SegDepthNet(FAST_TINY).layer1.conv1[0].stride == (2, 2)  # separable: the depthwise conv strides
    with pytest.raises(UserError, match="decoder_stride must be 2 or 4"):
        dataclasses.replace(TINY_MODEL, decoder_stride=8)


def test_checkpoint_round_trip_and_key(tmp_path):
    model = SegDepthNet(TINY_MODEL)
    init_weights(model, torch.Generator().manual_seed(1))
    camera = RenderSettings(width=32, height=32)
    save_checkpoint(tmp_path / "model.pt", model, camera)
    predictor = Predictor.from_checkpoint(tmp_path / "model.pt", device="cpu")
    assert predictor.model.config == TINY_MODEL
    assert predictor.settings == camera and predictor.checkpoint == str(
        tmp_path / "model.pt"
    )  # a RenderSettings, not a dict
    assert load_checkpoint(tmp_path / "model.pt")["settings"] == camera.to_json()  # what the file holds: plain data
    assert predictor.key == checkpoint_key(load_checkpoint(tmp_path / "model.pt"))
    with torch.no_grad():
        model.depth_head.bias += 1.0
    save_checkpoint(tmp_path / "other.pt", model, camera)
    assert Predictor.from_checkpoint(tmp_path / "other.pt").key != predictor.key  # new weights, new key
    (tmp_path / "bad.pt").write_bytes(b"not a checkpoint")
    with pytest.raises(UserError, match="bad.pt"):
        load_checkpoint(tmp_path / "bad.pt")


def test_seeded_initialisation_is_reproducible():
    a, b = SegDepthNet(TINY_MODEL), SegDepthNet(TINY_MODEL)
    init_weights(a, torch.Generator().manual_seed(5))
    init_weights(b, torch.Generator().manual_seed(5))
    assert all(torch.equal(x, y) for x, y in zip(a.state_dict().values(), b.state_dict().values()))
