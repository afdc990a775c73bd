"""``facing-service foxglove``: the scene of a running service, live in the Foxglove app,
served over Foxglove's WebSocket protocol by its own SDK (``foxglove.start_server``). The
same client and model as the live page (``client.view``): people, groups, who faces whom,
the places to join and greet, the robot, as ``/facing/scene`` (``foxglove.SceneUpdate``)
in the base frame, each person's frame on ``/facing/tf`` (``foxglove.FrameTransforms``),
and the page's model itself as JSON on ``/facing/model`` (for Foxglove's table panels).
Sent when it changes, checked ten times a second; entities deleted when people leave.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable

import foxglove
import foxglove.layouts as fl
from foxglove.channels import FrameTransformsChannel, SceneUpdateChannel
from foxglove.messages import FrameTransforms, Timestamp

from ..client.client import FacingClient
from ..client.view.live import page_model, watching
from .foxglove_scene import transforms, update

PERIOD_S = 0.1
SCENE, TF, MODEL = "/facing/scene", "/facing/tf", "/facing/model"


def serve_scene(
    client: FacingClient,
    frame: str,
    host: str,
    port: int,
    stopping: threading.Event,
    started: Callable[[str], None] = lambda url: None,
) -> None:
    """Serve ``frame``'s scene until ``stopping`` (blocking). Raises OSError when the
    address cannot be bound."""
    watcher = watching(client, frame)
    context = foxglove.Context()
    try:
        server = foxglove.start_server(name="facing-service", host=host, port=port,
                                       context=context)  # fmt: skip
    except RuntimeError as error:  # the SDK's error for an address in use
        raise OSError(str(error)) from error
    try:
        scene = SceneUpdateChannel(SCENE, context=context)
        tf = FrameTransformsChannel(TF, context=context)
        model_channel = foxglove.Channel(MODEL, context=context)
        started(f"ws://{host}:{server.port}")
        shown: set[str] = set()
        said = None
        with watcher.condition:
            while not stopping.wait(PERIOD_S):
                model = page_model(watcher)
                if (text := json.dumps(model, sort_keys=True)) == said:
                    continue
                said = text
                now = time.time_ns()
                stamp = Timestamp(sec=now // 1_000_000_000, nsec=now % 1_000_000_000)
                message, shown = update(model, shown, stamp)
                scene.log(message, log_time=now)
                tf.log(FrameTransforms(transforms=transforms(model, stamp)), log_time=now)
                model_channel.log(model, log_time=now)
    finally:
        server.stop()


def layout(frame: str = "base_link") -> str:
    """A Foxglove layout for the scene of ``frame`` (docs/foxglove-layout.json is this,
    for base_link): the 3D panel in the base frame beside a table of the people and the
    page's whole model, built with the SDK's own layout types."""
    three_d = fl.ThreeDeePanel(
        title="facing-service",
        config=fl.ThreeDeeConfig(
            fixed_frame=frame,
            follow_tf=frame,
            topics={SCENE: fl.BaseRendererSceneUpdateTopicSettings(visible=True)},
        ),
    )
    people = fl.TablePanel(title="people", config=fl.TableConfig(topic_path=f"{MODEL}.people"))
    whole = fl.RawMessagesPanel(title="model", config=fl.RawMessagesConfig(topic_path=MODEL))
    side = fl.SplitContainer(
        direction="column",
        items=[fl.SplitItem(proportion=1, content=people), fl.SplitItem(content=whole)],
    )
    content = fl.SplitContainer(
        direction="row",
        items=[fl.SplitItem(proportion=2, content=three_d), fl.SplitItem(content=side)],
    )
    return fl.Layout(content=content).to_json()
