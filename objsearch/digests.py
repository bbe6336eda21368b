"""Weights are verified before they are trusted: each folder's ``SHA256SUMS``.

Every checkpoint file objsearch writes (``policy.pt``, ``state.pt``, ``grg.npz``,
``model.pt``) gets its sha256 recorded in ``SHA256SUMS`` beside it, in the format of
``sha256sum`` (so ``sha256sum -c SHA256SUMS`` checks a folder by hand). Reading a file that
``SHA256SUMS`` lists checks it first: flipped bytes, a truncated copy or a file replaced
after training are refused, naming the file and the fix, instead of loading silently. A
file with no entry (copied alone, or written by other code) loads unverified.

The digest of what an agent loaded is written into its results (``weights_sha256``), so a
submission names the exact weights it used.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from objsearch.errors import UserError
from objsearch.fileio import atomic_write, open_regular

SUMS = "SHA256SUMS"


def sha256_file(path: str | os.PathLike) -> str:
    """sha256 of the file at ``path``, as hex (read in 1 MiB blocks). Only a regular file is
    read (``fileio.open_regular``): ``/dev/zero`` or a FIFO given as a checkpoint is a
    ``UserError``, not an endless read."""
    h = hashlib.sha256()
    with open_regular(path, "file", fix="give the path of a regular file") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def recorded(folder: str | os.PathLike) -> dict[str, str]:
    """File name -> sha256 of a folder's ``SHA256SUMS`` (empty if it has none)."""
    path = Path(folder) / SUMS
    try:
        text = path.read_text()
    except FileNotFoundError:
        return {}
    except (OSError, UnicodeDecodeError) as err:
        raise UserError(f"cannot read {path}: {err}; delete it to load the folder's files unverified") from None
    sums = {}
    for number, line in enumerate(text.splitlines(), 1):
        digest, sep, name = line.partition("  ")
        if not sep or len(digest) != 64 or not name:
            raise UserError(
                f"{path} line {number} is not `SHA256  NAME`; restore the file, or delete it to load "
                "the folder's files unverified"
            )
        sums[name.lstrip("*")] = digest
    return sums


def record(path: str | os.PathLike) -> str:
    """Write ``path``'s sha256 into ``SHA256SUMS`` beside it (replacing its entry); return it."""
    path = Path(path)
    digest = sha256_file(path)
    sums = {**recorded(path.parent), path.name: digest}
    with atomic_write(path.parent / SUMS) as f:
        f.writelines(f"{sums[name]}  {name}\n" for name in sorted(sums))
    return digest


def verify(path: str | os.PathLike) -> str:
    """The sha256 of ``path``, after checking it against ``SHA256SUMS`` beside it if that lists it."""
    path = Path(path)
    digest = sha256_file(path)
    expected = recorded(path.parent).get(path.name)
    if expected is not None and expected != digest:
        raise UserError(
            f"{path} does not match its digest in {path.parent / SUMS} (sha256 {digest[:12]}, recorded "
            f"{expected[:12]}): the file is damaged or was changed after it was written; restore it "
            "(git checkout, or copy it again), or retrain"
        )
    return digest


def of_files(paths) -> str:
    """One sha256 naming several files (what an agent loaded): over their ``SHA256SUMS``
    lines, sorted by name."""
    lines = sorted(f"{sha256_file(path)}  {Path(path).name}\n" for path in paths)
    return hashlib.sha256("".join(lines).encode()).hexdigest()
