"""The ROS 2 adapter, pure (no zenoh session: ``shell.ros_bus`` and ``shell.ros_input``
hold those): a robot's own topics as they are on zenoh (``wire``: keys, type hashes and
attachments per rmw_zenoh release or bridge; ``types``: CDR with rosbags and the upstream
``msg/`` files; ``input``: routing a sample and decoding it; ``people``: tracked ids to
poses through tf2's rules), our results said back on its topics (``output``, ``markers``
for RViz), and why a robot gives no results (``diagnosis``). In front of the core, never
a second service."""

from .people import People
from .wire import Distro, RosFormat, Wire

__all__ = ["Distro", "People", "RosFormat", "Wire"]
