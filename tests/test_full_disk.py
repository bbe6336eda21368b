"""A full disk: every write either succeeds or leaves the previous file in place, and the
command ends with one line naming the path, the space and the fix (exit 2), never a
traceback or a SIGBUS. On a real full filesystem: a small tmpfs, skipped where this process
cannot mount one."""

import json
import shutil
import subprocess
import uuid
from pathlib import Path

import pytest

from objsearch.cli import main
from objsearch.errors import UserError
from objsearch.fileio import atomic_write


@pytest.fixture
def small_disk(tmp_path):
    """A 256 KiB tmpfs; yields a function that fills it up to ``free`` bytes left."""
    disk = tmp_path / "disk"
    disk.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", str(disk)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here ({mounted.stderr.decode().strip() or 'not permitted'})")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "-l", str(disk)], check=False)


def fill(disk: Path, leave: int = 0) -> None:
    """Fill ``disk`` until at most ``leave`` bytes are free."""
    with open(disk / f"filler-{uuid.uuid4().hex}", "wb") as f:
        try:
            while True:
                f.write(b"\0" * 4096)
                f.flush()
                if shutil.disk_usage(disk).free <= leave:
                    break
        except OSError:
            pass


def leftovers(folder: Path) -> list[Path]:
    return [p for p in folder.rglob(".*") if p.name.endswith((".tmp", ".lock"))]


def test_a_failed_write_keeps_the_previous_file_and_names_the_path(small_disk):
    target = small_disk / "results.json"
    target.write_text('{"old": true}\n')
    fill(small_disk)
    with pytest.raises(UserError) as err:
        with atomic_write(target, elsewhere="choose another --out") as f:
            f.write("x" * 1_000_000)
    assert f"cannot write {target}" in str(err.value)
    assert "free some space there or choose another --out" in str(err.value)
    assert json.loads(target.read_text()) == {"old": True}
    assert not leftovers(small_disk)


def test_evaluation_on_a_full_disk_exits_2_and_keeps_its_partial_results(small_disk, capsys):
    out = small_disk / "r.json"
    # 300 grid-world episodes: the partial results (~55 KB) fit, the results JSON beside them does not
    fill(small_disk, leave=100_000)
    code = main(["eval", "--agent", "random", "--suite", "gridworld", "--seeds", "1", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2, err
    line = err.strip().splitlines()[-1]
    assert line.startswith("objsearch: error: cannot write ") and "choose another --out" in line, err
    assert "Traceback" not in err and not out.exists() and not leftovers(small_disk)
    partial = small_disk / "r.json.partial.jsonl"
    assert len(partial.read_text().splitlines()) == 301, "every finished episode was kept for the rerun"


def test_a_cache_that_does_not_fit_is_refused_before_rendering(small_disk, capsys):
    code = main(["cache", "build", "--suite", "house-single", "--cache-dir", str(small_disk)])
    err = capsys.readouterr().err
    assert code == 2, err
    assert f"cannot write {small_disk}/" in err and "MB needed" in err and "--cache-dir or $OBJSEARCH_CACHE" in err
    assert "Traceback" not in err
    assert not list(small_disk.iterdir()), "no temp folder, lock or half cache left"


def test_generate_on_a_full_disk_leaves_no_half_written_house(small_disk, capsys):
    fill(small_disk, leave=40_000)  # categories.json fits, a house with its meshes and preview does not
    code = main(["generate", "--num", "2", "--out", str(small_disk / "houses"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "cannot write" in err and "choose another --out" in err and "Traceback" not in err
    houses = [p for p in (small_disk / "houses").iterdir() if p.is_dir()]
    assert not houses and not leftovers(small_disk)
