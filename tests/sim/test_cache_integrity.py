"""Damaged, interrupted and concurrent observation caches (objsearch.sim.cache)."""

import json
import os
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from objsearch.cli import main
from objsearch.digests import sha256_file
from objsearch.fileio import MARKER_TEXT, TEMP_MARKER
from objsearch.sim.cache import (
    PREVIOUS_CACHE_VERSION,
    PREVIOUS_PREDICTED_VERSION,
    HouseCache,
    PredictedCache,
    _Previous,
    cache_key,
    quantize_depth,
)
from objsearch.sim.cache_folder import check_folder
from objsearch.sim.camera import RenderSettings
from objsearch.sim.navgraph import NAVGRAPH_VERSION
from objsearch.sim.renderer import HouseRenderer

SMALL = RenderSettings(width=16, height=16)


@pytest.fixture(scope="module")
def built(small_world, tmp_path_factory):
    """A small cache and copies of its arrays, to compare rebuilt ones with."""
    root = tmp_path_factory.mktemp("caches")
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    return root, {name: np.array(getattr(cache, name)) for name in ("rgb", "depth", "semantic")}


def _reopen_equal(world, root, arrays):
    cache = HouseCache.open(world, SMALL, root, progress=False)
    assert check_folder(cache.directory) is None
    for name, value in arrays.items():
        assert np.array_equal(np.asarray(getattr(cache, name)), value), name
    return cache


def _flip(path, offset=-100):
    data = bytearray(path.read_bytes())
    data[offset] ^= 0xFF
    path.write_bytes(bytes(data))


def _zero(path):
    header = path.read_bytes()[:128]
    path.write_bytes(header + bytes(path.stat().st_size - 128))


def _truncate(path):
    path.write_bytes(path.read_bytes()[:1000])


def _reheader(path):  # same size, another dtype: int32 where float32 depth was
    data = path.read_bytes()
    path.write_bytes(data.replace(b"'<f4'", b"'<i4'", 1))


@pytest.mark.parametrize("damage", [_flip, _zero, _truncate, lambda p: p.unlink(), _reheader])
def test_damaged_cache_is_detected_and_rebuilt(small_world, built, damage, capsys):
    root, arrays = built
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    damage(cache.directory / "frames.npy")
    problem = check_folder(cache.directory)
    assert problem is not None and "frames.npy" in problem
    _reopen_equal(small_world, root, arrays)
    assert "rebuilding" in capsys.readouterr().err


def test_depth_is_stored_as_the_metres_the_env_gives(small_world, built):
    root, arrays = built
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    assert np.load(cache.directory / "frames.npy", mmap_mode="r").dtype["depth"].base == np.float32
    poses = np.array([0, 5, len(arrays["depth"]) - 1])
    with HouseRenderer(small_world.model, SMALL) as renderer:
        live = quantize_depth(renderer.render(small_world.graph.world_poses()[poses]).depth)
    got = cache.depth[poses]
    assert got.dtype == np.float32 and np.array_equal(got, live)


def _write_v2(folder, expected: dict, layers: dict) -> None:
    """A cache-v2 folder as that version wrote it: a .npy file a layer, depth in uint16 millimetres."""
    folder.mkdir(parents=True)
    for name, value in layers.items():
        np.save(folder / f"{name}.npy", value)
    files = {
        f"{n}.npy": {"bytes": (folder / f"{n}.npy").stat().st_size, "sha256": sha256_file(folder / f"{n}.npy")}
        for n in layers
    }
    (folder / "meta.json").write_text(json.dumps({**expected, "files": files}))


class _Predictor:  # stands for the network: the conversion must not call it
    key = "stubpredictor"

    def predict(self, rgb):
        raise AssertionError("a converted cache is not predicted again")


def test_a_cache_v2_folder_is_converted_not_rendered_again(small_world, built, tmp_path, monkeypatch, capsys):
    _, arrays = built
    old_key = cache_key(small_world, SMALL, PREVIOUS_CACHE_VERSION)
    mm = np.rint(arrays["depth"] * 1000).astype(np.uint16)
    old = tmp_path / f"{small_world.house_id}-{old_key}"
    common = {"house_id": small_world.house_id, "settings": SMALL.to_json(), "num_poses": len(mm)}
    gt = {"version": PREVIOUS_CACHE_VERSION, "key": old_key, "spec_sha256": small_world.spec_sha256}
    _write_v2(
        old,
        {**gt, "navgraph": NAVGRAPH_VERSION, **common},
        {"rgb": arrays["rgb"], "depth": mm, "semantic": arrays["semantic"]},
    )
    pred = {"version": PREVIOUS_PREDICTED_VERSION, "observations": old_key, "predictor": _Predictor.key}
    (old / "tables-v1.npz").write_bytes(b"kept beside the cache by an agent")
    (old / "mydir" / "deeper").mkdir(parents=True)  # a folder in it: moved, never deleted
    (old / "mydir" / "deeper" / "precious.txt").write_text("years of work")
    semantic = (arrays["semantic"] + 1).astype(np.uint8)
    _write_v2(
        tmp_path / f"{old.name}-pred-{_Predictor.key}", {**pred, **common}, {"depth": mm // 2, "semantic": semantic}
    )

    def no_rendering(*args, **kwargs):
        raise AssertionError("a converted cache is not rendered again")

    monkeypatch.setattr("objsearch.sim.cache.HouseRenderer", no_rendering)
    cache = PredictedCache.open(small_world, SMALL, _Predictor(), tmp_path, progress=False)
    house = HouseCache.open(small_world, SMALL, tmp_path, progress=False)
    for name, value in arrays.items():  # the same bits as a cache rendered now
        assert np.asarray(getattr(house, name)).tobytes() == value.tobytes(), name
    assert np.array_equal(cache.semantic, semantic) and np.array_equal(cache.depth, quantize_depth((mm // 2) / 1000))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([house.directory.name, cache.directory.name])
    assert (house.directory / "tables-v1.npz").read_bytes() == b"kept beside the cache by an agent"
    assert (house.directory / "mydir" / "deeper" / "precious.txt").read_text() == "years of work"
    err = capsys.readouterr().err
    assert err.count("converting") == 2 and err.count("removed") == 2


def test_a_linked_cache_v2_folder_is_converted_and_left_where_it_is(small_world, built, tmp_path, capsys):
    _, arrays = built
    old_key = cache_key(small_world, SMALL, PREVIOUS_CACHE_VERSION)
    elsewhere = tmp_path / "disk2" / "v2-cache"
    meta = {"version": PREVIOUS_CACHE_VERSION, "key": old_key, "spec_sha256": small_world.spec_sha256}
    meta |= {"navgraph": NAVGRAPH_VERSION, "house_id": small_world.house_id, "settings": SMALL.to_json()}
    mm = np.rint(arrays["depth"] * 1000).astype(np.uint16)
    _write_v2(
        elsewhere, {**meta, "num_poses": len(mm)}, {"rgb": arrays["rgb"], "depth": mm, "semantic": arrays["semantic"]}
    )
    (elsewhere / "notes.txt").write_text("beside the v2 cache")
    root = tmp_path / "caches"
    root.mkdir()
    (root / f"{small_world.house_id}-{old_key}").symlink_to(elsewhere)
    house = HouseCache.open(small_world, SMALL, root, progress=False)
    assert np.asarray(house.rgb).tobytes() == arrays["rgb"].tobytes()
    err = capsys.readouterr().err
    assert "converting" in err and "removed" not in err and "a link" in err
    assert (root / f"{small_world.house_id}-{old_key}").is_symlink(), "a link is never followed to delete"
    assert sorted(p.name for p in elsewhere.iterdir()) == [
        "depth.npy",
        "meta.json",
        "notes.txt",
        "rgb.npy",
        "semantic.npy",
    ]
    assert main(["cache", "clear", "--cache-dir", str(root)]) == 0  # the old version, through a link: left, said so
    out = capsys.readouterr().out
    assert "removed 0 caches" in out and "left 1 link to a cache" in out and (elsewhere / "notes.txt").is_file()


def test_a_cache_v2_folder_keeps_what_the_new_cache_has_already(small_world, built, tmp_path, capsys):
    _, arrays = built
    house = HouseCache.open(small_world, SMALL, tmp_path, progress=False)  # a current cache is there
    (house.directory / "notes.txt").write_text("the new cache's")
    old_key = cache_key(small_world, SMALL, PREVIOUS_CACHE_VERSION)
    meta = {"version": PREVIOUS_CACHE_VERSION, "key": old_key, "spec_sha256": small_world.spec_sha256}
    meta |= {"navgraph": NAVGRAPH_VERSION, "house_id": small_world.house_id, "settings": SMALL.to_json()}
    mm = np.rint(arrays["depth"] * 1000).astype(np.uint16)
    old = tmp_path / f"{small_world.house_id}-{old_key}"
    _write_v2(old, {**meta, "num_poses": len(mm)}, {"rgb": arrays["rgb"], "depth": mm, "semantic": arrays["semantic"]})
    (old / "notes.txt").write_text("the old cache's")
    (old / "mine.txt").write_text("moved")
    previous = _Previous(old, {**meta, "num_poses": len(mm)}, ("rgb", "semantic", "depth"), 16, 16)
    previous.used = True  # as if the new cache had been filled from it
    previous.remove(house.directory)
    assert (house.directory / "notes.txt").read_text() == "the new cache's"
    assert (house.directory / "mine.txt").read_text() == "moved"
    assert sorted(p.name for p in old.iterdir()) == ["notes.txt"], "only its own files are deleted"
    assert (old / "notes.txt").read_text() == "the old cache's"
    assert "left" in capsys.readouterr().err


def test_cache_commands(small_world, tmp_path, capsys):
    root = tmp_path / "caches"
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    assert f"cache {small_world.house_id}: " in capsys.readouterr().err, "a build says where and how big"
    old = root / "train_999999-0123456789abcdef"  # a cache of an old version
    old.mkdir()
    (old / "meta.json").write_text(json.dumps({"version": "cache-v1", "house_id": "train_999999"}))
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    abandoned = root / f".{cache.directory.name}.{socket.gethostname()}.{dead.pid}.abcd1234.tmp"
    abandoned.mkdir()
    (abandoned / TEMP_MARKER).write_text(MARKER_TEXT + "a killed build\n")  # as atomic_directory marks it
    (abandoned / "rgb.npy").write_bytes(b"x" * 100)

    assert main(["cache", "list", "--cache-dir", str(root)]) == 0
    out = capsys.readouterr().out
    assert f"{small_world.house_id}" in out and "obs" in out and "current" in out
    assert "not current: old version cache-v1" in out and "interrupted build" in out

    assert main(["cache", "verify", "--cache-dir", str(root)]) == 2
    assert "objsearch cache clear" in capsys.readouterr().err
    _flip(cache.directory / "frames.npy")
    main(["cache", "verify", "--cache-dir", str(root)])
    assert "sha256 mismatch" in capsys.readouterr().out

    assert main(["cache", "clear", "--cache-dir", str(root)]) == 0  # the not current ones and temp folders
    assert list(root.iterdir()) == []
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    assert main(["cache", "verify", "--cache-dir", str(root)]) == 0
    assert main(["cache", "clear", "--cache-dir", str(root)]) == 0 and cache.directory.is_dir()
    assert "--all removes them too" in capsys.readouterr().out
    assert main(["cache", "clear", "--cache-dir", str(root), "--house", small_world.house_id]) == 0
    assert not cache.directory.exists()


def test_a_build_removes_temp_folders_of_killed_builds(small_world, tmp_path):
    old = tmp_path / ".train_000001-0123.oldstyle.tmp"  # another host's (or pid-less): by age
    recent = tmp_path / ".train_000001-0123.otherhost.12.abcd.tmp"
    running = tmp_path / f".train_000001-0123.{socket.gethostname()}.{os.getpid()}.abcd.tmp"
    unmarked = tmp_path / ".mine.tmp"  # a user's folder with a temp folder's name: no marker, never removed
    for folder in (old, recent, running, unmarked):
        folder.mkdir()
        if folder != unmarked:
            (folder / TEMP_MARKER).write_text(MARKER_TEXT + "a killed build\n")
    for folder in (old, unmarked):
        for p in [*folder.iterdir(), folder]:
            os.utime(p, (time.time() - 2 * 86400,) * 2)
    HouseCache.open(small_world, SMALL, tmp_path, progress=False)
    assert not old.exists() and recent.exists() and running.exists() and unmarked.exists()


BUILD = """
import sys
from objsearch.sim.cache import HouseCache
from objsearch.sim.camera import RenderSettings
from objsearch.sim.world import HouseRef, World
HouseCache.open(World.load(HouseRef(seed=3)), RenderSettings(width=16, height=16), sys.argv[1], progress=False)
"""


def test_concurrent_builds_of_one_cache(small_world, tmp_path):
    env = {**os.environ, "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    builders = [
        subprocess.Popen([sys.executable, "-c", BUILD, str(tmp_path)], env=env, stderr=subprocess.PIPE, text=True)
        for _ in range(3)
    ]
    errors = [b.communicate()[1] for b in builders]
    assert [b.returncode for b in builders] == [0, 0, 0], errors
    assert sum("cache train_" in e for e in errors) == 1, "built once, the others waited for it"
    cache = HouseCache.open(small_world, SMALL, tmp_path, progress=False)
    assert check_folder(cache.directory) is None
    assert json.loads((cache.directory / "meta.json").read_text())["files"]
    assert [p.name for p in tmp_path.iterdir()] == [cache.directory.name], "no temp folder or lock file left"
