"""The shipped house suite files are the benchmark: their bytes and versions never change
by accident, and they are written as ``objsearch suite rebuild`` writes them."""

import hashlib

import pytest

from objsearch.sim.suites import DATA_DIR, SUITE_NAMES, load_suite_file, write_suite_file

# Change one of these only with a deliberate rebuild (objsearch suite rebuild NAME) and a new version.
SHIPPED = {
    "house-single": ("house-single-v1", "92605b57d05a25798de3476edf63f8415f3e998fc6b2458799985981fdad1fda"),
    "house-multi": ("house-multi-v1", "3f68c77d2efbd5b28ab0f1cd9e36b187a09a1be34842bfdab716e2b9e959a306"),
    "house-gen": ("house-gen-v1", "6e206f26a198e48096b684235e5cb1054fe1068e8950c7ca4d1e331bc7122a09"),
    "house-gen-v2": ("house-gen-v2-v1", "c62052da5878932444d6cc157f886bbc19333a77f595b7b3217f4c0bfd6d0cc0"),
    "house-single-v2": ("house-single-v2-v1", "513ac949cae07a96199bb516cd305ee9246cb0239f8cf4187a1848e5761cfa54"),
    "house-multi-v2": ("house-multi-v2-v1", "f683105358252d0a702ebcab822633c55583bdd69361bd38b53f75102150655f"),
    "house-gen-v2-objectnav": (
        "house-gen-v2-objectnav-v1",
        "665e23e97971f5bba1a0ee516cab796c4ed315cd92a6ae0f46a964919118b058",
    ),
    "house-gen-v2-shuffled": (
        "house-gen-v2-shuffled-v1",
        "e8eeb214527e78badcfec1a9396ee6acdff65bd48a1a73083ec237274d76e021",
    ),
    "rooms": ("rooms-v1", "31f17d636bcc4269124a39e7a887c21753d1f368f3ba5f9a55e70fe5f7ccc0ce"),
    "house-large": ("house-large-v1", "85d62e147d861c07d13da9cf429d25693a54ac33c29d741056b34b2e0e48bc3c"),
    "house-large-roomwise": (
        "house-large-roomwise-v1",
        "c29329810030151778c0ac5d44f334b8abed68e8372ae95a5ece8b2a193c27d8",
    ),
    "house-large-shuffled": (
        "house-large-shuffled-v1",
        "f53fa25b59e01c0997d2e6441354c7cbe6f46f07e16be14a0743fba5f7c356da",
    ),
    "house-size-4": ("house-size-4-v1", "c437565362aeaa44e4e66285afc4a13cba4ab533696a5a5fd9c85bf2700de662"),
    "house-size-4-shuffled": (
        "house-size-4-shuffled-v1",
        "93f370d50d85fc3c39d4090e31810c033d4db7ac3a00e8e21a6f75ade6ae2880",
    ),
    "house-size-7": ("house-size-7-v1", "7c3370190b2c08bfc23c77f186b39fd407f6b7eb94f121a08f7c00e4e64f2f55"),
    "house-size-7-shuffled": (
        "house-size-7-shuffled-v1",
        "43df9aa55a20e73c0bd52ca04b573cde7b62caddc5be25f94c461e46c0e0ddc5",
    ),
    "house-size-10": ("house-size-10-v1", "f460fd4df4591086b7228d3b0e77f3cc78a9339e34f1d1482ddbb51ef3d2e982"),
    "house-size-10-shuffled": (
        "house-size-10-shuffled-v1",
        "83060169059ae1b2042d8812361e9b510b626f850fd739d08608b48e763921e1",
    ),
    "house-size-14": ("house-size-14-v1", "c4ae5bbf3bf2caa4d95f7fe85cf1997f2fc9935a7183abc677d2c702289a37fe"),
    "house-size-14-shuffled": (
        "house-size-14-shuffled-v1",
        "3ec177e3c6d3e91a85c2a3839c20ae58301fb29e1714540489bcfb8fb930d5ab",
    ),
    "house-large-v2": ("house-large-v2-v2", "ca04629d172dd03a63474fb14d927e6d4d6c1f4c42b55befb13dd5ac93569a3e"),
    "house-large-v2-p25": ("house-large-v2-p25-v2", "03266bc703ec92f282f0fe9120df76f2ff5dd033be3b0ff5ca28ccaeafc59926"),
    "house-large-v2-p50": ("house-large-v2-p50-v2", "930bab05c2607e4c17ceb90889f50715287086aa0ae9ad96ad5811a9f515f307"),
    "house-large-v2-p75": ("house-large-v2-p75-v2", "834af414f57a0363b621870ffc6272e9051895ae15e8909d7c238f0e2e1ea038"),
    "house-large-v2-shuffled": (
        "house-large-v2-shuffled-v2",
        "3e2a6f97886b83c5126b4f46bb47f66ba39fa9ae7aa2fb60e8e27d736a5926da",
    ),
    "house-large-v2-roomwise": (
        "house-large-v2-roomwise-v2",
        "66361d9a981036baf45ac0dd6bb602e9ad6571e5f68b61788e5e2baa11c63c67",
    ),
}


def test_every_shipped_suite_has_its_file_and_no_other_file_is_shipped():
    assert set(SUITE_NAMES) == set(SHIPPED)
    assert sorted(p.stem for p in DATA_DIR.glob("*.json")) == sorted(SHIPPED)


@pytest.mark.parametrize("name", SUITE_NAMES)
def test_shipped_file_loads_with_its_version_and_bytes(name, tmp_path):
    version, sha256 = SHIPPED[name]
    path = DATA_DIR / f"{name}.json"
    assert hashlib.sha256(path.read_bytes()).hexdigest() == sha256, (
        f"{path} changed: rebuild deliberately, bump its version"
    )
    suite = load_suite_file(name)
    assert suite["suite"] == name and suite["version"] == version and suite["navgraph"] == "navgraph-v1"
    assert all(len(info["spec_sha256"]) == 64 and "seed" in info for info in suite["houses"].values())
    # the writer of objsearch suite rebuild and objsearch suite make gives these bytes back
    write_suite_file(tmp_path / "again.json", suite)
    assert (tmp_path / "again.json").read_bytes() == path.read_bytes()
