"""The terminal view's drawing, pure: any person anywhere, any label, any map size, draws
without error and within the map (the demo crashed after a minute, at the right edge)."""

from __future__ import annotations

import io
import math

from hypothesis import given, settings
from hypothesis import strategies as st
from rich.console import Console, Group, RenderableType
from rich.panel import Panel
from rich.text import Text

from facing_service.client.sim import Crowd
from facing_service.client.watch import PersonView, render

coordinate = st.floats(min_value=-6.0, max_value=6.0, allow_nan=False)
label = st.text(alphabet="abcdefghijklmnopqrstuvwxyz_0123456789", min_size=1, max_size=30)


def canvas_rows(renderable: RenderableType) -> list[str]:
    """The map's rows, as drawn in its panel (rendered to text first, as a terminal would)."""
    Console(width=200, file=io.StringIO()).print(renderable)
    assert isinstance(renderable, Group)
    panel = renderable.renderables[0]
    assert isinstance(panel, Panel) and isinstance(panel.renderable, Text)
    return panel.renderable.plain.split("\n")


@settings(max_examples=300, deadline=None)
@given(
    people=st.lists(st.tuples(label, coordinate, coordinate, st.booleans()), max_size=8),
    width=st.integers(min_value=3, max_value=81),
    height=st.integers(min_value=3, max_value=41),
)
def test_any_person_anywhere_draws_within_the_map(people, width, height):
    views = [
        PersonView(name, x, y, 0.0, facing, 10.0, math.hypot(x, y), 20.0, 1.0)
        for name, x, y, facing in people
    ]
    rows = canvas_rows(render(views, "base_link", width=width, height=height))
    assert len(rows) == height
    assert all(len(row) == width for row in rows)


def test_a_person_at_the_right_edge_is_labelled_as_far_as_the_map_goes():
    """x = 0, y = -3.9 lands on the last column: the label had no room and its slice became
    ``label[:-1]``, written past the row's end (the demo's IndexError)."""
    view = PersonView("person_7", 0.0, -3.9, 90.0, True, 5.0, 3.9, 20.0, 1.0)
    robot_row = next(row for row in canvas_rows(render([view], "base_link")) if "R" in row)
    assert robot_row.endswith("←")  # the arrow drawn, no label written past it
    near = PersonView("person_7", 0.0, -3.6, 90.0, True, 5.0, 3.6, 20.0, 1.0)
    robot_row = next(row for row in canvas_rows(render([near], "base_link")) if "R" in row)
    assert robot_row.endswith("←pe")  # as much of the label as fits


def test_ten_minutes_of_simulated_crowds_draw_at_every_edge():
    """The demo's crowd, sped up: ten minutes of twelve people walking to and past the
    map's edges, drawn at every tick at the demo's size and at a small one."""
    crowd = Crowd(people=12, seed=3)
    seen_at_edge = 0
    for _ in range(6000):  # 600 s at 10 Hz
        tick = crowd.step(0.1)
        views = [
            PersonView(p.body_id, p.x, p.y, p.yaw_deg, False, None, None, 20.0, None)
            for p in tick.poses
        ]
        seen_at_edge += any(abs(v.y) > 3.5 or abs(v.x) > 3.5 for v in views)
        render(views, "base_link")
        render(views, "base_link", radius_m=2.0, width=11, height=5)
    assert seen_at_edge > 100  # the crowd did reach the edges
