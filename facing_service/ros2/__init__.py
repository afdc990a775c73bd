"""The ROS 2 adapter: a robot's own topics read off zenoh (``wire``: keys and type hashes
per rmw_zenoh release or bridge; ``types``: CDR with rosbags and the upstream ``msg/``
files; ``input``: subscriptions and routing; ``people``: tracked ids to poses), our
results said back on its topics (``output``), why a robot gives no results
(``diagnosis``) and bags of what was said (``record``). In front of the core, never a
second service."""

from .people import People
from .wire import Distro, RosFormat, Wire

__all__ = ["Distro", "People", "RosFormat", "Wire"]
