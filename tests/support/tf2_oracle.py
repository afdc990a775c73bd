"""Runs scenarios through ROS's own tf2 BufferCore (Debian's python3-tf2, on the system
Python) and prints the results as JSON: the oracle of test_tf_buffer.py.

stdin: a JSON list of scenarios, each a list of operations
  ["set", parent, child, stamp_ns, [tx, ty, tz], [qx, qy, qz, qw], is_static]
  ["lookup", target, source, time_ns]
stdout: per scenario, per lookup: {"t": [...], "q": [...], "stamp": ns} or {"error": kind}.
"""

import json
import sys

import rospy
import tf2_py
from geometry_msgs.msg import TransformStamped


def transform(parent, child, stamp, t, q):
    msg = TransformStamped()
    msg.header.frame_id = parent
    msg.child_frame_id = child
    msg.header.stamp = rospy.Time(stamp // 1_000_000_000, stamp % 1_000_000_000)
    tr, ro = msg.transform.translation, msg.transform.rotation
    tr.x, tr.y, tr.z = t
    ro.x, ro.y, ro.z, ro.w = q
    return msg


def run(ops):
    buffer = tf2_py.BufferCore(rospy.Duration(10.0))
    out = []
    for op in ops:
        if op[0] == "set":
            _, parent, child, stamp, t, q, static = op
            msg = transform(parent, child, stamp, t, q)
            (buffer.set_transform_static if static else buffer.set_transform)(msg, "oracle")
        else:
            _, target, source, time = op
            try:
                r = buffer.lookup_transform_core(
                    target, source, rospy.Time(time // 1_000_000_000, time % 1_000_000_000)
                )
            except tf2_py.TransformException as error:
                out.append({"error": type(error).__name__})
                continue
            tr, ro = r.transform.translation, r.transform.rotation
            out.append(
                {
                    "t": [tr.x, tr.y, tr.z],
                    "q": [ro.x, ro.y, ro.z, ro.w],
                    "stamp": r.header.stamp.to_nsec(),
                }
            )
    return out


if __name__ == "__main__":
    print(json.dumps([run(ops) for ops in json.load(sys.stdin)]))
