"""The social scene of a base frame: ``groups`` (F-formations by GCFF's method, who faces
whom), ``join`` (where the robot should stand to join a group or greet someone), ``scene``
(both per frame over time, as said: held, rate-limited, greetings against the groups)."""
