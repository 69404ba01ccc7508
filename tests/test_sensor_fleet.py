"""Fleet configs, their YAML files and unit-to-unit variation."""

from pathlib import Path

import numpy as np
import pytest

from anytip.errors import AnytipError
from anytip.sensor.fleet import FleetConfig, load_fleet_config
from anytip.sensor.simulate import unit_rng
from anytip.sensor.variation import UnitParams, draw_unit

FLEETS = Path(__file__).resolve().parents[1] / "configs" / "fleets"


def test_default_yaml_is_the_default_config():
    assert load_fleet_config(FLEETS / "default.yaml") == FleetConfig()


def test_named_fleets_load():
    assert load_fleet_config(FLEETS / "identical.yaml").severity == 0.0
    assert load_fleet_config(FLEETS / "gentle.yaml").severity == 0.5


def test_bad_key_names_file_and_key(tmp_path):
    path = tmp_path / "x.yaml"
    path.write_text("severty: 0.5\n")
    with pytest.raises(AnytipError) as e:
        load_fleet_config(path)
    msg = str(e.value)
    assert str(path) in msg and "'severty'" in msg and "severity" in msg and "allowed keys" in msg


def test_bad_nested_key_lists_the_section_keys(tmp_path):
    path = tmp_path / "y.yaml"
    path.write_text("nominal:\n  modulus: 2.0e6\n")
    with pytest.raises(AnytipError, match=r"'nominal\.modulus' is not allowed.*modulus_pa"):
        load_fleet_config(path)


@pytest.mark.parametrize(
    "text", ["severity: -1\n", "severity: lots\n", "spread:\n  bubble_probability: 2\n"]
)
def test_bad_value_names_file_and_key(tmp_path, text):
    path = tmp_path / "z.yaml"
    path.write_text(text)
    with pytest.raises(AnytipError) as e:
        load_fleet_config(path)
    assert str(path) in str(e.value) and text.split(":")[0].strip() in str(e.value)


def test_not_a_mapping(tmp_path):
    path = tmp_path / "w.yaml"
    path.write_text("- 1\n- 2\n")
    with pytest.raises(AnytipError, match="mapping"):
        load_fleet_config(path)


def test_severity_zero_gives_identical_nominal_units():
    config = FleetConfig(severity=0.0)
    units = [draw_unit(config, unit_rng(3, i)) for i in range(5)]
    assert all(u == units[0] for u in units)
    assert units[0].channel_gain == [config.nominal.coupling_gain] * 8
    assert units[0].modulus_pa == config.nominal.modulus_pa
    assert not any(units[0].bubble_strength)


def test_default_units_differ_and_serialise():
    a, b = (draw_unit(FleetConfig(), unit_rng(3, i)) for i in range(2))
    assert a != b
    assert UnitParams.model_validate_json(a.model_dump_json()) == a


def test_default_fleet_gain_ratio_reaches_3x():
    gains = np.array([draw_unit(FleetConfig(), unit_rng(11, i)).channel_gain for i in range(20)])
    ratio = gains.max(axis=0) / gains.min(axis=0)
    assert ratio.max() >= 3.0
    assert np.median(ratio) >= 2.0


def test_gentle_fleet_is_gentler():
    def spread(severity):
        gains = np.array(
            [
                draw_unit(FleetConfig(severity=severity), unit_rng(5, i)).channel_gain
                for i in range(20)
            ]
        )
        return np.log(gains).std()

    assert spread(0.5) == pytest.approx(spread(1.0) / 2)
