"""Writing files so that nothing half-written is ever left behind."""

from __future__ import annotations

import contextlib
import csv
import errno
import json
import os
import re
import shutil
import socket
import tempfile
import time
from pathlib import Path


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "w"):
    """Open a temp file beside ``path``; on success rename it over ``path``, on error delete it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the file the usual mode
    try:
        with os.fdopen(fd, mode) as f:
            yield f
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_json(path: str | os.PathLike, obj, indent: int | None = 1) -> None:
    """Write ``obj`` as JSON atomically."""
    with atomic_write(path) as f:
        json.dump(obj, f, indent=indent)
        f.write("\n")


def write_csv(path: str | os.PathLike, fieldnames, rows) -> None:
    """Write ``rows`` (dicts) as CSV with a header atomically."""
    with atomic_write(path) as f:
        writer = csv.DictWriter(f, fieldnames=fieldnames)
        writer.writeheader()
        writer.writerows(rows)


@contextlib.contextmanager
def atomic_directory(path: str | os.PathLike):
    """Yield a temp folder beside ``path``; on success it replaces ``path`` (whatever was
    there, also a folder another process put there meanwhile: the last one wins), on error
    it is deleted. The temp folder is ``.<name>.<host>.<pid>.XXXX.tmp``, so that
    ``abandoned_temp_folders`` can tell one of a killed process."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    prefix = f".{path.name}.{socket.gethostname()}.{os.getpid()}."
    tmp = Path(tempfile.mkdtemp(dir=path.parent, prefix=prefix, suffix=".tmp"))
    try:
        yield tmp
        old = tmp.with_name(tmp.name[: -len(".tmp")] + ".old.tmp")
        while True:
            try:
                os.replace(tmp, path)  # fails if a (non-empty) folder is there
                break
            except OSError as err:
                if err.errno not in (errno.ENOTEMPTY, errno.EEXIST, errno.ENOTDIR):
                    raise
            try:
                os.replace(path, old)  # move it aside (a folder or a file), then try again
            except FileNotFoundError:
                continue
            if old.is_dir() and not old.is_symlink():
                shutil.rmtree(old)
            else:
                old.unlink()
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def abandoned_temp_folders(parent: str | os.PathLike, max_age_hours: float = 24.0) -> list[Path]:
    """``atomic_directory`` temp folders in ``parent`` whose process is gone: on this host
    and not running, or (another host, or an old name without a pid) untouched for
    ``max_age_hours``."""
    parent, host, out = Path(parent), socket.gethostname(), []
    for tmp in parent.glob(".*.tmp") if parent.is_dir() else []:
        if not tmp.is_dir():
            continue
        mine = re.search(rf"\.{re.escape(host)}\.(\d+)\.", tmp.name)
        if mine:
            try:
                os.kill(int(mine.group(1)), 0)
                continue  # running
            except ProcessLookupError:
                out.append(tmp)
                continue
            except PermissionError:
                continue  # running, another user's
        try:
            newest = max([tmp.stat().st_mtime] + [f.stat().st_mtime for f in tmp.iterdir()])
        except OSError:
            continue
        if time.time() - newest > max_age_hours * 3600:
            out.append(tmp)
    return out


def check_writable(path: str | os.PathLike, what: str, folder: bool = False) -> None:
    """Refuse (``UserError``), before any work, an output ``path`` that cannot be written:
    a file path that is a folder (``folder`` False), a folder path that is a file
    (``folder`` True), or a place without write permission. ``what`` names it (a flag)."""
    from objsearch.errors import UserError

    path = Path(path).absolute()
    if not folder and path.is_dir():
        raise UserError(f"{what} {path} is a folder; give a file path, e.g. {path / 'results.json'}")
    if folder and path.exists() and not path.is_dir():
        raise UserError(f"{what} {path} is a file, not a folder; give a folder path")
    target = path if folder and path.is_dir() else path.parent
    while not target.exists():  # the folders that would be made: check the first that is there
        target = target.parent
    if not target.is_dir():
        raise UserError(f"{what} {path}: {target} is a file, not a folder; choose another place")
    try:  # a real write: permission bits say nothing for root, on read-only filesystems or in /proc
        with tempfile.TemporaryFile(dir=target):
            pass
    except OSError as err:
        raise UserError(
            f"{what} {path}: cannot write in {target} ({err.strerror}); choose a place you can write to"
        ) from None
    if not folder and path.exists() and not os.access(path, os.W_OK):
        raise UserError(f"{what} {path}: no permission to overwrite it; choose another file")
