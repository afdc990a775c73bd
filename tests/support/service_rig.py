"""What the shell's end-to-end tests share: the keys of a service on frame 'cam'."""

from __future__ import annotations

NAMESPACE = "hri"
FRAME_KEY = "hri/facing/cam"


def body_key(body: str, frame: str = "cam") -> str:
    return f"{NAMESPACE}/bodies/{body}/facing/{frame}"


def pose_key(body: str, frame: str = "cam") -> str:
    return f"{NAMESPACE}/bodies/{body}/pose/{frame}"
