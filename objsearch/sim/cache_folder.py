"""A cache folder's life: built once in a temp folder under a lock and renamed into place,
checked against the sizes and digests its ``meta.json`` records, rebuilt when stale or
damaged, and measured for ``objsearch cache``. What goes in the folders (rendered frames,
predictions) is ``objsearch.sim.cache``'s."""

from __future__ import annotations

import contextlib
import fcntl
import io
import json
import os
import re
import shutil
import sys
from pathlib import Path

import numpy as np
from tqdm import tqdm

from objsearch.digests import sha256_file
from objsearch.fileio import abandoned_temp_folders, atomic_directory, full_disk_as_error, reserve


def ensure_folder(directory: Path, expected: dict, layers: dict, fill, what: str) -> dict:
    """Keep ``directory`` if its ``meta.json`` matches ``expected`` and its files are intact
    (``check_folder``); otherwise rebuild it: ``fill`` writes the arrays into a temp folder
    that is then renamed into place. One process at a time (a lock file beside it).
    Returns the metadata (``expected`` plus the files' sizes and digests)."""

    def intact() -> dict:  # remember it, so that this process does not hash it again while it is unchanged
        _VERIFIED[directory] = (_signature(directory, layers), expected)
        return json.loads((directory / "meta.json").read_text())

    signature = _signature(directory, layers)
    if signature is not None and _VERIFIED.get(directory) == (signature, expected):
        return json.loads((directory / "meta.json").read_text())  # checked in this process, and unchanged since
    if check_folder(directory, expected, layers) is None:  # the usual case: no lock (a cache may be read-only)
        return intact()
    with locked(directory):
        problem = check_folder(directory, expected, layers)  # again: another process may have built it meanwhile
        if problem is None:
            return intact()
        if (directory / "meta.json").exists():
            print(f"{what}: {problem}; rebuilding {directory}", file=sys.stderr)
        for stale in abandoned_temp_folders(directory.parent):
            shutil.rmtree(stale, ignore_errors=True)
            print(f"removed {stale} (left by an interrupted build)", file=sys.stderr)
        needed = sum(np.dtype(dtype).itemsize * int(np.prod(shape)) for dtype, shape in layers.values())
        elsewhere = "pass a cache folder on a disk with room (--cache-dir or $OBJSEARCH_CACHE)"
        with full_disk_as_error(directory, elsewhere, needed), atomic_directory(directory) as tmp:
            fill(tmp)
            meta = {**expected, "files": {f"{name}.npy": _file_record(tmp / f"{name}.npy") for name in layers}}
            (tmp / "meta.json").write_text(json.dumps(meta, indent=1) + "\n")
        size = sum(f["bytes"] for f in meta["files"].values())
        print(f"{what}: {format_size(size)} in {_home_short(directory)}", file=sys.stderr)
        return intact()


_VERIFIED: dict[Path, tuple] = {}  # cache folder -> (its files' signature, metadata) when its digests last matched


def _signature(directory: Path, layers: dict) -> tuple | None:
    """Size, mtime and inode of a cache's files: a folder whose signature is unchanged since
    its digests were checked in this process is not hashed again (every env of a batched
    evaluation opens every house's cache)."""
    try:
        stats = [os.stat(directory / name) for name in ["meta.json", *(f"{layer}.npy" for layer in layers)]]
    except OSError:
        return None
    return tuple((st.st_size, st.st_mtime_ns, st.st_ino) for st in stats)


def check_folder(
    directory: Path, expected: dict | None = None, layers: dict | None = None, digests: bool = True
) -> str | None:
    """What is wrong with the cache ``directory`` (None: nothing): no or unreadable
    ``meta.json``, metadata other than ``expected`` (None: any), a layer file missing, of
    another size, dtype or shape than ``layers`` ({name: (dtype, shape)}; None: any) or
    whose sha256 differs from the one recorded when it was built (``digests``)."""
    try:
        meta = json.loads((directory / "meta.json").read_text())
        files = meta["files"]
        if not isinstance(files, dict) or not files:
            raise ValueError
    except FileNotFoundError:
        return "no meta.json"
    except (OSError, ValueError, KeyError, TypeError):
        return "unreadable meta.json"
    if expected is not None and {k: v for k, v in meta.items() if k != "files"} != expected:
        return "stale (made for another version, house or camera)"
    if layers is not None and set(files) != {f"{name}.npy" for name in layers}:
        return "stale (other layer files)"
    for name, record in files.items():
        path = directory / name
        try:
            if path.stat().st_size != record["bytes"]:
                return f"{name} has {path.stat().st_size} bytes, not {record['bytes']} (truncated or overwritten)"
            problem = header_problem(path, None if layers is None else layers[name[: -len(".npy")]])
            if problem is not None:
                return f"{name} {problem}"
            if digests and sha256_file(path) != record["sha256"]:
                return f"{name} differs from what was built (sha256 mismatch)"
        except FileNotFoundError:
            return f"{name} is missing"
        except (OSError, ValueError, KeyError, TypeError) as err:
            return f"{name} is unreadable ({err})"
    return None


CACHE_VERSION_NAME = re.compile(r"(?:predicted-)?cache-v\d+")  # every version a cache's meta.json has recorded
CACHE_NAME_REST = re.compile(r"[0-9a-f]{16}(?P<pred>-pred-.+)?")  # a cache folder's name after "<house_id>-"


def cache_meta(directory: Path) -> dict | None:
    """The ``meta.json`` of ``directory`` if it is a cache folder that objsearch made, else
    None: the file a build wrote there, with a cache version (``cache-vN``, or
    ``predicted-cache-vN``) and the house id that the folder's name starts with, the rest of
    the name being the key (16 hex digits, then ``-pred-<predictor key>`` for predictions).
    A folder is never taken for a cache by its name alone, or for being a folder: ``objsearch
    cache clear`` removes only these, whatever else the cache folder holds."""
    try:
        meta = json.loads((directory / "meta.json").read_text())
    except (OSError, ValueError):  # not there, unreadable, not JSON
        return None
    version, house = (meta.get("version"), meta.get("house_id")) if isinstance(meta, dict) else (None, None)
    if not isinstance(version, str) or not isinstance(house, str) or not CACHE_VERSION_NAME.fullmatch(version):
        return None
    rest = (
        CACHE_NAME_REST.fullmatch(directory.name[len(house) + 1 :]) if directory.name.startswith(f"{house}-") else None
    )
    if rest is None:
        return None
    return meta if bool(rest["pred"]) == version.startswith("predicted-") else None


def retire_folder(old: Path, new: Path, ours: list[str]) -> str:
    """Empty the cache folder ``old`` that ``new`` replaces, and say what became of it: every
    file and folder in it but ``ours`` (what the cache itself wrote) is moved into ``new``
    (one that ``new`` holds already, or that cannot be moved, e.g. to another filesystem,
    stays), then ``ours`` are deleted, and ``old`` too once it is empty. Nothing else is
    ever deleted; a symlink ``old`` is left as it is (its target may be anyone's)."""
    if old.is_symlink():
        return f"left {old}: a link to {os.path.realpath(old)}, which objsearch does not delete through; remove both"
    with locked(old):  # not while another process converts it
        for path in sorted(old.iterdir()) if old.is_dir() else []:
            if path.name not in ours and not (new / path.name).exists() and not (new / path.name).is_symlink():
                with contextlib.suppress(OSError):  # e.g. EXDEV: it stays where it is
                    os.rename(path, new / path.name)
        for name in ours:
            if (old / name).is_file() and not (old / name).is_symlink():
                (old / name).unlink()
        left = sorted(p.name for p in old.iterdir()) if old.is_dir() else []
        if not left:
            with contextlib.suppress(FileNotFoundError):
                old.rmdir()
            return f"removed {old}"
    return f"left {old}: it still holds {', '.join(left[:6])}{' ...' if len(left) > 6 else ''}, not the cache's"


def npy_header(dtype, shape) -> bytes:
    """The ``.npy`` header numpy writes for a C-order array of ``dtype`` and ``shape`` (as
    ``fill_arrays``' ``open_memmap`` wrote every cache file)."""
    header = {"descr": np.lib.format.dtype_to_descr(np.dtype(dtype)), "fortran_order": False, "shape": tuple(shape)}
    out = io.BytesIO()
    try:
        np.lib.format.write_array_header_1_0(out, header)
    except ValueError:  # too long for version 1.0
        out = io.BytesIO()
        np.lib.format.write_array_header_2_0(out, header)
    return out.getvalue()


def header_problem(path: Path, layer: tuple | None = None) -> str | None:
    """What is wrong with the ``.npy`` header of ``path`` (None: nothing), without trusting
    numpy's parser with a damaged header (one flipped byte can make it raise anything, e.g.
    ``tokenize.TokenError``): with ``layer`` ((dtype, shape)), its bytes must be the ones
    written for it; without, it must parse, be C order and match the file's size."""
    size = path.stat().st_size
    with open(path, "rb") as f:
        if layer is not None:
            expected = npy_header(*layer)
            found = f.read(len(expected))
            if found == expected and size == len(expected) + np.dtype(layer[0]).itemsize * int(np.prod(layer[1])):
                return None
            return f"has a damaged .npy header or size (not {np.dtype(layer[0])} {tuple(layer[1])}: {found[:80]!r})"
        try:
            version = np.lib.format.read_magic(f)
            read = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            shape, fortran_order, dtype = read(f)
            offset = f.tell()
        except Exception as err:  # noqa: BLE001 - whatever numpy's parser makes of damaged bytes
            return f"has a damaged .npy header ({type(err).__name__}: {str(err)[:120]})"
    if fortran_order or offset + dtype.itemsize * int(np.prod(shape)) != size:
        return f"has a damaged .npy header or size ({dtype} {shape} in {size} bytes)"
    return None


def _file_record(path: Path) -> dict:
    return {"bytes": path.stat().st_size, "sha256": sha256_file(path)}


@contextlib.contextmanager
def locked(directory: Path):
    """Hold an exclusive lock on ``.<name>.lock`` beside ``directory`` (waiting for it);
    the lock file is removed when it is released."""
    path = directory.parent / f".{directory.name}.lock"
    while True:
        try:
            directory.parent.mkdir(parents=True, exist_ok=True)
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as err:
            from objsearch.errors import UserError

            raise UserError(
                f"cache {directory} needs building but {directory.parent} is not writable ({err.strerror}); "
                "pass a cache folder you can write to (--cache-dir or $OBJSEARCH_CACHE)"
            ) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
            try:  # its holder removed it as we waited: lock the new one
                if os.stat(path).st_ino == os.fstat(fd).st_ino:
                    break
            except FileNotFoundError:
                pass
        except BaseException:
            os.close(fd)
            raise
        os.close(fd)
    try:
        yield
    finally:
        os.unlink(path)  # while still held: whoever waits on it sees it is gone and locks a new one
        os.close(fd)


def folder_bytes(path: Path) -> int:
    """Total size in bytes of the files under ``path``."""
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file())


def format_size(size: int) -> str:
    """``size`` bytes as whole MB (from 1 MB on) or KB, e.g. ``12 MB``."""
    return f"{size / 1e6:.0f} MB" if size >= 1e6 else f"{size / 1e3:.0f} KB"


def _home_short(path: Path) -> str:
    home = str(Path.home())
    text = str(path)
    return "~" + text[len(home) :] if text.startswith(home + os.sep) else text


def fill_arrays(folder: Path, layers: dict, batches, desc: str, progress: bool) -> None:
    """Create ``<name>.npy`` memory maps of ``layers`` ({name: (dtype, shape)}) in ``folder``
    and fill them from ``batches`` of (first pose, {field: values}): a field is a layer's
    name, or a field of a layer's record dtype (every layer with records is filled from
    the batches' values of its fields). The files' space is reserved first: a full disk is
    an ``OSError`` here, not a SIGBUS while filling."""
    arrays = {
        name: np.lib.format.open_memmap(folder / f"{name}.npy", mode="w+", dtype=dtype, shape=shape)
        for name, (dtype, shape) in layers.items()
    }
    for name in arrays:
        reserve(folder / f"{name}.npy")
    total = len(next(iter(arrays.values())))
    targets = {name: array for name, array in arrays.items() if array.dtype.names is None}
    targets.update({field: array[field] for array in arrays.values() for field in array.dtype.names or ()})
    with tqdm(total=total, desc=desc, unit="pose", disable=not progress or None) as bar:
        for start, values in batches:
            for name, value in values.items():
                targets[name][start : start + len(value)] = value
            bar.update(len(value))
    del targets
    for array in arrays.values():
        array.flush()
    del arrays  # close the memory maps before the files are hashed
