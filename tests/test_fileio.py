"""``objsearch.fileio``: atomic files and folders, their leftovers, and checking an output
path before any work."""

import csv
import json
import os
import re
import socket
import stat
import subprocess
import sys
import time

import pytest

from objsearch.errors import UserError
from objsearch.fileio import (
    MARKER_TEXT,
    TEMP_MARKER,
    abandoned_temp_folders,
    atomic_directory,
    atomic_write,
    check_writable,
    write_csv,
    write_json,
)


def leftovers(folder):
    """Everything in ``folder`` that looks like a temp file or folder of this module."""
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".") and p.name.endswith(".tmp"))


# -- atomic_write ---------------------------------------------------------------------------
def test_atomic_write_replaces_the_file_and_leaves_no_temp(tmp_path):
    path = tmp_path / "out.txt"
    path.write_text("old")
    with atomic_write(path) as f:
        f.write("new")
        assert path.read_text() == "old", "the file is replaced only when the block ends"
        assert len(leftovers(tmp_path)) == 1  # the temp file lies beside the target
    assert path.read_text() == "new"
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("error", [ValueError, KeyboardInterrupt])
def test_atomic_write_keeps_the_old_file_when_the_writer_raises(tmp_path, error):
    path = tmp_path / "out.txt"
    path.write_text("old")
    with pytest.raises(error):
        with atomic_write(path) as f:
            f.write("half")
            f.flush()
            raise error("writer failed")
    assert path.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.txt"]


def test_atomic_write_creates_no_file_when_the_first_write_fails(tmp_path):
    with pytest.raises(RuntimeError):
        with atomic_write(tmp_path / "new.json"):
            raise RuntimeError
    assert list(tmp_path.iterdir()) == []


def test_atomic_write_makes_the_parent_folders_and_writes_bytes(tmp_path):
    path = tmp_path / "a" / "b" / "blob.bin"
    with atomic_write(path, "wb") as f:
        f.write(b"\x00\x01")
    assert path.read_bytes() == b"\x00\x01"


def test_atomic_write_gives_the_file_the_usual_mode_not_mkstemps_0600(tmp_path):
    old = os.umask(0o027)
    try:
        with atomic_write(tmp_path / "f.txt") as f:
            f.write("x")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "f.txt").stat().st_mode) == 0o640
    assert os.umask(old) == old, "the umask is left as it was"


# -- write_json / write_csv ------------------------------------------------------------------
def test_write_json_round_trips_and_ends_with_a_newline(tmp_path):
    obj = {"agent": "hrl_grg", "seeds": [1, 5], "sr": 0.25, "nested": {"ok": True, "none": None}, "name": "ü"}
    path = tmp_path / "sub" / "r.json"
    write_json(path, obj)
    text = path.read_text()
    assert json.loads(text) == obj and text.endswith("}\n")
    write_json(path, [1, 2], indent=None)
    assert path.read_text() == "[1, 2]\n"


def test_write_json_keeps_the_old_file_when_the_object_is_not_json(tmp_path):
    path = tmp_path / "r.json"
    write_json(path, {"a": 1})
    with pytest.raises(TypeError):
        write_json(path, {"a": object()})
    assert json.loads(path.read_text()) == {"a": 1}
    assert leftovers(tmp_path) == []


def test_write_csv_round_trips_with_a_header(tmp_path):
    rows = [{"step": 1, "loss": 0.5, "note": "a,b"}, {"step": 2, "loss": 0.25, "note": 'say "hi"'}]
    path = tmp_path / "log.csv"
    write_csv(path, ["step", "loss", "note"], rows)
    with open(path, newline="") as f:
        back = list(csv.DictReader(f))
    assert back == [{k: str(v) for k, v in row.items()} for row in rows]
    write_csv(path, ["step"], [])
    assert path.read_text().splitlines() == ["step"]


def test_write_csv_keeps_the_old_file_on_a_row_with_an_unknown_field(tmp_path):
    path = tmp_path / "log.csv"
    write_csv(path, ["step"], [{"step": 1}])
    before = path.read_text()
    with pytest.raises(ValueError, match="oops"):
        write_csv(path, ["step"], [{"step": 2}, {"oops": 3}])
    assert path.read_text() == before and leftovers(tmp_path) == []


# -- atomic_directory ------------------------------------------------------------------------
def test_atomic_directory_creates_a_folder_whole(tmp_path):
    target = tmp_path / "parent" / "cache"
    with atomic_directory(target) as tmp:
        assert not target.exists()
        assert tmp.parent == target.parent and tmp.name.startswith(f".cache.{socket.gethostname()}.{os.getpid()}.")
        (tmp / "a.npz").write_text("a")
    assert sorted(p.name for p in target.iterdir()) == ["a.npz"]
    assert leftovers(target.parent) == []


def test_atomic_directory_replaces_a_full_folder(tmp_path):
    target = tmp_path / "cache"
    target.mkdir()
    (target / "stale").write_text("old")
    (target / "sub").mkdir()
    (target / "sub" / "deep").write_text("old")
    with atomic_directory(target) as tmp:
        (tmp / "fresh").write_text("new")
    assert sorted(p.name for p in target.iterdir()) == ["fresh"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cache"], "neither the temp nor the old folder is left"


def test_atomic_directory_keeps_the_old_folder_when_the_block_raises(tmp_path):
    target = tmp_path / "cache"
    target.mkdir()
    (target / "kept").write_text("old")
    with pytest.raises(KeyboardInterrupt):
        with atomic_directory(target) as tmp:
            (tmp / "half").write_text("x")
            raise KeyboardInterrupt
    assert sorted(p.name for p in target.iterdir()) == ["kept"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cache"]


def test_atomic_directory_replaces_a_file_in_the_way(tmp_path):
    target = tmp_path / "cache"
    target.write_text("a file")
    with atomic_directory(target) as tmp:
        (tmp / "fresh").write_text("new")
    assert target.is_dir()


# -- abandoned_temp_folders ------------------------------------------------------------------
def dead_pid() -> int:
    """The pid of a process that has ended (and been reaped)."""
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def temp_folder(path):
    """A temp folder as ``atomic_directory`` makes one: with its marker file."""
    path.mkdir()
    (path / TEMP_MARKER).write_text(MARKER_TEXT + "test\n")


def make_old(path, hours):
    when = time.time() - hours * 3600
    for p in [*path.iterdir(), path]:
        os.utime(p, (when, when))


def test_abandoned_temp_folders_finds_those_of_dead_processes_on_this_host(tmp_path):
    host = socket.gethostname()
    dead = tmp_path / f".cache.{host}.{dead_pid()}.abcd.tmp"
    alive = tmp_path / f".cache.{host}.{os.getpid()}.efgh.tmp"
    temp_folder(dead)
    temp_folder(alive)
    make_old(alive, 100)  # running: never abandoned, however old
    assert abandoned_temp_folders(tmp_path) == [dead]


def test_abandoned_temp_folders_of_another_host_or_without_pid_go_by_age(tmp_path):
    other_old = tmp_path / ".cache.some-other-host.12345.abcd.tmp"
    other_new = tmp_path / ".cache.some-other-host.12346.abcd.tmp"
    legacy_old = tmp_path / ".cache.abcd.tmp"
    for folder in (other_old, other_new, legacy_old):
        temp_folder(folder)
        (folder / "part").write_text("x")
    make_old(other_old, 30)
    make_old(legacy_old, 30)
    make_old(other_new, 30)
    (other_new / "part").write_text("touched just now")  # the newest file inside counts
    assert sorted(abandoned_temp_folders(tmp_path)) == sorted([other_old, legacy_old])
    assert abandoned_temp_folders(tmp_path, max_age_hours=40) == []


def test_abandoned_temp_folders_ignores_files_and_other_names_and_a_missing_parent(tmp_path):
    host = socket.gethostname()
    (tmp_path / f".out.json.{host}.{dead_pid()}.tmp").write_text("a temp *file*, not a folder")
    temp_folder(tmp_path / f"cache.{host}.{dead_pid()}.abcd.tmp")  # no leading dot: not a temp folder
    (tmp_path / "results").mkdir()
    assert abandoned_temp_folders(tmp_path) == []
    assert abandoned_temp_folders(tmp_path / "nowhere") == []


def test_a_temp_folder_left_by_a_killed_process_is_found(tmp_path):
    code = (
        "import os, sys; from objsearch.fileio import atomic_directory\n"
        "with atomic_directory(sys.argv[1]) as tmp:\n"
        "    (tmp / 'part').write_text('x'); os._exit(9)\n"
    )
    out = subprocess.run([sys.executable, "-c", code, str(tmp_path / "cache")], timeout=120)
    assert out.returncode == 9
    left = abandoned_temp_folders(tmp_path)
    assert len(left) == 1 and left[0].name.startswith(".cache.") and (left[0] / "part").exists()
    assert not (tmp_path / "cache").exists()


# -- check_writable --------------------------------------------------------------------------
def test_check_writable_accepts_new_and_existing_paths(tmp_path):
    check_writable(tmp_path / "r.json", "--out")
    (tmp_path / "r.json").write_text("{}")
    check_writable(tmp_path / "r.json", "--out")
    check_writable(tmp_path / "new" / "deeper" / "r.json", "--out")  # folders that would be made
    check_writable(tmp_path, "--video", folder=True)
    check_writable(tmp_path / "new-folder" / "sub", "--video", folder=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.json"], "checking writes nothing that stays"


def test_check_writable_refuses_a_folder_given_as_a_file(tmp_path):
    with pytest.raises(UserError) as err:
        check_writable(tmp_path, "--out")
    assert str(err.value) == f"--out {tmp_path} is a folder; give a file path, e.g. {tmp_path / 'results.json'}"


def test_check_writable_refuses_a_file_given_as_a_folder(tmp_path):
    (tmp_path / "video").write_text("x")
    with pytest.raises(UserError) as err:
        check_writable(tmp_path / "video", "--video", folder=True)
    assert str(err.value) == f"--video {tmp_path / 'video'} is a file, not a folder; give a folder path"


@pytest.mark.parametrize("folder", [False, True])
def test_check_writable_refuses_a_path_below_a_file(tmp_path, folder):
    (tmp_path / "runs").write_text("x")
    path = tmp_path / "runs" / "a" / "r.json"
    with pytest.raises(UserError) as err:
        check_writable(path, "--out", folder=folder)
    assert str(err.value) == f"--out {path}: {tmp_path / 'runs'} is a file, not a folder; choose another place"


def test_check_writable_names_the_absolute_path_of_a_relative_one(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "here").mkdir()
    with pytest.raises(UserError, match="^" + re.escape(f"--out {tmp_path / 'here'} is a folder")):
        check_writable("here", "--out")


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")
def test_check_writable_tries_a_real_write(tmp_path):
    """Permission bits say nothing for root: /proc refuses a write whoever asks."""
    with pytest.raises(UserError) as err:
        check_writable("/proc/objsearch-test/r.json", "--out")
    assert str(err.value).startswith("--out /proc/objsearch-test/r.json: cannot write in /proc (")
    assert str(err.value).endswith("); choose a place you can write to")


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root may write anywhere")
def test_check_writable_refuses_a_folder_or_file_without_write_permission(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    (tmp_path / "ro.json").write_text("{}")
    (tmp_path / "ro.json").chmod(0o444)
    locked.chmod(0o555)
    try:
        with pytest.raises(UserError, match=re.escape(f"--out {locked / 'r.json'}: cannot write in {locked} (")):
            check_writable(locked / "r.json", "--out")
        with pytest.raises(UserError, match=re.escape(f"--out {tmp_path / 'ro.json'}: no permission to overwrite it")):
            check_writable(tmp_path / "ro.json", "--out")
    finally:
        locked.chmod(0o755)
