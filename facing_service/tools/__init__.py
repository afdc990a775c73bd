"""The commands that put the layers together for a user: ``demo`` (service, simulator and
watch in one process), ``replay`` (a recording onto zenoh as a robot sends it), ``inspect``
(what a robot's zenoh carries), ``router`` (a zenoh router for robot and service) and
``loopback`` (sessions on 127.0.0.1, for the demo and the tests)."""
