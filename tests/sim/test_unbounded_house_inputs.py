"""Bounded work on house inputs: a house folder whose MJCF includes a FIFO (or names a device)
and a suite file far above any objsearch makes are refused at once, naming the file and the
limit, instead of hanging or reading for minutes."""

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from objsearch.errors import UserError
from objsearch.house.generate import generate_house, write_house
from objsearch.sim.suites import SUITE_FILE_MAX_BYTES, load_suite_file
from objsearch.sim.world import HouseRef, World

BIN = Path(sys.executable).parent


@pytest.fixture(scope="module")
def house_folder(tmp_path_factory):
    return write_house(generate_house(0, validate=False), tmp_path_factory.mktemp("houses"), preview=False)


@pytest.fixture
def no_hang():
    """Fail (SIGALRM) instead of hanging past 60 s."""

    def hung(*_):
        raise TimeoutError("hung")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(60)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def with_include(house_folder, tmp_path, what: str) -> Path:
    """A copy of ``house_folder`` whose house.xml includes ``evil.xml``, made by ``what``."""
    folder = tmp_path / "house"
    shutil.copytree(house_folder, folder)
    xml = (folder / "house.xml").read_text()
    (folder / "house.xml").write_text(xml.replace("<worldbody>", '<include file="evil.xml"/><worldbody>', 1))
    if what == "fifo":
        os.mkfifo(folder / "evil.xml")
    else:
        (folder / "evil.xml").symlink_to(what)
    return folder


def test_a_house_folder_loads(house_folder):
    assert World.load(HouseRef(path=str(house_folder))).model.nbody > 1


@pytest.mark.parametrize("what, kind", [("fifo", "FIFO .named pipe."), ("/dev/zero", "character device")])
def test_an_mjcf_include_of_a_fifo_or_device_is_refused_at_once(house_folder, tmp_path, no_hang, what, kind):
    folder = with_include(house_folder, tmp_path, what)
    with pytest.raises(UserError, match=f"house file {folder / 'evil.xml'} is a {kind}, not a regular file"):
        World.load(HouseRef(path=str(folder)))


def test_a_mesh_that_is_a_fifo_and_a_spec_that_is_a_device_are_refused(house_folder, tmp_path, no_hang):
    folder = tmp_path / "house"
    shutil.copytree(house_folder, folder)
    mesh = next((folder / "meshes").rglob("*.obj"))
    mesh.unlink()
    os.mkfifo(mesh)
    with pytest.raises(UserError, match=f"house file {mesh} is a FIFO"):
        World.load(HouseRef(path=str(folder)))
    (folder / "spec.json").unlink()
    (folder / "spec.json").symlink_to("/dev/zero")
    with pytest.raises(UserError, match="spec.json is a character device"):
        World.load(HouseRef(path=str(folder)))


def test_suite_make_on_a_house_that_includes_a_fifo_exits_2_at_once(house_folder, tmp_path):
    folder = with_include(house_folder, tmp_path, "fifo")
    out = subprocess.run(
        [str(BIN / "objsearch"), "suite", "make", "--houses", str(folder.parent), "--out", str(tmp_path / "s.json")],
        capture_output=True, text=True, timeout=120, env={**os.environ, "OBJSEARCH_CACHE": str(tmp_path / "cache")},
    )  # fmt: skip
    assert out.returncode == 2, out.stderr
    assert "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1
    assert "evil.xml is a FIFO (named pipe), not a regular file" in out.stderr
    assert not (tmp_path / "s.json").exists()


def test_a_suite_file_above_the_limit_is_refused_naming_it(tmp_path):
    big = tmp_path / "big.json"
    with open(big, "wb") as f:  # the 91 MB, sparse: no disk used
        f.truncate(91_000_000)
    with pytest.raises(UserError, match=r"suite file .*big.json is 91.0 MB, above the limit of 64.0 MB"):
        load_suite_file(str(big))
    out = subprocess.run(
        [str(BIN / "objsearch-eval"), "--agent", "random", "--suite", str(big)],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert out.returncode == 2 and "Traceback" not in out.stderr, out.stderr
    assert len(out.stderr.strip().splitlines()) == 1 and "above the limit of" in out.stderr
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    with pytest.raises(UserError, match=r"suite file .*fifo.json is a FIFO \(named pipe\), not a regular file"):
        load_suite_file(str(fifo))


def test_every_shipped_suite_file_is_far_below_the_limit():
    data = Path(__file__).resolve().parents[2] / "objsearch" / "sim" / "data"
    assert max(p.stat().st_size for p in data.glob("*.json")) * 16 < SUITE_FILE_MAX_BYTES
