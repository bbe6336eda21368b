"""The one config base (``objsearch.configs.JsonConfig``): round trips, the rule on unknown
keys, the legacy path for older files, ``--set`` overrides, and every shipped config and
checkpoint still loading through its class."""

import dataclasses
import json
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from objsearch import torchfile
from objsearch.configs import JsonConfig
from objsearch.errors import UserError
from objsearch.house.spec import HouseSpec
from objsearch.perception.config import TrainConfig
from objsearch.perception.model import ModelConfig
from objsearch_agents.gridworld.config import GridAgentConfig
from objsearch_agents.house.config import HouseAgentConfig

ROOT = Path(__file__).resolve().parents[1]
GOLDEN_SPECS = sorted((ROOT / "tests" / "house" / "golden").glob("spec_*.json"))
CONFIGS = [GridAgentConfig(), HouseAgentConfig(), TrainConfig(), ModelConfig()]


@pytest.mark.parametrize("config", CONFIGS + [HouseSpec.load(GOLDEN_SPECS[0])], ids=lambda c: type(c).__name__)
def test_round_trip_through_data_text_and_file(config, tmp_path):
    data = config.to_json()
    assert isinstance(data, dict)
    assert json.loads(config.to_json_text()) == data  # JSON-ready: tuples already lists
    assert type(config).from_json(data) == config
    config.save(tmp_path / "c.json")
    assert (tmp_path / "c.json").read_text() == config.to_json_text()
    assert type(config).load(tmp_path / "c.json") == config


def test_train_config_nests_the_model_config():
    config = TrainConfig(model=ModelConfig(stem=16, aspp_rates=(2, 4)))
    data = config.to_json()
    assert data["model"]["stem"] == 16 and data["model"]["aspp_rates"] == [2, 4]
    again = TrainConfig.from_json(data)
    assert isinstance(again.model, ModelConfig) and again == config


@pytest.mark.parametrize("config", CONFIGS, ids=lambda c: type(c).__name__)
def test_an_unknown_key_is_an_error_naming_key_class_file_and_fix(config):
    data = {**config.to_json(), "no_such_key": 1}
    with pytest.raises(UserError) as err:
        type(config).from_json(data, "runs/x/config.json")
    message = str(err.value)
    for part in ("runs/x/config.json", type(config).__name__, "'no_such_key'", "delete it", "LEGACY_KEYS"):
        assert part in message, (part, message)


def test_a_misspelt_key_gets_a_suggestion_and_a_nested_one_its_path():
    with pytest.raises(UserError, match="did you mean 'num_envs'"):
        GridAgentConfig.from_json({"num_env": 4})
    data = TrainConfig().to_json()
    data["model"]["stemm"] = 8
    with pytest.raises(UserError, match=r"'stemm' at model: ModelConfig has no such field \(did you mean 'stem'\?\)"):
        TrainConfig.from_json(data, "config.json")


def test_house_spec_refuses_unknown_keys_at_any_depth():
    data = json.loads(GOLDEN_SPECS[0].read_text())
    data["rooms"][1]["ceiling"] = "high"
    with pytest.raises(
        UserError, match=r"spec.json is not a house spec \(HouseSpec\): unknown key 'ceiling' at rooms\[1\]"
    ):
        HouseSpec.from_json(data, "spec.json")


def test_missing_keys_take_defaults_but_required_ones_are_errors():
    data = HouseAgentConfig(method="a3c").to_json()
    del data["explorer"]  # the shipped checkpoints predate this field
    assert HouseAgentConfig.from_json(data) == HouseAgentConfig(method="a3c")
    spec = json.loads(GOLDEN_SPECS[0].read_text())
    del spec["rooms"]
    with pytest.raises(UserError, match="is not a house spec.*missing key 'rooms'"):
        HouseSpec.from_json(spec, "spec.json")


def test_values_of_the_wrong_type_and_refused_values_are_errors():
    with pytest.raises(UserError, match="lr must be a number, got '0.1'"):
        GridAgentConfig.from_json({"lr": "0.1"})
    with pytest.raises(UserError, match="num_envs must be an integer, got True"):
        GridAgentConfig.from_json({"num_envs": True})
    with pytest.raises(UserError, match="checkpoint p.pt is not a house agent config.*method must be one of"):
        HouseAgentConfig.from_json({"method": "ppo"}, "checkpoint p.pt")
    with pytest.raises(UserError, match="expected a JSON object"):
        GridAgentConfig.from_json([1, 2])
    assert GridAgentConfig.from_json({"lr": 1}).lr == 1  # an int where a float goes: JSON writes 1.0 as 1 at times


def test_bad_files_are_user_errors(tmp_path):
    with pytest.raises(UserError, match="cannot read"):
        GridAgentConfig.load(tmp_path / "missing.json")
    (tmp_path / "bad.json").write_text("{")
    with pytest.raises(UserError, match="is not JSON"):
        GridAgentConfig.load(tmp_path / "bad.json")


@dataclass(frozen=True)
class _Renamed(JsonConfig):
    LEGACY_KEYS = {"learning_rate": "lr", "use_gpu": None}

    lr: float = 0.1
    steps: int = 10


@dataclass(frozen=True)
class _Upgraded(JsonConfig):
    rates: tuple[int, ...] = (2, 4)
    tags: dict = field(default_factory=dict)

    @classmethod
    def upgrade(cls, data: dict) -> dict:
        if "rate" in data:  # version 1 had one rate
            data["rates"] = [data.pop("rate")]
        return super().upgrade(data)


def test_legacy_keys_rename_and_drop_old_fields():
    assert _Renamed.from_json({"learning_rate": 0.5, "use_gpu": True, "steps": 3}) == _Renamed(lr=0.5, steps=3)
    with pytest.raises(UserError, match="'learning_rate' is the old name of 'lr'"):
        _Renamed.from_json({"learning_rate": 0.5, "lr": 0.2})
    assert "learning_rate" not in _Renamed().to_json()  # written only under the new name


def test_the_upgrade_hook_reads_what_a_table_cannot_say():
    assert _Upgraded.from_json({"rate": 3}) == _Upgraded(rates=(3,))
    assert _Upgraded.from_json({"rates": [1, 2], "tags": {"a": 1}}) == _Upgraded(rates=(1, 2), tags={"a": 1})
    with pytest.raises(UserError, match="unknown key 'rat'"):
        _Upgraded.from_json({"rat": 3})


def test_house_spec_legacy_hook_refuses_other_schema_versions():
    data = json.loads(GOLDEN_SPECS[0].read_text())
    data["schema_version"] = 0
    with pytest.raises(UserError, match="schema_version 0 is not 1; regenerate the house with objsearch generate"):
        HouseSpec.from_json(data, "spec.json")


def test_with_overrides_types_every_kind_of_field():
    config = GridAgentConfig().with_overrides(
        {"relation": "false", "num_envs": "8", "lr": "3e-4", "pretrained": "p.pt"}
    )
    assert (config.relation, config.num_envs, config.lr, config.pretrained) == (False, 8, 3e-4, "p.pt")
    train = TrainConfig().with_overrides({"steps": "5", "model.stem": "16", "model.aspp_rates": "1,3"})
    assert (train.steps, train.model.stem, train.model.aspp_rates) == (5, 16, (1, 3))
    assert train.model == dataclasses.replace(ModelConfig(), stem=16, aspp_rates=(1, 3))
    assert HouseAgentConfig().with_overrides({}) == HouseAgentConfig()


@pytest.mark.parametrize(
    "overrides, message",
    [
        ({"steps": "eight"}, "config field steps takes an int, got 'eight'"),
        ({"lr": "fast"}, "config field lr takes a float, got 'fast'"),
        ({"augment": "maybe"}, "config field augment takes a bool"),
        ({"model.stem": "1.5"}, "config field model.stem takes an int, got '1.5'"),
        ({"model.stem": "0"}, "model config field stem must be a positive integer"),
        ({"model.aspp_rates": "2,x"}, "model.aspp_rates takes a comma-separated list (1,2,3)"),
        ({"no_such": "1"}, "unknown config field 'no_such' of TrainConfig"),
        ({"model.wide": "1"}, "unknown config field 'model.wide' of ModelConfig"),
        ({"model": "1"}, "config field model is a group of fields; set them as model.FIELD=VALUE"),
        ({"stepz": "1"}, "did you mean steps"),
        ({"steps": "0"}, "steps must be >= 1"),
        ({"class_weighting": "median"}, "class_weighting must be one of"),
    ],
)
def test_with_overrides_refuses_bad_values_and_unknown_fields(overrides, message):
    with pytest.raises(UserError) as err:
        TrainConfig().with_overrides(overrides)
    assert message in str(err.value)


def _agent_config_class(path: Path):
    if "scene_priors" in path.parts:  # a method with a config of its own
        from objsearch_agents.baselines.scene_priors import ScenePriorsConfig

        return ScenePriorsConfig
    return GridAgentConfig if "gridworld" in path.parts else HouseAgentConfig


AGENT_CONFIGS = sorted((ROOT / "agents" / "checkpoints").rglob("config.json"))


def test_the_shipped_checkpoints_are_found():
    assert len(AGENT_CONFIGS) >= 20 and all((p.parent / "policy.pt").is_file() for p in AGENT_CONFIGS)


@pytest.mark.parametrize(
    "path", AGENT_CONFIGS, ids=lambda p: str(p.relative_to(ROOT / "agents" / "checkpoints").parent)
)
def test_every_shipped_agent_config_and_policy_loads_through_its_class(path):
    cls = _agent_config_class(path)
    config = cls.load(path)
    state = torchfile.load(path.parent / "policy.pt", "a shipped policy.pt")
    assert cls.from_json(state["config"], path.parent / "policy.pt") == config
    assert cls.from_json(json.loads(config.to_json_text())) == config


def test_the_shipped_perception_checkpoint_loads_through_its_classes():
    folder = ROOT / "objsearch" / "perception" / "checkpoint"
    config = TrainConfig.load(folder / "config.json")
    assert config.to_json_text() == (folder / "config.json").read_text()  # written by this base's format
    state = torchfile.load(folder / "model.pt", "the shipped perception model.pt")
    assert ModelConfig.from_json(state["model_config"]) == config.model


@pytest.mark.parametrize("path", GOLDEN_SPECS, ids=lambda p: p.name)
def test_golden_house_specs_load_and_write_the_same_bytes(path):
    text = path.read_text()
    assert HouseSpec.load(path).to_json_text() == text
