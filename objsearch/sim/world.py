"""A house ready to move and look in: its spec, compiled model and pose graph.

Houses come from a generator seed (regenerated, and checked against a recorded spec hash
so a generator change cannot silently change a benchmark) or from a house directory
written by ``objsearch generate``.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import mujoco
import numpy as np

from objsearch.errors import UserError
from objsearch.fileio import open_regular
from objsearch.house.spec import HouseSpec
from objsearch.sim.navgraph import GRID, PoseGraph, build_pose_graph


def spec_hash(spec: HouseSpec) -> str:
    """sha256 of the canonical spec JSON: the identity of a house's content."""
    return hashlib.sha256(spec.to_json_text().encode()).hexdigest()


@dataclass(frozen=True)
class HouseRef:
    """How to obtain a house: a generator seed (with split and size class) or a directory.

    Attributes:
        seed, split, size_class: regenerate with ``objsearch.house.generate``.
        generator: the generator version to regenerate with (None: ``house-gen-1``; unset fields
            are left out of ``to_json``, so references to ``house-gen-1`` houses keep their bytes).
        placement: how its objects are placed (``objsearch.house.spec.HOUSE_PLACEMENTS``; None:
            ``functional``), e.g. ``shuffled``.
        room: a single room of this type instead of a house (``objsearch.house.rooms.ROOM_TYPES``;
            its generator is ``house-gen-2`` unless ``generator`` says otherwise).
        path: a house directory (``house.xml`` + ``spec.json``) instead of a seed.
        spec_sha256: if set, the house's spec must hash to it.
    """

    seed: int | None = None
    split: str = "train"
    size_class: str | None = None
    path: str | None = None
    spec_sha256: str | None = None
    generator: str | None = None
    placement: str | None = None
    room: str | None = None

    def to_json(self) -> dict:
        """The reference as a JSON dict, without its unset (None) fields."""
        return {k: v for k, v in self.__dict__.items() if v is not None}


# A house folder's files: spec.json and house.xml are a few MB at most, its meshes tens of MB;
# anything larger (or not a regular file) is not a house objsearch generate wrote.
HOUSE_FILE_MAX_BYTES = 256 * 2**20
HOUSE_FIX = "a house folder holds the regular files objsearch generate writes; generate it again"
MAX_INCLUDE_DEPTH = 8


def check_mjcf_files(xml_path: Path, _depth: int = 0, _model_dir: Path | None = None) -> None:
    """Refuse (``UserError``) an MJCF file ``xml_path``, or any file it names (``<include>``d
    MJCF, meshes, textures: every ``file`` attribute, under the model's folder or its compiler's
    ``meshdir`` / ``texturedir`` / ``assetdir``), that is not a regular file of at most
    ``HOUSE_FILE_MAX_BYTES``: MuJoCo would block forever on an ``<include>`` of a FIFO and read a
    device without end. Files that do not exist are left to MuJoCo to report."""
    import xml.etree.ElementTree as ET

    with open_regular(xml_path, "house file", HOUSE_FILE_MAX_BYTES, HOUSE_FIX) as f:
        data = f.read()
    try:
        root = ET.fromstring(data)
    except ET.ParseError:
        return  # not XML: MuJoCo says where, as for any MJCF it cannot compile
    model_dir = _model_dir or xml_path.parent  # MuJoCo takes every file, included ones too, from here
    folders = {model_dir}
    for compiler in root.iter("compiler"):
        folders |= {model_dir / compiler.get(k) for k in ("meshdir", "texturedir", "assetdir") if compiler.get(k)}
    for element in root.iter():
        name = element.get("file")
        if not name:
            continue
        for folder in folders:
            path = folder / name
            if not os.path.lexists(path):
                continue
            if element.tag == "include":
                if _depth >= MAX_INCLUDE_DEPTH:
                    raise UserError(
                        f"house file {xml_path} nests <include> deeper than {MAX_INCLUDE_DEPTH}; {HOUSE_FIX}"
                    )
                check_mjcf_files(path, _depth + 1, model_dir)
            else:
                open_regular(path, "house file", HOUSE_FILE_MAX_BYTES, HOUSE_FIX).close()


class World:
    """One loaded house. ``model`` and ``graph`` are built on first use."""

    def __init__(self, spec: HouseSpec, model: mujoco.MjModel | None = None):
        self.spec = spec
        self._model = model

    @classmethod
    def load(cls, ref: HouseRef) -> "World":
        """Load the house ``ref`` names: from its directory, or regenerated from its seed.

        Raises ``UserError`` if the directory cannot be read or the spec no longer hashes to ``ref.spec_sha256``.
        """
        if ref.path is not None:
            directory = Path(ref.path)
            try:
                with open_regular(directory / "spec.json", "house file", HOUSE_FILE_MAX_BYTES, HOUSE_FIX) as f:
                    text = f.read().decode("utf-8")
                spec = HouseSpec.from_json(json.loads(text), directory / "spec.json")
                check_mjcf_files(directory / "house.xml")
                model = mujoco.MjModel.from_xml_path(str(directory / "house.xml"))
            except (OSError, ValueError) as err:
                raise UserError(
                    f"cannot load house {directory}: {err}; expected a folder written by objsearch generate"
                ) from None
            world = cls(spec, model)
        else:
            from objsearch.house.generate import generate_house

            house = generate_house(
                ref.seed,
                ref.size_class,
                ref.split,
                validate=False,
                generator=ref.generator or ("house-gen-2" if ref.room else "house-gen-1"),
                placement=ref.placement or "functional",
                room=ref.room,
            )
            world = cls(house.spec, house.model)
        if ref.spec_sha256 is not None and world.spec_sha256 != ref.spec_sha256:
            raise UserError(
                f"house {world.spec.house_id} no longer matches the benchmark (spec hash {world.spec_sha256[:12]} != "
                f"{ref.spec_sha256[:12]}): the house generator changed; use the objsearch version the suite was made with"
            )
        return world

    @property
    def house_id(self) -> str:
        """The house's id (from its spec)."""
        return self.spec.house_id

    @cached_property
    def spec_sha256(self) -> str:
        """sha256 of the house's canonical spec JSON (``spec_hash``)."""
        return spec_hash(self.spec)

    @property
    def model(self) -> mujoco.MjModel:
        """The house's compiled ``MjModel``, compiled from the spec on first use."""
        if self._model is None:
            from objsearch.house.mjcf import compile_house

            self._model, _ = compile_house(self.spec)
        return self._model

    @cached_property
    def graph(self) -> PoseGraph:
        """The house's pose graph, built from the spec on first use."""
        return build_pose_graph(self.spec)

    @cached_property
    def cell_rooms(self) -> np.ndarray:
        """The room id of every free cell of ``graph`` (int (P // 4,); -1 for a cell in no room,
        e.g. in a doorway): pose ``p`` stands in room ``cell_rooms[p // 4]``."""
        graph = self.graph
        xy = (graph.cells[:, ::-1] + 0.5) * GRID
        rooms = np.full(len(xy), -1, dtype=np.int64)
        for room in self.spec.rooms:
            inside = np.array([room.contains(float(x), float(y)) for x, y in xy], dtype=bool)
            rooms[inside & (rooms < 0)] = room.id
        return rooms
