"""``house-gen-v2-shuffled``: ``house-gen-v2``'s houses with their objects shuffled, its targets
and splits, episodes drawn as ``house-gen-v2`` draws them."""

from objsearch.sim.suites import SHUFFLED_SUITES, load_suite_file
from objsearch.sim.world import HouseRef, World


def _floorplan(spec) -> dict:
    data = spec.to_json()
    for key in ("objects", "extra"):
        data.pop(key)
    return data


def test_shuffled_suite_is_its_base_suite_with_shuffled_houses():
    assert SHUFFLED_SUITES == {"house-gen-v2-shuffled": "house-gen-v2"}
    suite, base = load_suite_file("house-gen-v2-shuffled"), load_suite_file("house-gen-v2")
    assert suite["categories"] == base["categories"] and list(suite["splits"]) == list(base["splits"])
    assert {k: suite[k] for k in ("goal_rule", "goal_camera", "start_steps", "max_steps")} == {
        k: base[k] for k in ("goal_rule", "goal_camera", "start_steps", "max_steps")
    }
    for group in ("houses", "training_houses"):
        assert list(suite[group]) == list(base[group])
        for house, info in suite[group].items():
            functional = {k: v for k, v in base[group][house].items() if k != "spec_sha256"}
            assert {k: v for k, v in info.items() if k != "spec_sha256"} == {**functional, "placement": "shuffled"}
    for split, episodes in suite["splits"].items():
        assert len(episodes) == 100
        assert {e["house"] for e in episodes} == {e["house"] for e in base["splits"][split]}
        assert all(e["target"] in suite["goals"][e["house"]] for e in episodes)
    # a validation, a test and a training house regenerate to their recorded hashes: the
    # functional house of house-gen-v2 (the same floorplan), its objects elsewhere
    for group, house in (("houses", "test_002000"), ("houses", "test_003005"), ("training_houses", "train_001000")):
        shuffled = World.load(HouseRef(**suite[group][house]))
        functional = World.load(HouseRef(**base[group][house]))
        assert shuffled.spec.placement == "shuffled" and _floorplan(shuffled.spec) == _floorplan(functional.spec)
        assert [o.name for o in shuffled.spec.objects] == [o.name for o in functional.spec.objects]
        assert [o.position for o in shuffled.spec.objects] != [o.position for o in functional.spec.objects]
