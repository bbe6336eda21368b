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
import stat
import tempfile
import time
from pathlib import Path

FULL_DISK = (errno.ENOSPC, errno.EDQUOT)


def full_disk_error(
    err: OSError, path: str | os.PathLike | None, elsewhere: str = "write elsewhere", needed: int | None = None
):
    """The ``UserError`` for ``err`` if it is a full disk (or quota) while writing ``path``,
    naming the path, the space ``needed`` (bytes, if known) and left, and the fix (free
    space, or ``elsewhere``: e.g. "choose another --out"); None for any other error."""
    from objsearch.errors import UserError

    if not isinstance(err, OSError) or err.errno not in FULL_DISK:
        return None
    where = Path(path).absolute() if path is not None else None
    folder = where.parent if where is not None else None
    while folder is not None and not folder.exists():
        folder = folder.parent
    try:
        free = f"{_megabytes(shutil.disk_usage(folder).free)} free" if folder is not None else "no space left"
    except OSError:
        free = "no space left"
    if needed is not None:
        free = f"{_megabytes(needed)} needed, {free}"
    what = f"cannot write {where}" if where is not None else "cannot write a file"
    return UserError(
        f"{what}: {err.strerror or 'no space left on device'} ({free}); free some space there or {elsewhere}"
    )


def _megabytes(size: int) -> str:
    return f"{size / 1e6:.1f} MB" if size >= 1e5 else f"{size / 1e3:.0f} KB"


@contextlib.contextmanager
def full_disk_as_error(path: str | os.PathLike, elsewhere: str = "write elsewhere", needed: int | None = None):
    """Turn a full disk while writing ``path`` in the block into ``full_disk_error``'s ``UserError``."""
    try:
        yield
    except OSError as err:
        full = full_disk_error(err, path, elsewhere, needed)
        if full is None:
            raise
        raise full from None


def reserve(path: str | os.PathLike) -> None:
    """Allocate the disk blocks of the file ``path`` up to its size (``os.posix_fallocate``),
    so that writing it through a memory map cannot hit a full disk, which would kill the
    process with SIGBUS: a full disk is an ``OSError`` (ENOSPC) here instead. Filesystems
    that cannot allocate ahead are left as they are."""
    fd = os.open(path, os.O_RDWR)
    try:
        os.posix_fallocate(fd, 0, os.fstat(fd).st_size)
    except OSError as err:
        if err.errno in FULL_DISK:
            raise
    except AttributeError:  # no posix_fallocate on this platform
        pass
    finally:
        os.close(fd)


_KINDS = {
    stat.S_IFDIR: "folder",
    stat.S_IFCHR: "character device",
    stat.S_IFBLK: "block device",
    stat.S_IFIFO: "FIFO (named pipe)",
    stat.S_IFSOCK: "socket",
}


def not_regular(path: str | os.PathLike) -> str | None:
    """What ``path`` is if it exists (following symlinks) and is not a regular file: ``folder``,
    ``character device``, ... (None for a regular file or nothing there)."""
    try:
        mode = os.stat(path).st_mode
    except (FileNotFoundError, NotADirectoryError):
        return None
    return None if stat.S_ISREG(mode) else _KINDS.get(stat.S_IFMT(mode), "special file")


def open_regular(path: str | os.PathLike, what: str, max_bytes: int | None = None, fix: str = "give a file's path"):
    """``path`` opened for reading in binary, if it is a regular file (following symlinks) of
    at most ``max_bytes``: a device (``/dev/zero``), FIFO, socket or folder is refused before a
    byte is read, and a FIFO without a writer does not block (opened non-blocking, checked with
    ``fstat``). ``UserError`` naming ``what`` (e.g. "checkpoint"), the path, the limit and ``fix``;
    a missing file raises ``FileNotFoundError`` as ``open`` does."""
    from objsearch.errors import UserError

    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = _KINDS.get(stat.S_IFMT(st.st_mode), "special file")
            raise UserError(f"{what} {path} is a {kind}, not a regular file; {fix}")
        if max_bytes is not None and st.st_size > max_bytes:
            raise UserError(
                f"{what} {path} is {_megabytes(st.st_size)}, above the limit of {_megabytes(max_bytes)}; {fix}"
            )
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def output_file(path: str | os.PathLike, elsewhere: str = "write elsewhere") -> Path:
    """The file that writing ``path`` replaces: ``path``, or, when ``path`` is a symlink, the
    file it points to (the link stays a link, and points to the new content). Refuses
    (``UserError``, naming the path and ``elsewhere``, the fix) a path that is, or points to,
    anything but a regular file: a folder, a character device (``/dev/null``), a FIFO, a
    socket. The one check of every output objsearch writes (``atomic_write``, ``check_writable``)."""
    from objsearch.errors import UserError

    path = Path(path)
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    kind = not_regular(target)
    if kind is not None:
        via = f" (a symlink to {target})" if target != path else ""
        raise UserError(
            f"cannot write {path}{via}: it is a {kind}, not a regular file, and objsearch replaces only "
            f"regular files; {elsewhere}"
        )
    return target


@contextlib.contextmanager
def atomic_write(path: str | os.PathLike, mode: str = "w", elsewhere: str = "write elsewhere"):
    """Open a temp file beside ``path``; on success rename it over ``path``, on error delete it
    (``path`` keeps what it held). ``path`` must be a regular file or nothing yet; a symlink's
    target is replaced, not the link (``output_file``). A full disk is a ``UserError`` naming
    ``path`` and the fix (``full_disk_error``)."""
    path = output_file(path, elsewhere)
    with full_disk_as_error(path, elsewhere):
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


def write_json(path: str | os.PathLike, obj, indent: int | None = 1, elsewhere: str = "write elsewhere") -> None:
    """Write ``obj`` as JSON atomically (``elsewhere``: see ``atomic_write``)."""
    with atomic_write(path, elsewhere=elsewhere) as f:
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
    it is deleted. The temp folder is ``.<name>.<host>.<pid>.XXXX.tmp`` and holds the marker
    file ``TEMP_MARKER`` until it is renamed, so that ``abandoned_temp_folders`` can tell one
    of a killed process, and never takes a folder that objsearch did not make for one."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    prefix = f".{path.name}.{socket.gethostname()}.{os.getpid()}."
    tmp = Path(tempfile.mkdtemp(dir=path.parent, prefix=prefix, suffix=".tmp"))
    try:
        (tmp / TEMP_MARKER).write_text(f"{MARKER_TEXT}{socket.gethostname()} {os.getpid()}\n")
        yield tmp
        (tmp / TEMP_MARKER).unlink(missing_ok=True)
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


TEMP_MARKER = ".objsearch-temp-folder"  # in every atomic_directory temp folder until it is renamed into place
MARKER_TEXT = "a temp folder of objsearch.fileio.atomic_directory: "


def is_temp_folder(folder: str | os.PathLike) -> bool:
    """Whether ``folder`` is a temp folder that ``atomic_directory`` made: a real folder (no
    symlink) holding the marker file it wrote, a regular file that starts with ``MARKER_TEXT``."""
    folder, marker = Path(folder), Path(folder, TEMP_MARKER)
    if folder.is_symlink() or not folder.is_dir() or marker.is_symlink() or not marker.is_file():
        return False
    try:
        with marker.open("rb") as f:
            return f.read(len(MARKER_TEXT)) == MARKER_TEXT.encode()
    except OSError:
        return False


def abandoned_temp_folders(parent: str | os.PathLike, max_age_hours: float = 24.0) -> list[Path]:
    """``atomic_directory`` temp folders in ``parent`` whose process is gone: on this host
    and not running, or (another host) untouched for ``max_age_hours``. A folder counts only
    if it holds the marker ``atomic_directory`` wrote (``is_temp_folder``), never by its name
    alone: a user's ``.notes.tmp`` folder beside the caches is never taken for one."""
    parent, host, out = Path(parent), socket.gethostname(), []
    for tmp in parent.glob(".*.tmp") if parent.is_dir() else []:
        if not is_temp_folder(tmp):
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
    if not folder:
        output_file(path, f"choose another {what}")
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
