import os
import shutil
import subprocess

import pytest

from objsearch.eval.runner import EvalConfig, evaluate


@pytest.fixture(scope="session")
def oracle_results():
    """A partial gridworld result (one split, two seeds): seconds to make."""
    return evaluate(EvalConfig(agent="oracle", splits=("unseen-goals",), seeds=(1, 5)), progress=False)


@pytest.fixture(scope="session")
def random_results():
    return evaluate(EvalConfig(agent="random", splits=("unseen-goals",), seeds=(1, 5)), progress=False)


@pytest.fixture(scope="session")
def full_oracle():
    """A full gridworld result: every split with the standard seeds (1500 episodes)."""
    return evaluate(EvalConfig(agent="oracle"), progress=False, batch=64)


@pytest.fixture(scope="session")
def full_random():
    return evaluate(EvalConfig(agent="random"), progress=False, batch=64)


@pytest.fixture
def page_dom(tmp_path):
    """A function: the DOM that headless Chromium builds from an HTML file (its scripts run).
    Skips where Chromium is missing, but fails on CI, which installs it (.ci/run)."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        if os.environ.get("CI"):
            pytest.fail("CI must have chromium (.ci/run installs Debian's package)")
        pytest.skip("chromium is not installed (apt-get install chromium)")
    flags = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        f"--user-data-dir={tmp_path / 'chromium-profile'}",
    ]

    def dom(page) -> str:
        out = subprocess.run(
            [browser, *flags, "--dump-dom", page.as_uri()], capture_output=True, text=True, timeout=120
        )
        assert out.returncode == 0 and "</html>" in out.stdout, out.stderr[-2000:]
        return out.stdout

    return dom
