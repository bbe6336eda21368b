"""The house evaluation suites: fixed, versioned episode files, and how they were made.

A suite file (``objsearch/sim/data/<suite>.json``) records its houses by generator seed
with their spec hashes, the goal poses of every target (by the goal rule, so success never
depends on the renderer at evaluation time) and the episodes of every split. Evaluation
regenerates the houses and refuses to run if a hash differs.

* ``house-single`` (the paper's Table 3, left): one house, 12 target categories; splits
  ``seen-goals`` and ``unseen-goals`` (6 categories each; agents train on the seen ones).
* ``house-multi`` (Table 3, right): 4 training houses and 4 unseen houses with the same 6
  target categories; splits ``seen-envs`` and ``unseen-envs``.
* ``house-gen`` (beyond the paper): 40 training houses (listed, no episodes), 10
  validation and 10 test houses generated as test houses (unseen object instances), with
  seen and unseen target categories (targets found in at least half of the evaluation
  houses, a third of them held out as unseen); splits ``val-seen``, ``val-unseen``,
  ``test-seen``, ``test-unseen``.
* ``house-gen-v2``: ``house-gen`` made again with the generator ``house-gen-2`` (circulation
  through a public core, rooms of real sizes, an entrance; the same seeds, splits and rule
  for targets). ``house-gen`` stays, since the shipped agents were trained and measured on it.
* ``house-gen-v2-objectnav``: ``house-gen-v2``'s houses, targets, splits and starts under the
  ObjectNav protocol (``objsearch.sim.goals.PROTOCOLS``): goal poses by the ``near_visible``
  rule, success only on STOP at one, 500 steps. Its episodes are ``house-gen-v2``'s whose
  start reaches a goal pose under that rule, with ``min_steps`` counted again (the STOP
  included).
* ``house-gen-v2-shuffled``: ``house-gen-v2``'s houses (training, validation and test, the
  same seeds) with their objects shuffled (``objsearch.house.shuffle``: every object moved
  to a random place anywhere in the house, ignoring groups and room priors), built as
  ``house-gen-v2`` is (its draws: the same targets and splits, episodes drawn the same way).
  What an agent loses here against ``house-gen-v2`` is what it owed to object relations.
* ``rooms`` (the paper's AI2-THOR experiment): single functional rooms (``objsearch.house.rooms``),
  30 of each of 4 types (20 training, 5 validation and 5 test rooms; "unseen env" is the 10
  validation and test rooms), seen and unseen goals per room type from the authors' lists,
  starts that do not see the target, 100 steps (200 in living rooms: ``room_max_steps``);
  splits ``seen-env-seen-goals``, ``seen-env-unseen-goals``, ``unseen-env-seen-goals``,
  ``unseen-env-unseen-goals`` (``objsearch.sim.rooms_suite``, docs/rooms.md).

* ``house-large``, ``house-large-roomwise``, ``house-large-shuffled`` (the large-house tier,
  ``docs/large_houses.md``): ``house-gen-3`` houses of 9-14 rooms, small targets (a cup, a
  book, soap, ...) once per house, the ObjectNav protocol with 500 steps and a goal rule for
  small objects, starts at least 8 m and 2 rooms from the target; the same houses, starts and
  targets with objects placed functionally, within room types, or anywhere
  (``objsearch.sim.large_suite``); splits ``val`` and ``test``.

* ``house-large-v2`` and ``-p25``, ``-p50``, ``-p75``, ``-shuffled``, ``-roomwise``: the tier's
  second version, on ``house-gen-4`` houses (``large_suite.LARGE_V2``, docs/large_houses.md).

* ``house-size-N`` and ``house-size-N-shuffled``, N = 4, 7, 10, 14 (the tier's size sweep):
  8 ``house-gen-3`` test houses of N rooms each, six small targets, 150 test episodes starting
  in another room than the target's and at least 4 m from it; functional and shuffled. For the
  curve of a prior's gain against house size (``objsearch.leaderboard.sweep``).

Episodes (all but ``rooms`` and the large tier and sweep): 100 per split, house and target drawn uniformly, the start uniformly among poses
6 to 40 minimal steps from the nearest goal pose (``START_STEPS``); 1000 steps at most (the
paper's protocol).
Rebuild (deliberately; bump the version): ``objsearch suite rebuild NAME``. How the files
are built, the shipped ones and users' own: ``objsearch.sim.suite_build``.

``SHIPPED`` declares the shipped house suites, one ``ShippedSuite`` record each (name,
content digest, recipe, generator, the suite it is made from); ``SUITE_NAMES`` and the
other tables are views of it, and the harness's registry (``objsearch.eval.suites.SUITES``)
takes the names from there. A new shipped suite is a record there (a new recipe also a
builder in ``suite_build.RECIPES``) and its file (``docs/add_a_suite.md``).

A user's own houses (folders written by ``objsearch generate``) make a suite file with
``objsearch suite make`` (``suite_build.suite_from_houses``): the same fields, with each
house recorded by its folder (a path relative to the suite file) and spec hash.
``load_suite_file`` takes a shipped suite's name or such a file's path and checks it field
by field (``objsearch.sim.suite_schema``); ``load_house`` refuses a house folder that is
missing, does not load, or no longer matches its spec or the suite, naming the house.

A suite's version is computed from its content (``suite_version``): a shipped file's
``version`` holds only while its content has the digest recorded here (``SUITE_DIGESTS``);
a made file's version is ``custom:`` and its digest, whatever its ``version`` field says (a
field a hand edit left stale is reported).
"""

from __future__ import annotations

import json
import os
import sys
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from objsearch.errors import UserError
from objsearch.fileio import open_regular, write_json
from objsearch.sim.env import HouseTask
from objsearch.sim.goals import PROTOCOLS, Protocol
from objsearch.sim.world import HouseRef, World

DATA_DIR = Path(__file__).parent / "data"


@dataclass(frozen=True)
class ShippedSuite:
    """A shipped house suite, declared once (``SHIPPED``); ``suite_build.build_suite`` makes its file.

    Attributes:
        name: the suite's name (its file is ``data/<name>.json``).
        digest: sha256 of the file's content (``suite_schema.content_digest``): its version
            holds only for this content. A deliberate rebuild (``objsearch suite rebuild NAME``
            prints it) bumps the version and this.
        recipe: how its houses and episodes are drawn: ``house-single``, ``house-multi`` or
            ``house-gen`` (``suite_build``), ``rooms`` (``rooms_suite``), ``house-large``
            (``large_suite``: the placements of a tier, the large-house tier or one size of its
            sweep, drawn together);
            None for a suite made from another one (below), which follows that one's.
        generator: its houses' generator; None: ``house-gen-1``, left out of the file's house
            entries so that the v1 files keep their bytes.
        objectnav_of: the paper-protocol suite whose houses, targets, splits and starts it
            plays under the ObjectNav protocol.
        shuffled_of: the suite whose houses (objects shuffled), seeds and draws it is made with.
    """

    name: str
    digest: str
    recipe: str | None = None
    generator: str | None = None
    objectnav_of: str | None = None
    shuffled_of: str | None = None


# The large-house tier's second version (large_suite.LARGE_V2): its six placements, drawn together.
LARGE_V2 = {
    "house-large-v2": "6a5d422192ac9ccf2835367cf47c8e2cfaa06ac6099e5d620d0b125eaedd03c3",
    "house-large-v2-p25": "08e873952d021a260d9bbbb4038d90ab135f482f238b37724e5a2a4341c59643",
    "house-large-v2-p50": "943f329f0ccbfdbf2df9e313484e3fe35c4060c0779fc3cd83b77ddf25aad62b",
    "house-large-v2-p75": "b608eaebb1bcf6e72e2cd628710ab65456d5bea2a760314ab61338f12f0e059e",
    "house-large-v2-shuffled": "d18a8565160fa1a9e57f6abc2d82c8b49adabc9ec98287b7b69c6c630d6cf69f",
    "house-large-v2-roomwise": "10a1f6123d47fe51ea0409ffe34ee51c9800161a14d695a8f026a574dd5b7273",
}
# The shipped house suites, in this order for good: a suite's index seeds its builder.
SHIPPED = (
    ShippedSuite(
        "house-single", "1abc146b5673fa9ddeb5d0b77908b4820fe7259d2115971bff83c52c261eac79", recipe="house-single"
    ),
    ShippedSuite(
        "house-multi", "d6222bc5441477d581ac67717740d9aa16d311911f0ef38412efd96d227f015f", recipe="house-multi"
    ),
    ShippedSuite("house-gen", "335992bd0ec90820bca3fd0120e2bd667088ede69ab5bee1ecb295d53ab058ea", recipe="house-gen"),
    ShippedSuite(
        "house-gen-v2",
        "e5e22e620fb28c5d268eecdc32ca9a1d3ae1ea7fc6179f4b6c9f129d7b72049d",
        recipe="house-gen",
        generator="house-gen-2",
    ),
    ShippedSuite(
        "house-single-v2",
        "80465c6e4a57889848fc7d139e6bd952e4fc2300ebddf639d3f719c1bb1344f0",
        recipe="house-single",
        generator="house-gen-2",
    ),
    ShippedSuite(
        "house-multi-v2",
        "c01ede47b5dfb495dbbcf5efcca919725c73f36cd2307cd20b4d93c7f6ddf91a",
        recipe="house-multi",
        generator="house-gen-2",
    ),
    ShippedSuite(
        "house-gen-v2-objectnav",
        "25b4286254cd944724b7b5dbca81adfbbe02d1aeb24f2ad73401e99438d96adf",
        objectnav_of="house-gen-v2",
    ),
    ShippedSuite(
        "house-gen-v2-shuffled",
        "bda0dace56ff67a72911170bafb7680ff46ea100ec1a417831680d927d2329e0",
        shuffled_of="house-gen-v2",
    ),
    ShippedSuite(
        "rooms",
        "b0e6e724a75149bd9eb59d49d1f87e346c98f50c0f27d1ad502adaca7739fb9e",
        recipe="rooms",
        generator="house-gen-2",
    ),
    ShippedSuite(
        "house-large",
        "02ef71353383d00dd8480e49576d2eb06a926305a6e1c2c33fafc9cce8951126",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-large-roomwise",
        "336cac5a5edbc3412f152332dcde6a8d50667cb30246f4126e39b0af73e4b082",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-large-shuffled",
        "e481d5d48bf7de6fd006d27be9e7641833b236fac3f285d298211fcba8dfef64",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-4",
        "98ce4f886b1bd34e053f48bea3327f55f7e8488ea449e84568682e2c6ff28834",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-4-shuffled",
        "42283db8b45f3bfc030201a09b1c78ed1690991d9b5fb6a3e61900d1e801aa94",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-7",
        "e6e882dfb416b96efdfd4dbc16f8f730af3aaed0ab1630465d4d5b9276146e12",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-7-shuffled",
        "f11bb801a670f2f4602ec89d215089728dd3fe7c51408268252f1284f36e074c",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-10",
        "45acf1ef542ed09bc8d7de779986665090ea12159aff1b802080e3ee0873a204",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-10-shuffled",
        "dee262b25b2d571d3b49f0cd9535eb33a1ba388d9a3b64bd512679857e342887",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-14",
        "9be7869e892db999dd47ac39fb4fd7f22fd133ceba922beb03b6efc5fcee2004",
        recipe="house-large",
        generator="house-gen-3",
    ),
    ShippedSuite(
        "house-size-14-shuffled",
        "6501b217dc5725343f2bf6d5bde7d7ac8d5c62399e176177747f889437c61c6a",
        recipe="house-large",
        generator="house-gen-3",
    ),
    *(ShippedSuite(name, digest, recipe="house-large", generator="house-gen-4") for name, digest in LARGE_V2.items()),
)
SHIPPED_SUITES = {suite.name: suite for suite in SHIPPED}
# Views of SHIPPED that the rest of objsearch reads.
SUITE_NAMES = tuple(SHIPPED_SUITES)
SUITE_DIGESTS = {suite.name: suite.digest for suite in SHIPPED}
OBJECTNAV_SUITES = {suite.name: suite.objectnav_of for suite in SHIPPED if suite.objectnav_of}
SHUFFLED_SUITES = {suite.name: suite.shuffled_of for suite in SHIPPED if suite.shuffled_of}
MADE_FIX = "correct it, or make the file again with objsearch suite make"


# The largest shipped suite file is under 0.5 MB (rooms.json); a suite file above this is not one
# objsearch made, and reading and checking it would take minutes and gigabytes.
SUITE_FILE_MAX_BYTES = 64_000_000


def load_suite_file(name: str) -> dict:
    """The suite file of a shipped house suite (a name of ``SUITE_NAMES``), or the one at the
    path ``name`` (``*.json``, made by ``objsearch suite make``) checked field by field
    (``suite_schema.check_suite_file``), its ``version`` the one its content gives
    (``suite_version``) and its house folders resolved against the file's folder. A bad file
    is a ``UserError`` naming the field and the fix."""
    if name in SUITE_NAMES:
        return _shipped_suite_file(name)
    if not name.endswith(".json"):
        raise UserError(
            f"unknown house suite {name!r}; known: {', '.join(SUITE_NAMES)}, "
            "or the path of a suite file (.json) made by objsearch suite make"
        )
    path = Path(name)
    try:
        with open_regular(
            path,
            "suite file",
            SUITE_FILE_MAX_BYTES,
            "a suite file objsearch suite make writes is a regular JSON file well below that; remake it with "
            "objsearch suite make",
        ) as f:
            data = json.loads(f.read().decode("utf-8"))
    except FileNotFoundError:
        raise UserError(
            f"suite file {path} does not exist; make it with objsearch suite make --houses DIR --out {path}"
        ) from None
    except OSError as err:
        raise UserError(f"cannot read suite file {path}: {err.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise UserError(f"suite file {path} is not JSON ({err}); remake it with objsearch suite make") from None
    except RecursionError:
        raise UserError(
            f"suite file {path} nests too deep to be a suite file; remake it with objsearch suite make"
        ) from None
    from objsearch.sim.suite_schema import check_suite_file

    check_suite_file(data, str(path), MADE_FIX)
    data["version"] = suite_version(data, str(path))
    for group in ("houses", "training_houses"):
        for info in data[group].values():
            if "path" in info:
                info["path"] = os.path.abspath(path.parent / info["path"])
    return data


@lru_cache(maxsize=None)
def _shipped_suite_file(name: str) -> dict:
    path = DATA_DIR / f"{name}.json"
    if not path.exists():
        raise UserError(f"suite file {path} is missing; rebuild it with objsearch suite rebuild {name}")
    data = json.loads(path.read_text())
    suite_version(data, str(path), name)
    return data


_REPORTED: set[tuple[str, str]] = set()  # (file, version) whose stale version field was reported


def suite_version(data: dict, source: str, shipped: str | None = None) -> str:
    """The version of the suite file content ``data`` (read from ``source``): for the shipped
    suite ``shipped``, its ``version`` field, which holds only while the content has the
    digest recorded in ``SUITE_DIGESTS`` (else ``UserError``: the package's file was edited);
    for any other file ``custom:`` and the first 12 hex digits of its digest
    (``suite_schema.content_digest``). A ``version`` field that differs (a hand edit left it
    stale) is reported once on stderr."""
    from objsearch.sim.suite_schema import content_digest

    digest = content_digest(data)
    if shipped is not None:
        if digest != SUITE_DIGESTS[shipped]:
            raise UserError(
                f"suite file {source} was edited: its content digest is {digest[:12]}, but {data.get('version')} is "
                f"{SUITE_DIGESTS[shipped][:12]}; restore it (reinstall objsearch), or rebuild it deliberately "
                f"(objsearch suite rebuild {shipped}) with a new version and its digest in SUITE_DIGESTS"
            )
        return data["version"]
    version = f"custom:{digest[:12]}"
    if data["version"] != version and (source, data["version"]) not in _REPORTED:
        _REPORTED.add((source, data["version"]))
        print(
            f"warning: suite file {source} changed after objsearch suite make wrote it (its version field says "
            f"{data['version']}, its content is {version}): results record {version}",
            file=sys.stderr,
        )
    return version


def suite_protocol(data: dict) -> Protocol:
    """The protocol of a suite file's content (``paper`` where the file has no ``protocol``)."""
    return PROTOCOLS[data.get("protocol", "paper")]


def write_suite_file(path: str | os.PathLike, suite: dict) -> None:
    """Write a suite file as the shipped ones are written (one line of JSON, atomically)."""
    write_json(path, suite, indent=None)


def load_house(ref: HouseRef, name: str) -> World:
    """``World.load(ref)``, with a house folder (``ref.path``) checked further: it must exist,
    load, hold the ``house.xml`` its ``spec.json`` compiles to, and match ``ref.spec_sha256``.
    A bad one is a one-line ``UserError`` naming the house (``name``) and the fix."""
    if ref.path is None:
        return World.load(ref)
    from objsearch.house.mjcf import compile_house

    folder = Path(ref.path)
    if not folder.is_dir():
        raise UserError(
            f"house {name}: folder {folder} is missing; restore it, or remake the suite with objsearch suite make"
        )
    try:
        world = World.load(HouseRef(path=ref.path))
        if ref.spec_sha256 is not None and world.spec_sha256 != ref.spec_sha256:
            raise UserError(
                f"{folder / 'spec.json'} changed after the suite was made (spec hash {world.spec_sha256[:12]}, "
                f"the suite has {ref.spec_sha256[:12]}); restore the house, or remake the suite with "
                "objsearch suite make"
            )
        if compile_house(world.spec)[1] != (folder / "house.xml").read_text():
            raise UserError(
                f"{folder / 'spec.json'} no longer matches its house.xml (one was edited, or they come from "
                "another objsearch or MuJoCo version); regenerate the house with objsearch generate"
            )
    except UserError as err:
        raise UserError(f"house {name}: {' '.join(str(err).split())}") from None
    except (ValueError, KeyError, TypeError, AttributeError) as err:
        raise UserError(
            f"house {name}: {folder / 'spec.json'} is not a house spec ({' '.join(str(err).split())}); "
            "regenerate the house with objsearch generate"
        ) from None
    return world


def load_houses(suite: dict) -> dict[str, World]:
    """A suite's evaluation houses by house id, each loaded and checked by ``load_house``."""
    worlds = (load_house(HouseRef(**info), house_id) for house_id, info in suite["houses"].items())
    return {world.house_id: world for world in worlds}


def house_refs(suite: dict) -> list[HouseRef]:
    """The ``HouseRef`` of every evaluation house of a suite dict."""
    return [HouseRef(**info) for info in suite["houses"].values()]


def episode_task(suite: dict, item: dict) -> HouseTask:
    """The ``HouseTask`` of one split entry ``item`` of a suite dict, with its goal poses."""
    goals = suite["goals"][item["house"]][item["target"]]
    return HouseTask(
        house=item["house"],
        start=tuple(item["start"]),
        target=item["target"],
        goals=tuple(tuple(g) for g in goals),
        min_steps=item["min_steps"],
    )


def house_generator(info: dict) -> str:
    """The generator version of one house entry of a suite file: recorded for generated
    houses (absent: ``house-gen-1``), read from ``spec.json`` for a house folder."""
    if "path" not in info:
        return info.get("generator") or "house-gen-1"
    try:
        return json.loads((Path(info["path"]) / "spec.json").read_text()).get("generator_version") or "house-gen-1"
    except (OSError, ValueError, AttributeError):
        raise UserError(
            f"house folder {info['path']}: no readable spec.json; restore it, or remake the suite with objsearch suite make"
        ) from None


def suite_generators(suite: dict) -> set[str]:
    """The generator versions of a suite's evaluation houses."""
    return {house_generator(info) for info in suite["houses"].values()}


def training_houses(suite: dict) -> list[HouseRef]:
    """The houses agents train on: ``house-single``'s house, ``house-multi``'s seen
    environments, ``house-gen``'s training houses (never an evaluation-only house)."""
    if suite["training_houses"]:
        return [HouseRef(**info) for info in suite["training_houses"].values()]
    split = "seen-envs" if "seen-envs" in suite["splits"] else next(iter(suite["splits"]))
    ids = sorted({item["house"] for item in suite["splits"][split]})
    return [HouseRef(**suite["houses"][house]) for house in ids]


def training_targets(suite: dict) -> list[str]:
    """The target categories agents train on: the suite's seen ones (``house-multi``: its six)."""
    categories = suite["categories"]
    return list(categories.get("seen", categories.get("targets", [])))


if __name__ == "__main__":  # the old entry point, gone: say where it went
    raise SystemExit("python -m objsearch.sim.suites is now: objsearch suite rebuild NAME [NAME ...]")
