"""The social scene of a base frame: ``groups`` (F-formations by GCFF's method, who faces
whom; ``facility``: its assignment, the same whatever order people come in), ``memory``
(what the last seconds say), ``join`` (where the robot should stand to join a group or
greet someone), ``vacancy``, ``scene`` (both per frame over time, as said: held,
rate-limited, greetings against the groups)."""
