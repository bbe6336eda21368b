"""What ``objsearch generate`` may do with a house folder that is there already.

A house folder is named by split and seed only (``train_000042``: the house id, which the
house's spec, caches and suites record), so two generators, placements or sizes of one seed
want the same folder. ``write_house`` writes into a folder only what is safe: nothing there;
the same house (its ``spec.json`` and ``house.xml`` byte for byte: written again, or, with
other files beside it, left as it is); another house only with ``overwrite``
(``objsearch generate --overwrite``). A folder holding anything ``write_house`` did not
write (a user's file, a link) is never replaced, ``overwrite`` or not: nothing of a user's is
ever deleted."""

from __future__ import annotations

import json
import os
from pathlib import Path

from objsearch.errors import UserError

OWN_FILES = ("house.xml", "spec.json", "preview.png")  # and meshes/<category>/<variant>.obj
MESHES = "meshes"


def foreign_files(folder: Path) -> list[str]:
    """The paths in ``folder`` (relative, sorted) that ``write_house`` does not write: other
    than ``OWN_FILES`` and ``meshes/<category>/<variant>.obj``, or a link, or not a regular file."""
    out = []
    for top, dirs, files in os.walk(folder):
        rel = Path(top).relative_to(folder)
        depth = len(rel.parts)
        for name in dirs:  # os.walk does not enter links to folders: list them here
            inside = (depth == 0 and name == MESHES) or (depth == 1 and rel.parts[0] == MESHES)
            if Path(top, name).is_symlink() or not inside:
                out.append((rel / name).as_posix())
        dirs[:] = [d for d in dirs if not Path(top, d).is_symlink() and (rel / d).as_posix() not in out]
        for name in files:
            path = Path(top, name)
            ours = (depth == 0 and name in OWN_FILES) or (
                depth == 2 and rel.parts[0] == MESHES and name.endswith(".obj")
            )
            if not ours or path.is_symlink() or not path.is_file():
                out.append((rel / name).as_posix())
    return sorted(out)


def describe(spec: dict) -> str:
    """A house spec (its JSON) in a few words: ``house-gen-2, placement functional, size medium``."""
    extra = spec.get("extra") if isinstance(spec.get("extra"), dict) else {}
    words = [str(spec.get("generator_version", "?")), f"placement {extra.get('placement', 'functional')}"]
    if extra.get("room"):
        words.append(f"room {extra['room']}")
    elif spec.get("size_class"):
        words.append(f"size {spec['size_class']}")
    return ", ".join(words)


def stored_spec(folder: Path) -> dict | None:
    """The spec JSON in ``folder/spec.json`` (None: none, or not a spec)."""
    try:
        spec = json.loads((folder / "spec.json").read_text())
    except (OSError, ValueError):
        return None
    return spec if isinstance(spec, dict) else None


def _read(path: Path) -> str | None:
    try:
        return path.read_text()
    except (OSError, ValueError):
        return None


def check_house_folder(folder: Path, spec: dict, text: dict[str, str], overwrite: bool = False) -> bool:
    """Whether ``write_house`` should write the house ``spec`` (its JSON; ``text``: the
    ``spec.json`` and ``house.xml`` it writes) into ``folder``: True if nothing is there, the
    folder is empty, holds the same house and nothing else, or (``overwrite``) another house
    and nothing else; False if it holds the same house with other files beside it (left as it
    is). ``UserError`` naming the folder and the fix where it must not be replaced."""
    if not folder.exists() and not folder.is_symlink():
        return True
    fix = "choose another --out (a folder for each generator, placement or size)"
    if folder.is_symlink() or not folder.is_dir():
        raise UserError(f"{folder} is there and is not a house folder; it is left as it is: move it away, or {fix}")
    if not any(folder.iterdir()):
        return True
    same = all(_read(folder / name) == text[name] for name in ("spec.json", "house.xml"))
    foreign = foreign_files(folder)
    if same:
        return not foreign
    old = stored_spec(folder)
    if foreign:
        what = f"another house ({describe(old)})" if old is not None else "no house objsearch wrote"
        names = ", ".join(foreign[:5]) + (f" and {len(foreign) - 5} more" if len(foreign) > 5 else "")
        raise UserError(
            f"{folder} holds {what} and files objsearch generate did not write ({names}); it is left as it is: "
            f"move those files out (then --overwrite replaces the house), or {fix}"
        )
    refuse_other_house(folder, old, spec, overwrite)
    return True


def refuse_other_house(folder: Path, old: dict | None, new: dict, overwrite: bool) -> None:
    """``UserError`` unless ``overwrite``: ``folder`` holds the house ``old`` (its spec JSON;
    None: something without a readable spec) and the house ``new`` would replace it."""
    if overwrite:
        return
    what = f"another house ({describe(old)})" if old is not None else "no readable spec.json"
    raise UserError(
        f"{folder} holds {what}, not this one ({describe(new)}); pass --overwrite to replace it, or choose "
        "another --out (a folder for each generator, placement or size)"
    )


def precheck(folder: Path, wanted: dict, overwrite: bool) -> None:
    """Before any house is generated: refuse (``UserError``) a ``folder`` that ``write_house``
    will refuse for certain, its house of another generator, placement, size or room than
    ``wanted`` (spec JSON fields: ``generator_version``, ``extra.placement``, ``size_class``
    when one was asked for, ``extra.room``), so that a run of many seeds stops before the first."""
    old = stored_spec(folder) if folder.is_dir() and not folder.is_symlink() else None
    if old is None:
        return
    extra = old.get("extra") if isinstance(old.get("extra"), dict) else {}
    found = {"generator_version": old.get("generator_version"), "placement": extra.get("placement", "functional")}
    found |= {"size_class": old.get("size_class"), "room": extra.get("room")}
    if any(found[key] != value for key, value in wanted.items()):
        foreign = foreign_files(folder)
        if foreign:
            raise UserError(
                f"{folder} holds another house ({describe(old)}) and files objsearch generate did not write "
                f"({', '.join(foreign[:5])}); it is left as it is: move those files out, or choose another --out"
            )
        new = {"generator_version": wanted["generator_version"], "size_class": wanted.get("size_class")}
        new["extra"] = {"placement": wanted["placement"], "room": wanted.get("room")}
        refuse_other_house(folder, old, new, overwrite)
