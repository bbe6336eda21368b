"""``objsearch cache clear`` removes only caches objsearch made (objsearch.perception.cache_cli,
objsearch.sim.cache_folder.cache_meta): a user's folders in the cache folder, a folder named
like a cache, a link to a cache and a home folder given as the cache folder lose nothing."""

import json
import os

import pytest

from objsearch.cli import main

OLD_CACHE = "train_000001-0123456789abcdef"  # a cache of an old version: clear removes it


def _old_cache(folder, house="train_000001", version="cache-v1"):
    folder.mkdir(parents=True)
    (folder / "rgb.npy").write_bytes(b"\x93NUMPY" + bytes(100))
    (folder / "meta.json").write_text(json.dumps({"version": version, "house_id": house, "key": "0123456789abcdef"}))


def _files(root):
    return sorted(str(p.relative_to(root)) for p in root.rglob("*") if p.is_file() or p.is_symlink())


@pytest.fixture
def root(tmp_path):
    root = tmp_path / "caches"
    (root / "Documents").mkdir(parents=True)
    (root / "Documents" / "thesis.tex").write_text("\\section{years of work}")
    (root / "project" / "src").mkdir(parents=True)
    (root / "project" / "src" / "main.py").write_text("print('mine')")
    named = root / "train_000002-fedcba9876543210"  # named like a cache, with no meta.json objsearch wrote
    named.mkdir()
    (named / "notes.txt").write_text("not a cache")
    fake = root / "train_000003-00000000000000aa"  # a meta.json, but not a cache's
    fake.mkdir()
    (fake / "meta.json").write_text(json.dumps({"version": "1.0", "house_id": "train_000003"}))
    (root / "todo.txt").write_text("a file beside the caches")
    _old_cache(root / OLD_CACHE)
    return root


@pytest.mark.parametrize("which", [[], ["--all"], ["--house", "Documents", "project", "train_000002", "train_000003"]])
def test_clear_removes_only_caches_and_names_what_it_left(root, which, capsys):
    house = which[:1] == ["--house"]  # houses none of whose caches are there
    others = [f for f in _files(root) if house or not f.startswith(OLD_CACHE)]
    assert main(["cache", "clear", "--cache-dir", str(root), *which]) == 0
    out = capsys.readouterr().out
    assert _files(root) == others, "nothing but the cache is removed"
    assert (root / OLD_CACHE).exists() == house
    assert "left 4 folders and 1 file that are not objsearch caches: Documents, project, todo.txt, train_000002" in out
    assert f"removed {0 if house else 1} cache" in out


def test_a_link_to_a_cache_is_left_and_said_so(tmp_path, capsys):
    root, elsewhere = tmp_path / "caches", tmp_path / "disk2" / "cache"
    _old_cache(elsewhere)
    root.mkdir()
    (root / OLD_CACHE).symlink_to(elsewhere)
    assert main(["cache", "clear", "--cache-dir", str(root), "--all"]) == 0
    out = capsys.readouterr().out
    assert (root / OLD_CACHE).is_symlink() and (elsewhere / "rgb.npy").is_file()
    assert "removed 0 caches" in out
    assert f"left 1 link to a cache (not removed: objsearch does not delete through links): {OLD_CACHE} -> " in out


def test_a_home_folder_as_the_cache_folder_loses_no_file(tmp_path, capsys):
    home = tmp_path / "home"
    for name in ("Documents/cv.pdf", ".ssh/id_ed25519", ".config/app/settings.json", "notes.md", ".bashrc"):
        (home / name).parent.mkdir(parents=True, exist_ok=True)
        (home / name).write_text(name)
    (home / "build.tmp").mkdir()
    (home / ".old.tmp").mkdir()  # a hidden .tmp folder objsearch did not make
    before = _files(home)
    for which in ([], ["--all"]):
        assert main(["cache", "clear", "--cache-dir", str(home), *which]) == 0
        assert _files(home) == before and (home / ".old.tmp").is_dir()
    assert "removed 0 caches" in capsys.readouterr().out
    assert main(["cache", "list", "--cache-dir", str(home)]) == 0
    out = capsys.readouterr().out
    assert "0 caches" in out and "not objsearch caches" in out


def test_verify_and_list_ignore_folders_that_are_not_caches(root, capsys):
    assert main(["cache", "list", "--cache-dir", str(root)]) == 0
    out = capsys.readouterr().out
    lines = out.splitlines()
    assert len(lines) == 2 and OLD_CACHE in lines[0] and "old version cache-v1" in lines[0]
    assert (
        lines[1].startswith("1 caches") and "not listed: 4 folders and 1 file that are not objsearch caches" in lines[1]
    )
    assert main(["cache", "verify", "--cache-dir", str(root)]) == 2
    assert "1 of 1 caches" in capsys.readouterr().err
    os.remove(root / OLD_CACHE / "meta.json")  # no longer provably a cache: left alone
    assert main(["cache", "clear", "--cache-dir", str(root), "--all"]) == 0
    assert (root / OLD_CACHE / "rgb.npy").is_file()
