"""What ``leaderboard add`` already checked: a memo, in the board's folder (``MEMO``), of the
stored entries that passed every check, so that adding one entry checks that entry and not
again every stored one.

A memo line is keyed by the sha256 of the entry file's name and bytes and of the checking code (every
``objsearch`` source file and shipped suite file): an entry edited by hand, or a new objsearch,
is checked again. The memo only spares ``add``'s re-check of entries it stored itself;
``objsearch leaderboard check`` and ``verify`` read every entry afresh.
"""

from __future__ import annotations

import functools
import hashlib
import json
from pathlib import Path

MEMO = ".checked.json"  # in the board's folder, beside submissions/ (not committed: .gitignore)


@functools.cache
def code_digest() -> str:
    """sha256 of the checking code: objsearch's source files and its shipped suite files (by content)."""
    package = Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    for path in sorted([*package.rglob("*.py"), *package.glob("sim/data/*.json")]):
        h.update(str(path.relative_to(package)).encode() + b"\0" + path.read_bytes() + b"\0")
    return h.hexdigest()


def entry_key(path: Path, raw: bytes) -> str:
    """The memo's key of the entry file ``path`` (its name is checked too) holding ``raw``, under this code."""
    return hashlib.sha256(f"{code_digest()}\0{path.parent.name}/{path.name}\0".encode() + raw).hexdigest()


class Memo:
    """The memo of the board ``root``: entry key -> the entry's ``content_sha256``."""

    def __init__(self, root: str | Path):
        self.path = Path(root, MEMO)
        try:
            memo = json.loads(self.path.read_text(encoding="utf-8"))
            self.digests = {str(k): str(v) for k, v in memo.get(code_digest(), {}).items()}
        except (OSError, ValueError, AttributeError):  # none yet, unreadable or not ours: check everything
            self.digests = {}

    def content_sha256(self, path: Path, check) -> str:
        """The ``content_sha256`` of the stored entry ``path``: remembered if its bytes passed
        under this code, else ``check(path)`` (its results, or an error) is called first."""
        from objsearch.leaderboard.validate import content_sha256

        key = entry_key(path, path.read_bytes())
        if key not in self.digests:
            self.digests[key] = content_sha256(check(path))
        return self.digests[key]

    def load(self, path: Path) -> dict:
        """The results in the stored entry ``path``: parsed at once if the memo knows its bytes
        (they passed ``load_submission``'s limits), else by ``load_submission``."""
        from objsearch.leaderboard.parsing import load_submission

        raw = path.read_bytes()
        if entry_key(path, raw) in self.digests:
            return json.loads(raw)
        return load_submission(path)

    def remember(self, path: Path, digest: str) -> None:
        """Remember that the stored entry ``path`` as it is now (with ``content_sha256`` ``digest``) passed."""
        self.digests[entry_key(path, path.read_bytes())] = digest

    def save(self, keep: set[str] | None = None) -> None:
        """Write the memo (only this code's lines; ``keep``: only these digests' lines) atomically;
        a board folder that cannot take it is left as it is (the memo only saves time)."""
        from objsearch.errors import UserError
        from objsearch.fileio import write_json

        lines = {k: v for k, v in self.digests.items() if keep is None or v in keep}
        try:
            write_json(self.path, {code_digest(): lines}, indent=None)
        except (OSError, UserError):
            pass
