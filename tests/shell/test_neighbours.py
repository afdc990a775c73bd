"""A second service reading the same poses in one namespace is said in both logs
(every result arrived twice and neither log said anything); one sharded by frame is
not."""

from __future__ import annotations

import logging
import time

import pytest

from facing_service.shell.neighbours import FIRST_WAITS_S, PERIOD_S, overlapping

from loopback import wait_until

SAID = "another facing service reads the same poses in namespace 'hri'"


def said(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records if SAID in r.getMessage()]


@pytest.mark.slow
def test_two_services_on_the_same_frames_each_say_the_other(net, caplog):
    """Both of one instance name (two services in one process: the default --instance is
    the host's name and the process id), so one token: the older one learns of the newer
    by asking again (PERIOD_S)."""
    caplog.set_level(logging.WARNING, logger="facing_service")
    _, ep = net.service(base_frame="*")
    net.service(base_frame="cam", connect=[ep])
    asked = sum(FIRST_WAITS_S) + PERIOD_S  # the older's third ask, at the latest
    # (and its fourth: under a CI run's load, the container build beside, one ask missed)
    wait_until(lambda: len(said(caplog)) == 2, asked + PERIOD_S + 5, "both services said the other")
    lines = said(caplog)
    assert any("base frame cam; this one's *" in line for line in lines), lines
    assert any("base frame *; this one's cam" in line for line in lines), lines
    assert all("Give each its own --namespace, or --base-frame" in line for line in lines)
    time.sleep(1.0)
    assert len(said(caplog)) == 2  # once per other service


def test_a_second_service_of_another_instance_name_is_said_at_once(net, caplog):
    caplog.set_level(logging.WARNING, logger="facing_service")
    _, ep = net.service(instance="left")
    net.service(instance="right", connect=[ep])
    wait_until(lambda: len(said(caplog)) == 2, 5.0, "both services said the other at once")


def test_services_sharded_by_frame_judge_each_other_and_warn_of_nothing(net, caplog):
    """Each judged the other (the test passed had no question ever been asked),
    and neither warned."""
    caplog.set_level(logging.INFO, logger="facing_service")
    # two instance names: each learns of the other from its token at once (one name in
    # one process would wait the older's next periodic ask, 10 s)
    _, ep = net.service(base_frame="map", instance="map-side")
    net.service(base_frame="camera_left", instance="camera-side", connect=[ep])

    def judged() -> list[str]:
        return [r.getMessage() for r in caplog.records if "reads other frames" in r.getMessage()]

    wait_until(lambda: len(judged()) == 2, 15.0, "each service judged the other")
    assert any("base frame camera_left; this one's map" in line for line in judged())
    assert any("base frame map; this one's camera_left" in line for line in judged())
    assert said(caplog) == []


def test_frames_overlap_when_one_reads_every_frame_or_both_the_same():
    assert overlapping("*", "map") and overlapping("map", "*") and overlapping("map", "map")
    assert not overlapping("map", "camera_left")
