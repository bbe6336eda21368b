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
from objsearch.fileio import MARKER_TEXT, TEMP_MARKER
from objsearch.sim.cache import HouseCache, depth_to_mm, quantize_depth
from objsearch.sim.cache_folder import check_folder
from objsearch.sim.camera import RenderSettings
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


def _reheader(path):  # same size, another dtype: float16 where uint16 was
    data = path.read_bytes()
    path.write_bytes(data.replace(b"'<u2'", b"'<f2'", 1))


@pytest.mark.parametrize(
    "damage, layer",
    [(_flip, "semantic"), (_zero, "rgb"), (_truncate, "depth"), (lambda p: p.unlink(), "rgb"), (_reheader, "depth")],
)
def test_damaged_cache_is_detected_and_rebuilt(small_world, built, damage, layer, capsys):
    root, arrays = built
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    damage(cache.directory / f"{layer}.npy")
    problem = check_folder(cache.directory)
    assert problem is not None and f"{layer}.npy" in problem
    _reopen_equal(small_world, root, arrays)
    assert "rebuilding" in capsys.readouterr().err


def test_depth_is_stored_in_millimetres_and_reads_bit_identical(small_world, built):
    root, arrays = built
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    assert np.load(cache.directory / "depth.npy", mmap_mode="r").dtype == np.uint16
    poses = np.array([0, 5, len(arrays["depth"]) - 1])
    with HouseRenderer(small_world.model, SMALL) as renderer:
        live = quantize_depth(renderer.render(small_world.graph.world_poses()[poses]).depth)
    got = cache.depth[poses]
    assert got.dtype == np.float32 and np.array_equal(got, live)
    assert np.array_equal(cache.depth[int(poses[1])], live[1]) and (cache.depth <= 1.0).shape == cache.depth.shape
    # every millimetre value comes back as quantize_depth gives it, bit for bit
    metres = quantize_depth(np.arange(65536, dtype=np.float64) / 1000 + 0.0002)
    from objsearch.sim.cache import MillimetreDepth

    assert np.array_equal(MillimetreDepth(depth_to_mm(metres))[:], metres)
    with pytest.raises(ValueError, match="65.535"):
        depth_to_mm(np.array([70.0], np.float32))


def test_cache_commands(small_world, tmp_path, capsys):
    root = tmp_path / "caches"
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    assert f"cache {small_world.house_id}: " in capsys.readouterr().err, "a build says where and how big"
    (root / "train_999999-0123456789abcdef").mkdir()  # an old cache: no meta.json
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    abandoned = root / f".{cache.directory.name}.{socket.gethostname()}.{dead.pid}.abcd1234.tmp"
    abandoned.mkdir()
    (abandoned / TEMP_MARKER).write_text(MARKER_TEXT + "a killed build\n")  # as atomic_directory marks it
    (abandoned / "rgb.npy").write_bytes(b"x" * 100)

    assert main(["cache", "list", "--cache-dir", str(root)]) == 0
    out = capsys.readouterr().out
    assert f"{small_world.house_id}" in out and "obs" in out and "current" in out
    assert "not current: no meta.json" in out and "interrupted build" in out

    assert main(["cache", "verify", "--cache-dir", str(root)]) == 2
    assert "objsearch cache clear" in capsys.readouterr().err
    _flip(cache.directory / "semantic.npy")
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
