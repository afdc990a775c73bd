"""What a user says about the robot: the values of --ros-format and --ros-distro."""

from __future__ import annotations

from facing_service.config.settings import Settings
from facing_service.contract.robot import Distro, RosFormat


def test_the_settings_take_exactly_these_values():
    fields = Settings.model_fields
    assert set(fields["ros_format"].annotation.__args__) == {f.value for f in RosFormat}
    assert set(fields["ros_distro"].annotation.__args__) == {"auto"} | {d.value for d in Distro}


def test_each_distro_says_what_its_keys_carry():
    assert "TypeHashNotSupported" in Distro.HUMBLE.describe()
    assert "RIHS01" in Distro.JAZZY.describe()
