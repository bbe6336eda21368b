"""Every public function, method and class of ``objsearch/`` has a docstring.

Public: a name that does not start with ``_``, defined at module level or in a public class
(nested public classes included); functions defined inside functions are not counted, and
dunder methods (``__init__`` and the like) start with ``_`` so are skipped. No module is
exempt (the fixed data under ``objsearch/*/data`` is not Python).
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "objsearch"
DEFS = (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)


def _missing(body: list[ast.stmt], path: Path, prefix: str = "") -> list[str]:
    out = []
    for node in body:
        if not isinstance(node, DEFS) or node.name.startswith("_"):
            continue
        if ast.get_docstring(node) is None:
            out.append(f"{path.relative_to(PACKAGE.parent)}:{node.lineno} {prefix}{node.name}")
        if isinstance(node, ast.ClassDef):
            out += _missing(node.body, path, f"{prefix}{node.name}.")
    return out


def test_public_definitions_have_docstrings():
    files = sorted(PACKAGE.rglob("*.py"))
    assert files, f"no modules under {PACKAGE}"
    missing = [m for path in files for m in _missing(ast.parse(path.read_text(), str(path)).body, path)]
    assert not missing, f"{len(missing)} public definitions without a docstring:\n" + "\n".join(missing)
