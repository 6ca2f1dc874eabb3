"""granular.Scenario: loading, overrides with the command line's syntax, serialisation, errors."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest

import granular
from conftest import EDMD_2D, cli


def test_load_bundled_scenario(root: Path) -> None:
    sc = granular.Scenario.load(root / "scenarios" / "maxwell-boltzmann.toml")
    assert sc.engine == "edmd"
    assert sc.dimension == 2
    assert sc.particle_count == 10000
    assert sc.species_names == ["disk"]
    assert sc.seed == 1
    assert sc.path is not None and sc.path.endswith("maxwell-boltzmann.toml")
    assert sc.check() == "valid (10000 grains, 1 species)"
    assert "Problem 1" in sc.description
    assert "maxwell-boltzmann.toml" in repr(sc)


def test_every_bundled_scenario_loads(root: Path) -> None:
    for path in sorted((root / "scenarios").glob("*.toml")):
        sc = granular.Scenario.load(path)
        assert sc.check().startswith("valid"), path


def test_set_uses_the_cli_syntax(edmd2d: granular.Scenario) -> None:
    edmd2d.set("collisions.restitution", 0.8)
    edmd2d.set("species[1].mass", 2)
    edmd2d.set("species.0.name", "tiny")
    d = edmd2d.to_dict()
    assert d["collisions"]["restitution"] == 0.8
    assert d["species"][1]["mass"] == 2.0
    assert d["species"][0]["name"] == "tiny"
    assert edmd2d.overrides == ["collisions.restitution=0.8", "species[1].mass=2", 'species.0.name="tiny"']
    edmd2d.set("seed", 99)
    assert edmd2d.seed == 99


def test_set_values_of_every_type(edmd2d: granular.Scenario) -> None:
    edmd2d.set("box.boundary", "wall")
    edmd2d.set("initial.zero_momentum", True)
    edmd2d.set("box.lengths", [2.0, 1.0])
    edmd2d.set("species[0].velocity", {"distribution": "fixed_speed", "speed": 2.0})
    d = edmd2d.to_dict()
    assert d["box"]["boundary"] == "wall"
    assert d["initial"]["zero_momentum"] is True
    assert d["box"]["lengths"] == [2.0, 1.0]
    assert d["species"][0]["velocity"] == {"distribution": "fixed_speed", "speed": 2.0}
    with pytest.raises(TypeError, match="no TOML form"):
        edmd2d.set("seed", object())


def test_update_changes_coupled_keys_together(edmd2d: granular.Scenario) -> None:
    with pytest.raises(granular.ScenarioError):
        edmd2d.set("dimension", 3)
    edmd2d.update({"dimension": 3, "box.lengths": [1.0, 1.0, 1.0]})
    assert edmd2d.dimension == 3


def test_failed_set_leaves_the_scenario_unchanged(edmd2d: granular.Scenario) -> None:
    before = edmd2d.to_toml()
    with pytest.raises(granular.ScenarioError) as info:
        edmd2d.set("collisions.restitution", 1.5)
    assert info.value.key == "collisions.restitution"
    assert "1.5" in str(info.value) and "[0, 1]" in str(info.value)
    assert edmd2d.to_toml() == before


def test_error_names_key_value_line_and_fix() -> None:
    text = EDMD_2D.replace("restitution = 0.95", "restitution = 2.0")
    with pytest.raises(granular.ScenarioError) as info:
        granular.Scenario.from_toml(text)
    e = info.value
    line = 1 + text.splitlines().index("restitution = 2.0")
    assert e.key == "collisions.restitution"
    assert e.line == line
    assert str(e).startswith(f"line {line}: `collisions.restitution`: is 2")
    assert "must lie in [0, 1]" in e.reason
    assert isinstance(e, ValueError)


def test_unknown_key_and_syntax_errors() -> None:
    with pytest.raises(granular.ScenarioError, match="restitutoin"):
        granular.Scenario.from_toml(EDMD_2D.replace("restitution = 0.95", "restitutoin = 0.95"))
    with pytest.raises(granular.ScenarioError):
        granular.Scenario.from_toml("engine = [")
    with pytest.raises(granular.ScenarioError):
        granular.Scenario.from_toml(EDMD_2D).set("species[7].mass", 1.0)


def test_error_text_is_the_cli_text(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(EDMD_2D.replace("count = 300", "count = 300\nmass = -1.0"))
    with pytest.raises(granular.ScenarioError) as info:
        granular.Scenario.load(path)
    result = cli("check", str(path), check=False)
    assert result.returncode == 2
    # The command line shows the same message (through miette, with the file's line underlined).
    assert str(info.value) in result.stderr


def test_check_output_is_the_cli_output(tmp_path: Path) -> None:
    path = tmp_path / "ok.toml"
    path.write_text(EDMD_2D)
    sc = granular.Scenario.load(path)
    result = cli("check", str(path), "--set", "collisions.restitution=0.5")
    sc.set("collisions.restitution", 0.5)
    assert result.stdout == sc.to_toml()
    # The cost estimate first (lines "estimate: ..."), then the verdict, as check() gives it.
    lines = result.stderr.strip().splitlines()
    assert lines[-1] == f"{path}: {sc.check()}"
    assert [line for line in lines[:-1] if not line.startswith("estimate: ")] == []


def test_missing_file() -> None:
    with pytest.raises(FileNotFoundError, match="nowhere.toml"):
        granular.Scenario.load("nowhere.toml")


def test_round_trips(edmd2d: granular.Scenario) -> None:
    again = granular.Scenario.from_toml(edmd2d.to_toml())
    assert again == edmd2d
    from_dict = granular.Scenario.from_dict(edmd2d.to_dict())
    assert from_dict == edmd2d
    c = edmd2d.copy()
    c.set("seed", 12)
    assert edmd2d.seed == 5 and c.seed == 12
    assert copy.deepcopy(edmd2d) == edmd2d and copy.copy(edmd2d) == edmd2d
    assert edmd2d.source == EDMD_2D
    assert edmd2d != "not a scenario"


def test_from_dict_minimal() -> None:
    sc = granular.Scenario.from_dict(
        {
            "engine": "edmd",
            "species": [{"name": "disk", "count": 50, "radius": 0.01, "velocity": None}],
            "stop": {"time": 1.0},
        }
    )
    assert sc.particle_count == 50
    with pytest.raises(TypeError, match="not a string"):
        granular.Scenario.from_dict({1: 2})  # type: ignore[dict-item]
