"""What the tests of users' own houses and suite files share: the CLI in a subprocess, its
clean one-line errors, and two small generated houses with a suite file made from them."""

import subprocess
import sys
from pathlib import Path

BIN = Path(sys.executable).parent


def run(*args, cwd=None):
    """``BIN/args[0] args[1:]`` in a subprocess (its CompletedProcess, text output)."""
    return subprocess.run([str(BIN / args[0]), *args[1:]], capture_output=True, text=True, cwd=cwd, timeout=300)


def assert_clean_error(out, *needles):
    """Exit 2 with one line on stderr, no traceback, holding every one of ``needles``."""
    assert out.returncode == 2, (out.returncode, out.stderr)
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.stderr, out.stderr
    for needle in needles:
        assert needle in lines[0], (needle, lines[0])


def make_own_houses(work: Path, cache_dir: str) -> Path:
    """``work/houses/`` (two small houses, as objsearch generate writes them) and
    ``work/my-suite.json`` (20 episodes, seed 1) made from them; returns ``work``."""
    out = run(
        "objsearch", "generate", "--seed", "3", "--num", "2", "--rooms", "small", "--generator", "house-gen-1",
        "--no-preview", "--quiet", "--out", "houses", cwd=work,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    out = run(
        "objsearch", "suite", "make", "--houses", "houses", "--out", "my-suite.json", "--episodes", "20",
        "--seed", "1", "--cache-dir", cache_dir, cwd=work,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "objsearch-eval --suite my-suite.json" in out.stderr
    return work
