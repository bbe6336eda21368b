"""Every checkpoint (``agents/checkpoints/...``) and leaderboard file or entry that the docs
name exists: a path, ``house-single/{a3c,hrl_grg}/predicted/`` (each of the braces), a
``SUITE/NAME`` pair, and an entry name such as ``a3c_predicted_trained``."""

import re
from pathlib import Path

from objsearch.eval.suites import SUITES

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted([ROOT / "README.md", ROOT / "DEVELOPERS.md", *(ROOT / "docs").glob("*.md")])
# a path from the repository root, not the tail of another (objsearch/leaderboard/validate.py)
PATH = re.compile(r"(?<![\w./-])(?:agents/checkpoints|leaderboard)/[\w.{},/<>*-]*")
TICKED = re.compile(r"`([^`\s]+)`")
ENTRY = re.compile(r"[a-z0-9_]+_predicted(?:_trained)?")  # names only `leaderboard add` gives
PLACEHOLDER = ("<", ">", "*", "my_agent")  # <suite>/<agent>/, the reader's own agent
CAPS = re.compile(r"/(?:SUITE|METHOD|AGENT|ENTRY|NAME)\b")  # agents/checkpoints/SUITE/METHOD: placeholders


def expand(path: str) -> list[str]:
    """``a/{b,c}/d`` as ``a/b/d`` and ``a/c/d``."""
    braces = re.search(r"\{([^{}]*)\}", path)
    if not braces:
        return [path]
    head, tail = path[: braces.start()], path[braces.end() :]
    return [p for alt in braces.group(1).split(",") for p in expand(head + alt + tail)]


def named(page: Path) -> list[tuple[int, str]]:
    """(line, what must exist, relative to the root) for each path, pair or entry the page names."""
    out = []
    for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
        for match in PATH.finditer(line):
            if not any(p in match.group(0) for p in PLACEHOLDER) and not CAPS.search(match.group(0)):
                out += [(number, p.rstrip(".,:;/")) for p in expand(match.group(0).rstrip(".,:;"))]
        for token in TICKED.findall(line):
            suite, _, name = token.partition("/")
            if suite in SUITES and re.fullmatch(r"[a-z0-9_]+", name) and "my_agent" not in name:
                out.append((number, f"{suite}/{name}"))  # an entry or a checkpoint of that suite
            elif ENTRY.fullmatch(token):
                out.append((number, f"*/{token}"))
    return out


def exists(thing: str) -> bool:
    if thing.startswith("*/"):
        return any((ROOT / "leaderboard" / "submissions").glob(f"*/{thing[2:]}.json"))
    if thing.split("/")[0] in SUITES:
        return (ROOT / "leaderboard" / "submissions" / f"{thing}.json").is_file() or (
            ROOT / "agents" / "checkpoints" / thing
        ).is_dir()
    return (ROOT / thing).exists()


def test_every_checkpoint_and_entry_the_docs_name_exists():
    missing = [f"{p.relative_to(ROOT)}:{n} {thing}" for p in PAGES for n, thing in named(p) if not exists(thing)]
    assert not missing, "the docs name checkpoints or leaderboard entries that do not exist:\n" + "\n".join(missing)


def test_the_patterns_find_paths_pairs_and_entries(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "`agents/checkpoints/house-single/{a3c,hrl_grg}/predicted/`, see objsearch/leaderboard/validate.py\n"
        "`house-single/frontier` and `hrl_grg_predicted_trained`; agents/checkpoints/<suite>/<agent>/.\n"
        "leaderboard/submissions/house-single/my_agent.json and leaderboard/README.md.\n"
        "agents/checkpoints/SUITE/METHOD/ and leaderboard/submissions/SUITE/ENTRY.json are placeholders.\n"
    )
    assert named(page) == [
        (1, "agents/checkpoints/house-single/a3c/predicted"),
        (1, "agents/checkpoints/house-single/hrl_grg/predicted"),
        (2, "house-single/frontier"),
        (2, "*/hrl_grg_predicted_trained"),
        (3, "leaderboard/README.md"),
    ]
    assert [exists(t) for _, t in named(page)] == [True, False, True, False, True]
