"""Writes that cannot destroy: outputs are regular files only (a device, FIFO or folder is
refused, a symlink's target is replaced and the link kept), and temp folders are recognised
by the marker objsearch wrote, never by their name."""

import json
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from objsearch.errors import UserError
from objsearch.fileio import (
    TEMP_MARKER,
    abandoned_temp_folders,
    atomic_directory,
    atomic_write,
    check_writable,
    is_temp_folder,
    write_json,
)

BIN = Path(sys.executable).parent


def make_old(path: Path, hours: float) -> None:
    when = time.time() - hours * 3600
    for p in [*path.iterdir(), path]:
        os.utime(p, (when, when), follow_symlinks=False)


def test_a_users_folder_named_like_a_temp_folder_is_never_taken_for_one(tmp_path):
    host = socket.gethostname()
    for name in (".notes.tmp", f".cache.{host}.999999.abcd.tmp", ".cache.some-other-host.12345.abcd.tmp"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "precious.txt").write_text("mine")
        make_old(tmp_path / name, 48)
    assert abandoned_temp_folders(tmp_path) == []
    fake = tmp_path / ".faked.tmp"  # a marker that is a symlink, or with other content, is no marker
    fake.mkdir()
    (fake / TEMP_MARKER).symlink_to(tmp_path / ".notes.tmp" / "precious.txt")
    make_old(fake, 48)
    assert not is_temp_folder(fake) and abandoned_temp_folders(tmp_path) == []


def test_atomic_directory_marks_its_temp_folder_and_leaves_no_marker_in_the_result(tmp_path):
    with atomic_directory(tmp_path / "house") as tmp:
        assert is_temp_folder(tmp)
        (tmp / "house.xml").write_text("<mujoco/>")
    assert sorted(p.name for p in (tmp_path / "house").iterdir()) == ["house.xml"]


def test_a_cache_build_removes_only_marked_temp_folders(tmp_path):
    code = (
        "import os, sys; from objsearch.fileio import atomic_directory\n"
        "with atomic_directory(sys.argv[1]) as tmp:\n"
        "    (tmp / 'part').write_text('x'); os._exit(9)\n"
    )
    assert subprocess.run([sys.executable, "-c", code, str(tmp_path / "cache")], timeout=120).returncode == 9
    (tmp_path / ".mine.tmp").mkdir()
    make_old(tmp_path / ".mine.tmp", 48)
    (left,) = abandoned_temp_folders(tmp_path)
    assert left.name.startswith(".cache.") and (left / "part").exists()


@pytest.mark.parametrize("kind", ["fifo", "chardev", "folder"])
def test_an_output_that_is_not_a_regular_file_is_refused(tmp_path, kind):
    if kind == "fifo":
        target = tmp_path / "pipe"
        os.mkfifo(target)
        what = "FIFO (named pipe)"
    elif kind == "chardev":
        target, what = Path("/dev/null"), "character device"
    else:
        target, what = tmp_path / "folder", "folder"
        target.mkdir()
    with pytest.raises(UserError) as err:
        write_json(target, {"a": 1}, elsewhere="choose another --out")
    assert f"cannot write {target}: it is a {what}, not a regular file" in str(err.value)
    assert "choose another --out" in str(err.value)
    assert not stat_changed(target)
    link = tmp_path / "link.json"
    link.symlink_to(target)
    with pytest.raises(UserError) as err:
        write_json(link, {"a": 1})
    assert f"cannot write {link} (a symlink to {target.resolve()}): it is a {what}" in str(err.value)
    assert link.is_symlink()
    if kind != "folder":
        with pytest.raises(UserError):
            check_writable(target, "--out")
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith(".")) == []  # no temp file left


def stat_changed(path: Path) -> bool:
    return path.is_file() and not path.is_symlink()  # a device or FIFO replaced by a regular file


def test_a_symlink_output_replaces_its_target_and_stays_a_link(tmp_path):
    (tmp_path / "real").mkdir()
    target = tmp_path / "real" / "results.json"
    target.write_text("old")
    link = tmp_path / "results.json"
    link.symlink_to(target)
    with atomic_write(link) as f:
        f.write("new")
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_text() == "new" and link.read_text() == "new"
    assert sorted(p.name for p in (tmp_path / "real").iterdir()) == ["results.json"]


def test_objsearch_eval_out_to_a_fifo_or_device_exits_2_before_any_episode(tmp_path):
    os.mkfifo(tmp_path / "pipe")
    for out in (tmp_path / "pipe", Path("/dev/null")):
        done = subprocess.run(
            [str(BIN / "objsearch-eval"), "--agent", "random", "--suite", "gridworld", "--split", "unseen-goals",
             "--seeds", "1", "--quiet", "--out", str(out)],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        lines = done.stderr.strip().splitlines()
        assert done.returncode == 2 and len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
        assert f"cannot write {out}: it is a " in lines[0] and "not a regular file" in lines[0]
    assert Path("/dev/null").is_char_device() and (tmp_path / "pipe").is_fifo()
    assert json.dumps(sorted(p.name for p in tmp_path.iterdir())) == '["pipe"]'
