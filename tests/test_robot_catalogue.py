"""robots.catalogue(): one frozen RobotInfo per robot, parameters as plain SI floats."""

from __future__ import annotations

import dataclasses

import pytest

import robots
from robots.three_gm import ThreeGM


def test_catalogue_lists_both_robots():
    infos = robots.catalogue()
    assert [i.name for i in infos] == ["planar_hand", "three_gm"]
    for info in infos:
        assert info.description
        assert info.params and all(type(v) is float for v in info.params.values())
        with pytest.raises(dataclasses.FrozenInstanceError):
            info.name = "x"  # type: ignore[misc]
    gm = {i.name: i for i in infos}["three_gm"]
    for k, v in ThreeGM().params.items():
        assert gm.params[k] == v
    assert gm.params["workspace_volume_in3"] == pytest.approx(112.0)
    hand = {i.name: i for i in infos}["planar_hand"]
    assert hand.params["right_tip_radius"] == 0.025
    assert hand.params["friction"] == 1.0
