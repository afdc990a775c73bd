"""The shell's fixtures: a service on 'cam' with a client recording its results."""

from __future__ import annotations

import pytest
from service_rig import FRAME_KEY, NAMESPACE

from loopback import wait_until_answered


@pytest.fixture
def rig(net):
    """A service on 'cam' plus a connected client recording everything under hri/."""

    def make(**settings):
        service, ep = net.service(**settings)
        client = net.client(ep)
        recorder = net.recorder(client, f"{NAMESPACE}/**/facing/**")
        wait_until_answered(client, FRAME_KEY)
        return service, client, recorder

    return make
