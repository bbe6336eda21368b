"""Checkpoints are data, not code: every ``.pt`` file objsearch writes or reads goes here.

Files are read with ``torch.load(weights_only=True)``, which unpickles tensors and plain
Python data only, so a file can never run code when it is opened. numpy arrays (replay
memories, option state) are stored as tensors marked ``{"__ndarray__": tensor}``, numpy
scalars as Python numbers, and restored on reading. A file that cannot be read (missing,
empty, truncated, damaged, not a checkpoint, or holding something other than data) is a
``UserError`` naming the file and what was expected. Every file written is recorded in its
folder's ``SHA256SUMS`` and checked against it when read (``objsearch.digests``).
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
from pathlib import Path

import numpy as np
import torch

from objsearch import digests
from objsearch.errors import UserError
from objsearch.fileio import atomic_write, open_regular

_ARRAY = "__ndarray__"
MAX_BYTES = 8 * 2**30  # a checkpoint read: far above any training state objsearch writes


def to_saved(obj):
    """``obj`` with numpy arrays as marked tensors and numpy scalars as Python numbers."""
    if isinstance(obj, np.ndarray):
        return {_ARRAY: torch.from_numpy(np.ascontiguousarray(obj))}
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, dict):
        return {k: to_saved(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return type(obj)(to_saved(v) for v in obj)
    return obj


def from_saved(obj):
    """The inverse of ``to_saved``."""
    if isinstance(obj, dict):
        if set(obj) == {_ARRAY}:
            return obj[_ARRAY].numpy()
        return {k: from_saved(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return type(obj)(from_saved(v) for v in obj)
    return obj


def save(path: str | os.PathLike, obj) -> None:
    """Write ``obj`` (tensors, numpy arrays, plain data) to ``path`` atomically, and record
    its digest in ``SHA256SUMS`` beside it."""
    with atomic_write(path, "wb") as f:
        torch.save(to_saved(obj), f)
    digests.record(path)


def load(path: str | os.PathLike, expected: str):
    """Read a file written by ``save`` (or any weights-only ``torch.save``); ``expected``
    says what it should be, for the error message (e.g. "a policy.pt written by objsearch train")."""
    path = Path(path)
    try:
        with open_regular(path, "checkpoint", MAX_BYTES, f"expected {expected}"):
            pass  # a regular file within the limit: never a device or FIFO read forever
        digests.verify(path)
        return from_saved(torch.load(path, map_location="cpu", weights_only=True))
    except FileNotFoundError:
        raise UserError(f"checkpoint {path} does not exist; expected {expected}") from None
    except IsADirectoryError:
        raise UserError(f"checkpoint {path} is a folder; expected {expected}") from None
    except UserError:
        raise
    except Exception as err:  # torch raises many kinds for a damaged, foreign or code-carrying file
        first = str(err).strip().splitlines()[0] if str(err).strip() else ""
        reason = (
            first
            if first and "weights_only" not in first
            else "not a weights-only checkpoint (damaged, or it holds code)"
        )
        if path.stat().st_size == 0:
            reason = "the file is empty"
        raise UserError(f"cannot read checkpoint {path}: {reason}; expected {expected}") from None


def policy_path(path: str | os.PathLike, file_name: str = "policy.pt") -> Path:
    """``path`` itself, or ``file_name`` inside it when ``path`` is a (training run) folder; a
    ``UserError`` naming the fix if there is no such file."""
    path = Path(path)
    if path.is_dir():
        path = path / file_name
    if not path.exists():
        raise UserError(f"checkpoint {path} does not exist; pass a {file_name} or a training run directory")
    return path


@contextlib.contextmanager
def fitting(path: str | os.PathLike, expected: str):
    """Interpret a loaded file's contents inside this block: a missing field, a wrong type or
    weights of another shape (``KeyError``, ``TypeError``, ``ValueError``, ``RuntimeError``
    from ``load_state_dict``) become a ``UserError`` naming the file and what was expected."""
    try:
        yield
    except (KeyError, TypeError, ValueError, AttributeError, RuntimeError) as err:
        reason = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise UserError(
            f"checkpoint {path} does not hold what it should ({type(err).__name__}: {reason[:200]}); "
            f"expected {expected}"
        ) from None


def resume(
    path: str | os.PathLike, config, restore, budget: str | None = None, expected: str = "a training run's state.pt"
):
    """Resume a training run from its ``state.pt`` at ``path``: read it, refuse one written
    with another ``config`` (a dataclass with ``to_json``/``from_json``; the field ``budget``,
    the run's length, may differ: a rerun extends it), then ``restore(state)``. Contents that
    do not fit are a ``UserError``, as in ``fitting``."""
    path = Path(path)
    state = load(path, expected)
    with fitting(path, expected):
        saved = type(config).from_json(state["config"], f"{path}")
        if budget is not None:
            saved = dataclasses.replace(saved, **{budget: getattr(config, budget)})
        if saved != config:
            diff = [f for f, v in config.to_json().items() if saved.to_json().get(f) != v]
            raise UserError(
                f"{path.parent} holds a run with another config (fields {', '.join(diff)}); "
                "pass another --out, the same settings, or --fresh to start over"
            )
        restore(state)
