"""A cache file whose ``.npy`` header has one flipped byte: opening the cache (evaluations,
``objsearch cache build``) rebuilds it instead of failing with whatever numpy's header parser
raises, and ``objsearch cache list`` never calls it current."""

import numpy as np
import pytest

from objsearch.cli import main
from objsearch.sim.cache import HouseCache, cache_folders
from objsearch.sim.cache_folder import check_folder, header_problem
from objsearch.sim.camera import RenderSettings

SMALL = RenderSettings(width=16, height=16)


@pytest.fixture(scope="module")
def built(small_world, tmp_path_factory):
    root = tmp_path_factory.mktemp("caches")
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    return root, {name: np.array(getattr(cache, name)) for name in ("rgb", "depth", "semantic")}


def flip(path, offset, mask=0xFF):
    data = bytearray(path.read_bytes())
    data[offset] ^= mask
    path.write_bytes(bytes(data))


# 10: the header's "{" (numpy's parser raised tokenize.TokenError: a traceback); 9: its length;
# 31: inside 'descr'; "shape": a digit of the shape; -2: the padding
@pytest.mark.parametrize("offset", [10, 9, 31, "shape", -2])
def test_a_flipped_header_byte_is_rebuilt_not_a_traceback(small_world, built, offset, capsys):
    root, arrays = built
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    path = cache.directory / "frames.npy"
    header = path.read_bytes()[: path.read_bytes().index(b"\n") + 1]
    if offset == "shape":
        offset = header.index(b"'shape': (") + len(b"'shape': (")
    flip(path, offset % len(header))
    problem = check_folder(cache.directory)
    assert problem is not None and "frames.npy has a damaged .npy header" in problem
    assert header_problem(path) is not None or offset == 31  # parsed alone, some flips still read
    capsys.readouterr()
    reopened = HouseCache.open(small_world, SMALL, root, progress=False)
    err = capsys.readouterr().err
    assert "frames.npy has a damaged .npy header" in err and "rebuilding" in err
    assert check_folder(reopened.directory) is None
    for name, value in arrays.items():
        assert np.array_equal(np.asarray(getattr(reopened, name)), value), name


def test_cache_list_calls_no_cache_with_a_flipped_header_bit_current(small_world, built, capsys):
    root, _ = built
    cache = HouseCache.open(small_world, SMALL, root, progress=False)
    path = cache.directory / "frames.npy"
    good = path.read_bytes()
    header_end = good.index(b"\n")
    try:
        for offset in range(header_end + 1):  # every bit of the header, '<f4' -> '<i4' (same size) among them
            for bit in range(8):
                flip(path, offset, 1 << bit)
                (listed,) = cache_folders(root)
                assert listed["problem"] is not None, (offset, bit)
                path.write_bytes(good)
        flip(path, 10)
        assert main(["cache", "list", "--cache-dir", str(root)]) == 0
        out = capsys.readouterr().out
        assert "not current: frames.npy has a damaged .npy header" in out and "  current  " not in out
    finally:
        path.write_bytes(good)
    assert main(["cache", "list", "--cache-dir", str(root)]) == 0
    assert "  current  " in capsys.readouterr().out
