"""The distribution as a user gets it: every package folder and data file in the wheel, the
code finding its data in an installed copy, the two commands, and every registered agent
built by name and playing an episode of a tiny suite."""

import configparser
import json
import os
import shutil
import subprocess
import sys
import zipfile
from importlib.metadata import distribution, entry_points
from pathlib import Path

import numpy as np
import pytest
import tomllib

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
INSTALLED_NAME = {"objsearch": "objsearch", "agents": "objsearch_agents"}  # source folder -> package


def test_every_package_folder_is_listed_in_pyproject():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    found = set()
    for top, name in (("objsearch", "objsearch"), ("agents", "objsearch_agents")):
        for init in (ROOT / top).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / top).parts
            found.add(".".join((name, *rel)))
    assert found == listed, f"add to pyproject.toml [tool.setuptools] packages: {sorted(found - listed)}"


def package_files(top: str) -> list[Path]:
    """The files under ``top`` that a clone holds (tracked, or new and not ignored); every file
    under it when this is no git checkout."""
    try:
        listed = (
            subprocess.run(
                ["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z", top],
                cwd=ROOT,
                capture_output=True,
                check=True,
            )
            .stdout.decode()
            .split("\0")
        )
        paths = [ROOT / name for name in listed if name]
    except (OSError, subprocess.CalledProcessError):
        paths = [p for p in (ROOT / top).rglob("*") if "__pycache__" not in p.parts]
    return [p for p in paths if p.is_file()]


def shipped_data(top: str, name: str) -> set[Path]:
    """The files of package-data ``name`` (folder ``top``): setuptools expands its patterns
    with glob from the package's folder, as here."""
    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"].get(name, [])
    return {path for pattern in patterns for path in (ROOT / top).glob(pattern) if path.is_file()}


def test_every_data_file_is_listed_in_package_data():
    for top, name in (("objsearch", "objsearch"), ("agents", "objsearch_agents")):
        data = {p for p in package_files(top) if p.suffix != ".py"}
        missing = sorted(str(p.relative_to(ROOT / top)) for p in data - shipped_data(top, name))
        assert not missing, f"add to pyproject.toml [tool.setuptools.package-data] {name}: {missing}"


# -- the wheel -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The wheel built from a copy of this checkout's files (so no build output lands in the
    checkout), unpacked as pip would install it: (wheel names, site folder)."""
    pytest.importorskip("setuptools", reason="building the wheel needs setuptools (the build backend)")
    tmp = tmp_path_factory.mktemp("wheel")
    src = tmp / "src"
    for top in ("objsearch", "agents"):
        for path in package_files(top):
            dest = src / path.relative_to(ROOT)
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(path, dest)
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "--no-index",
            "-q",
            "-w",
            str(tmp / "dist"),
            str(src),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr[-3000:]
    (wheel,) = (tmp / "dist").glob("objsearch-*.whl")
    site = tmp / "site"
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
        z.extractall(site)
    return names, site


def test_the_wheel_holds_every_module_and_data_file(installed):
    names, _ = installed
    for top, package in INSTALLED_NAME.items():
        expected = {"/".join((package, *p.relative_to(ROOT / top).parts)) for p in package_files(top)}
        missing = sorted(expected - names)
        assert not missing, f"the wheel lacks (pyproject.toml [tool.setuptools]): {missing[:20]}"
    stray = sorted(n for n in names if not n.startswith(("objsearch/", "objsearch_agents/", "objsearch-")))
    assert not stray, f"the wheel installs files outside its packages: {stray[:20]}"


def test_the_wheel_declares_the_entry_points_of_pyproject(installed):
    names, site = installed
    (dist_info,) = {n.split("/")[0] for n in names if n.split("/")[0].endswith(".dist-info")}
    text = (site / dist_info / "entry_points.txt").read_text()
    parser = configparser.ConfigParser(delimiters=("=",))
    parser.optionxform = str
    parser.read_string(text)
    assert dict(parser["console_scripts"]) == PYPROJECT["project"]["scripts"]
    assert dict(parser["objsearch.agents"]) == PYPROJECT["project"]["entry-points"]["objsearch.agents"]


INSTALLED_CHECK = r"""
import json, sys
from pathlib import Path
site = Path(sys.argv[1]).resolve()
import objsearch, objsearch_agents
assert Path(objsearch.__file__).resolve().is_relative_to(site), objsearch.__file__
assert Path(objsearch_agents.__file__).resolve().is_relative_to(site), objsearch_agents.__file__
from objsearch.gridworld import dataset
from objsearch.eval.suites import make_suite
from objsearch.eval.registry import make_agent
from objsearch.sim.suites import SUITE_NAMES, load_suite_file
from objsearch.perception.inference import SHIPPED_CHECKPOINT
from objsearch.leaderboard.render import DATA_PLACEHOLDER, page_template
out = {
    "train_maps": len(dataset.train_maps()), "test_maps": len(dataset.test_maps()),
    "tasks": {split: len(dataset.split_tasks(split)) for split in dataset.SPLIT_GOALS},
    "gridworld_episodes": len(make_suite("gridworld").episodes("unseen-goals")),
    "house_suites": {name: len(load_suite_file(name)) > 0 for name in SUITE_NAMES},
    "perception": SHIPPED_CHECKPOINT.resolve().is_relative_to(site) and SHIPPED_CHECKPOINT.is_file(),
    "template": page_template().count(DATA_PLACEHOLDER),
    "checkpoints": {},
}
for name in ("dqn", "hdqn", "hrl_grg", "hrl_grg_no_relation", "hrl_grg_no_termination", "hrl_grg_no_high_level"):
    out["checkpoints"][name] = make_agent(name).loaded_from
for suite in SUITE_NAMES:
    for name in ("a3c", "dqn", "hdqn", "hrl_grg", "hdqn_explorer", "hrl_grg_explorer", "scene_priors"):
        try:
            out["checkpoints"][f"{suite}/{name}"] = make_agent(name, suite=suite).loaded_from
        except Exception as err:
            out["checkpoints"][f"{suite}/{name}"] = f"{type(err).__name__}: {err}"
print(json.dumps(out))
"""


def test_an_installed_copy_finds_the_data_it_needs(installed):
    """Run from the unpacked wheel (ahead of the editable install on sys.path), the code
    reads its maps, tasks, suite files, perception network, page template and the shipped
    agent checkpoints from the installed package."""
    _, site = installed
    env = {**os.environ, "PYTHONPATH": str(site)}
    out = subprocess.run(
        [sys.executable, "-c", INSTALLED_CHECK, str(site)],
        capture_output=True,
        text=True,
        env=env,
        cwd=site,
        timeout=300,
    )
    assert out.returncode == 0, out.stderr[-3000:]
    found = json.loads(out.stdout.splitlines()[-1])
    assert found["train_maps"] == 100 and found["test_maps"] == 20
    assert found["tasks"] == {"seen-goals": 100, "unseen-goals": 100, "all-goals": 100}
    assert found["gridworld_episodes"] == 100
    assert all(found["house_suites"].values()) and found["perception"] and found["template"] == 1
    shipped = {
        f"{p.parent.parent.name}/{p.parent.name}"
        for p in (ROOT / "agents" / "checkpoints").glob("*/*/policy.pt")
        if p.parent.parent.name != "gridworld"
    }
    shipped |= {p.parent.name for p in (ROOT / "agents" / "checkpoints" / "gridworld").glob("*/policy.pt")}
    for key, loaded in found["checkpoints"].items():
        if key in shipped:
            assert loaded and Path(loaded).resolve().is_relative_to(site.resolve()), f"{key}: {loaded}"
    assert shipped <= set(found["checkpoints"]), sorted(shipped - set(found["checkpoints"]))


# -- the installed project's metadata and commands ----------------------------------------------
def test_the_installed_metadata_is_this_pyproject():
    """The editable install was made from this pyproject.toml (``make`` reinstalls when it changes)."""
    import objsearch

    dist = distribution("objsearch")
    assert dist.version == PYPROJECT["project"]["version"] == objsearch.__version__
    scripts = {ep.name: ep.value for ep in dist.entry_points if ep.group == "console_scripts"}
    assert scripts == PYPROJECT["project"]["scripts"]
    agents = {ep.name: ep.value for ep in entry_points(group="objsearch.agents")}
    assert agents == PYPROJECT["project"]["entry-points"]["objsearch.agents"]


def command(*args):
    return subprocess.run([str(BIN / args[0]), *args[1:]], capture_output=True, text=True, timeout=300)


def test_objsearch_version_and_help():
    version = command("objsearch", "--version")
    assert version.returncode == 0 and version.stdout == f"objsearch {PYPROJECT['project']['version']}\n"
    usage = command("objsearch", "--help")
    assert usage.returncode == 0 and usage.stdout.startswith("usage: objsearch ")
    from objsearch.cli import build_parser

    (sub,) = [a for a in build_parser()._actions if a.dest == "command"]
    for name in sub.choices:
        assert f"\n    {name} " in usage.stdout or f"\n    {name}\n" in usage.stdout, (
            f"{name} missing from objsearch --help"
        )


def test_every_subcommand_has_help(capsys):
    from objsearch.cli import build_parser, main

    (sub,) = [a for a in build_parser()._actions if a.dest == "command"]
    assert len(sub.choices) >= 9
    for name in sub.choices:
        with pytest.raises(SystemExit) as done:
            main([name, "--help"])
        assert done.value.code == 0, name
        assert capsys.readouterr().out.startswith(f"usage: objsearch {name}"), name


def test_objsearch_eval_help():
    usage = command("objsearch-eval", "--help")
    assert usage.returncode == 0 and usage.stdout.startswith("usage: objsearch-eval ")
    for flag in ("--agent", "--suite", "--split", "--seeds", "--out", "--list-agents"):
        assert flag in usage.stdout


def test_objsearch_eval_version():
    version = command("objsearch-eval", "--version")
    assert version.returncode == 0 and version.stdout == f"objsearch-eval {PYPROJECT['project']['version']}\n"


# -- every registered agent, by name, plays -------------------------------------------------
AGENT_NAMES = sorted(PYPROJECT["project"]["entry-points"]["objsearch.agents"])
HOUSE_SUITE = "house-single"


@pytest.fixture(scope="module")
def tiny_suites(tmp_path_factory):
    """Two grid-world tasks (maps and a task file, as a user passes them) and one
    house-single episode rendered live and cut at 5 steps: {world: (name, suite, split, episodes)}."""
    from objsearch.eval.suites import make_suite
    from objsearch.gridworld.dataset import DATA_DIR

    tasks = tmp_path_factory.mktemp("tiny") / "tiny.jsonl"
    tasks.write_text("\n".join((DATA_DIR / "tasks" / "all-goals.jsonl").read_text().splitlines()[:2]) + "\n")
    grid = make_suite("gridworld", maps=str(DATA_DIR / "test"), tasks=str(tasks))
    house = make_suite(HOUSE_SUITE, mode="live", max_steps=5)
    return {
        "gridworld": ("gridworld", grid, "tiny", grid.episodes("tiny")),
        "house": (HOUSE_SUITE, house, house.splits[0], house.episodes(house.splits[0])[:1]),
    }


class CheckedEnv:
    """The suite's env, recording every action the agent gives and whether the env's action
    space contains it."""

    def __init__(self, env):
        self.env, self.actions = env, []
        self.observation_space, self.action_space = env.observation_space, env.action_space

    def reset(self, **kwargs):
        return self.env.reset(**kwargs)

    def step(self, action):
        self.actions.append((action, self.env.action_space.contains(action)))
        return self.env.step(action)


def untrained_checkpoint(cls, suite: str, out: Path) -> str:
    """An untrained policy of ``cls``'s house method for ``suite``, saved as training saves one."""
    from dataclasses import replace

    from objsearch_agents.baselines import scene_priors
    from objsearch_agents.house.checkpoint import save_policy
    from objsearch_agents.house.policy import HousePolicy

    out.mkdir(parents=True, exist_ok=True)
    if issubclass(cls, scene_priors.ScenePriorsAgent):  # its own network and checkpoint
        predictor = scene_priors.feature_network()
        features, scores = scene_priors.frame_features(predictor.model, np.zeros((1, 64, 64, 3), np.uint8))
        net = scene_priors.ScenePriorsNet(scene_priors.prior_graph(), features.shape[1], scores.shape[1])
        scene_priors.save_policy(net, replace(cls.config, suite=suite), predictor.key, out)
        return str(out)
    save_policy(HousePolicy(replace(cls.house.config, suite=suite)), out)
    return str(out)


@pytest.mark.parametrize("name", AGENT_NAMES)
def test_every_registered_agent_is_built_by_name_and_plays_an_episode(name, tiny_suites, tmp_path):
    from objsearch.errors import UserError
    from objsearch.eval.episode import run_episode
    from objsearch.eval.registry import make_agent, resolve_agent

    cls = resolve_agent(name)
    worlds = cls.worlds() if callable(getattr(cls, "worlds", None)) else ("gridworld", "house")
    assert set(worlds) <= {"gridworld", "house"} and worlds, worlds
    for world, (suite_name, suite, split, episodes) in tiny_suites.items():
        if world not in worlds:
            with pytest.raises(UserError, match="runs in the .* world"):
                make_agent(name, suite=suite_name)
            continue
        try:
            agent = make_agent(name, suite=suite_name)
        except UserError as err:  # a method without a shipped checkpoint for the suite says how to make one
            assert f"train one with `objsearch train --agent {name} --suite {suite_name}`" in str(err)
            agent = make_agent(name, untrained_checkpoint(cls, suite_name, tmp_path / world), suite=suite_name)
        env = CheckedEnv(suite.make_env())
        for episode in episodes:
            env.actions.clear()
            try:
                record = run_episode(agent, env, suite_name, split, episode, seed=1)
            finally:
                env.env.close()
            assert "error" not in record, (world, record)
            assert record["steps"] == len(env.actions) >= 1 and all(ok for _, ok in env.actions), (world, env.actions)
            limit = suite.max_steps
            assert record["steps"] <= limit and (record["success"] or record["steps"] == limit), (world, record)
            if name == "oracle" and world == "gridworld":
                assert record["success"] and record["steps"] == record["min_steps"]
