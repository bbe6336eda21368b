"""``objsearch generate`` never replaces another house, nor a folder with a user's file in it,
silently (objsearch.house.house_folder, ``write_house``); the README's "Generate houses"
block runs as written."""

import json
import re
from pathlib import Path

from objsearch.cli import main

README = Path(__file__).resolve().parents[2] / "README.md"


def _generate(out, *more):
    return main(["generate", "--seed", "0", "--out", str(out), "--no-preview", "--quiet", *more])


def _spec(folder):
    return json.loads((folder / "spec.json").read_text())


def test_another_generator_into_the_same_folder_is_refused(tmp_path, capsys):
    assert _generate(tmp_path, "--generator", "house-gen-1") == 0
    house = tmp_path / "train_000000"
    before = (house / "spec.json").read_bytes()
    assert _generate(tmp_path) == 2  # house-gen-2, seed 0: another house of the same name
    err = capsys.readouterr().err
    assert (house / "spec.json").read_bytes() == before, "the house-gen-1 house is kept"
    assert f"{house} holds another house (house-gen-1" in err and "house-gen-2" in err and "--overwrite" in err
    assert _generate(tmp_path, "--overwrite") == 0
    assert _spec(house)["generator_version"] == "house-gen-2"


def test_the_same_house_again_keeps_the_files_beside_it(tmp_path):
    assert _generate(tmp_path) == 0
    house = tmp_path / "train_000000"
    (house / "notes.txt").write_text("mine")
    assert _generate(tmp_path) == 0  # the same seed and generator: the same house, left as it is
    assert (house / "notes.txt").read_text() == "mine"


def test_a_users_file_is_never_deleted_even_with_overwrite(tmp_path, capsys):
    assert _generate(tmp_path, "--generator", "house-gen-1") == 0
    house = tmp_path / "train_000000"
    (house / "notes.txt").write_text("mine")
    (house / "meshes" / "extra").mkdir()
    assert _generate(tmp_path, "--overwrite") == 2
    err = capsys.readouterr().err
    assert (house / "notes.txt").read_text() == "mine" and _spec(house)["generator_version"] == "house-gen-1"
    assert "notes.txt" in err and "did not write" in err


def test_a_folder_that_is_no_house_is_never_replaced(tmp_path, capsys):
    mine = tmp_path / "train_000000"
    mine.mkdir()
    (mine / "data.csv").write_text("1,2,3")
    assert _generate(tmp_path, "--overwrite") == 2
    assert (mine / "data.csv").read_text() == "1,2,3" and not (mine / "spec.json").exists()
    assert "data.csv" in capsys.readouterr().err


def test_the_placement_is_checked_before_any_house_is_generated(tmp_path, capsys, monkeypatch):
    assert main(["generate", "--seed", "0", "--num", "2", "--out", str(tmp_path), "--no-preview", "--quiet"]) == 0
    import objsearch.house.generate as generate

    def never(*args, **kwargs):
        raise AssertionError("refused before generating")

    monkeypatch.setattr(generate, "generate_house", never)
    assert main(["generate", "--seed", "1", "--out", str(tmp_path), "--placement", "shuffled", "--quiet"]) == 2
    assert "placement functional" in capsys.readouterr().err


def test_the_readme_generate_block_runs_as_written(tmp_path, monkeypatch, capsys):
    text = README.read_text()
    block = text[text.index("## Generate houses") :]
    block = block[block.index("```bash") + len("```bash") : block.index("```", block.index("```bash") + 3)]
    lines = [line.split("#")[0].split() for line in block.strip().splitlines()]
    generates = [line for line in lines if line[:2] == [".venv/bin/objsearch", "generate"]]
    make = next(line for line in lines if line[1:3] == ["suite", "make"])
    assert len(generates) >= 2
    monkeypatch.chdir(tmp_path)
    for line in generates:  # 2 houses each, not 20: the same folders and seeds
        args = [("2" if prev == "--num" else word) for prev, word in zip([None, *line], line)]
        assert main([*args[1:], "--no-preview", "--quiet"]) == 0, line
    houses = Path(make[make.index("--houses") + 1])
    generators = {_spec(folder)["generator_version"] for folder in houses.iterdir() if folder.is_dir()}
    assert generators == {"house-gen-2"}, "suite make --houses takes houses of one generator"
    assert re.search(r"--out (\S+)", " ".join(generates[1])).group(1) != str(houses) + "/"
