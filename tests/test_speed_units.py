"""A single ``--speed`` takes units as ``--speeds`` does: ``modes --speed 12000rpm`` is the
modes at 12000 rpm = 400 pi rad/s (the conversion is exact arithmetic: 2 pi / 60 rad/s per rpm).
"""

import json
import math
from pathlib import Path

import pytest

import rubrotor
from rubrotor.cli import main
from rubrotor.errors import InputError
from rubrotor.units import parse_speed

GENERAL = str(Path(rubrotor.__file__).parent / "scenarios" / "general_rotor.toml")


@pytest.mark.parametrize(
    ("text", "rad_s"),
    [("500", 500.0), ("12000rpm", 400 * math.pi), ("200Hz", 400 * math.pi), ("7 rad/s", 7.0)],
)
def test_parse_speed_converts_to_rad_per_s(text, rad_s):
    assert parse_speed(text) == pytest.approx(rad_s, rel=1e-15)


@pytest.mark.parametrize("text", ["fast", "-5", "inf", "12000rpms", "nan"])
def test_parse_speed_refuses_by_name(text):
    with pytest.raises(InputError, match="--speed"):
        parse_speed(text)


def test_modes_speed_in_rpm_equals_the_speed_in_rad_per_s(capsys):
    assert main(["modes", GENERAL, "--speed", "12000rpm", "--json", "--number", "4"]) == 0
    rpm = json.loads(capsys.readouterr().out)
    assert main(["modes", GENERAL, "--speed", repr(400 * math.pi), "--json", "--number", "4"]) == 0
    rad = json.loads(capsys.readouterr().out)
    assert rpm["speed_rad_s"] == pytest.approx(400 * math.pi, rel=1e-15)
    # the two speeds may differ in their last bit (12000 * 2 pi / 60 against 400 pi)
    for a, b in zip(rpm["modes"], rad["modes"], strict=True):
        assert a["frequency_hz"] == pytest.approx(b["frequency_hz"], rel=1e-9)
        assert a["damping_ratio"] == pytest.approx(b["damping_ratio"], rel=1e-9)
    assert main(["modes", GENERAL, "--speed", "fast"]) == 2
