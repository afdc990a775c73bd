"""The ROS 2 message definitions the package carries, pinned to their upstream releases:
what the type tests check and the output tests hash with an independent implementation."""

from __future__ import annotations

from facing_service.ros2 import types as ros2_types
from facing_service.ros2.output import ENGAGEMENT_LEVEL, GAZE, GROUP, INTENT

#: typename -> (file in facing_service/ros2/msg, git blob id at the upstream tag, RIHS01 hash).
#: Upstream: ros4hri/hri_msgs 2.0.0 (5d52c81f) and ros4hri/hri_actions_msgs 2.0.1
#: (a5909864), branch humble-devel: the ROS 2 packages (msg/README.md).
UPSTREAM = {
    ENGAGEMENT_LEVEL: (
        "hri_msgs/EngagementLevel.msg",
        "0b7090157a4d5d990a66ac4d0009c83a3e41d7d3",
        "RIHS01_275391f46d2e6cc0d21085f8e02dce6a8150baa57539ec99bd9f4e0321443788",
    ),
    ros2_types.IDS_LIST: (
        "hri_msgs/IdsList.msg",
        "cb80145624c949c1f1ffb52fa07b5aff12167674",
        "RIHS01_7e0812d1ac945c98fd3e393568d581ad0ab567f37b24eff633eab778c1bfe62d",
    ),
    GROUP: (
        "hri_msgs/Group.msg",
        "2da931d2285aa6957d90c5ccb06d463b2f2ec367",
        "RIHS01_8a5322be10347f118545806061283201525b8f572bfe6131b4b45b70c56f2935",
    ),
    GAZE: (
        "hri_msgs/Gaze.msg",
        "a2707146312c1edbf9a744ef270e390ba72d02a3",
        "RIHS01_e8c46fafadbeca4367ca1987944b54863fcfc0175319002a76df5298570f4ab3",
    ),
    INTENT: (
        "hri_actions_msgs/Intent.msg",
        "fb1ea5ca93f80f14764a60efa85edb3ad24a77b5",
        "RIHS01_850d5c0a06aecf153f4cbc75f27fc655d687f93300bcc928a9d21712716fcfaa",
    ),
}
#: ROS 2's own std_msgs/Header and builtin_interfaces/Time (common_interfaces,
#: rcl_interfaces), for the SDK's hash of types that nest a Header.
STANDARD_MSGS = {
    "std_msgs/msg/Header": "builtin_interfaces/Time stamp\nstring frame_id\n",
    "builtin_interfaces/msg/Time": "int32 sec\nuint32 nanosec\n",
}


def definition(typename: str) -> str:
    return (ros2_types.MSG_DIR / UPSTREAM[typename][0]).read_text()
