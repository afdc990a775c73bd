"""tf2's rules, pure (no ROS): ``buffer`` (BufferCore: static and dynamic links, the
cache time, lookups at the latest common time), ``cache`` (one link's timeline),
``geometry`` (rigid transforms and quaternions), ``errors`` (tf2's exceptions, as ours)."""
