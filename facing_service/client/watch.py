"""``facing-service watch``: a live terminal view of a running deployment.

A top-down map around the robot (each person drawn where they stand, as an arrow along
their heading; people facing the robot highlighted and labelled) beside a table of id,
facing, angle, distance and since when. ``render`` is pure (plain data in, a rich
renderable out) so the view is tested without a terminal; ``Watcher`` gathers the data
from zenoh. The rows and the map are what the service publishes (its results, with where
each person stands and faces, and engagement levels), whatever its input: JSON poses or
a ROS 2 robot's topics.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import zenoh
from rich.console import Console, Group, RenderableType
from rich.live import Live
from rich.panel import Panel
from rich.table import Table
from rich.text import Text

from ..contract import keys
from ..contract.errors import FacingError
from ..contract.schemas import FacingState, GroupState
from ..contract.stamps import Time
from .client import FacingClient
from .condition import InputCondition

#: Arrows for a heading in the map (base x is up, base y is left), every 45 degrees.
_ARROWS = "↑↖←↙↓↘→↗"


@dataclass(frozen=True)
class PersonView:
    body_id: str
    x: float  # where the person stands, and their heading, in the base frame
    y: float
    yaw_deg: float
    facing: bool
    angle_deg: float | None
    distance_m: float | None
    threshold_deg: float  # the facing cone the service applied (the page draws it)
    since_s: float | None  # how long the facing decision has held, in pose time
    engagement: str | None = None  # the engagement level, when known
    since_seen: bool = True  # False: held since before the view started (at least since_s)


def arrow(yaw_deg: float) -> str:
    return _ARROWS[round((yaw_deg % 360) / 45) % 8]


#: What the screen's marks and columns mean, said under it (a newcomer asked).
LEGEND = (
    "arrows: where each person faces (green: facing the robot R, yellow: not); "
    "held s: how long the facing decision has held (≥: at least, already so when this "
    "view first saw them); "
)
#: How the service decides engagement, by its --engagement mode (its status says which).
ENGAGEMENT_LEGENDS = {
    "service": "engagement needs more than facing: a score that falls with distance past "
    "2.5 m (0 at 4.5 m) held about a second (docs/engagement.md)",
    "rule": "engagement is hri_engagement's rule: mutual gaze and distance voted every 0.1 s "
    "over a 10 s window, no level for the first 5 s (docs/engagement.md)",
}
#: The lines the map needs at the least, and at the most (its width follows).
MAP_ROWS = (7, 19)
#: How often a frame is written when the output is no terminal (a file, a pipe, a log).
FRAME_S = 1.0


def render(
    people: list[PersonView],
    frame_id: str,
    radius_m: float = 4.0,
    width: int = 41,
    height: int = 19,
    elsewhere: dict[str, int] | None = None,
    groups: Sequence[GroupState] = (),
    legend: str | None = LEGEND + ENGAGEMENT_LEGENDS["service"],
    note: str | None = None,
) -> RenderableType:
    """The map and the table for one instant; ``elsewhere``: people tracked in other
    frames (frame -> how many), said when this frame has nobody; ``groups``: the frame's
    F-formations (each centre drawn ``o``, each member's group in the table); ``legend``
    under the table (None: none); ``note``: what the service's input gives now, when it
    is not heard (``condition.input_note``), said above the table."""
    canvas = _map(people, radius_m, width, height, groups)
    table = _table(people, frame_id, groups, legend)
    facing = sum(1 for p in people if p.facing)
    title = f"{facing} of {len(people)} facing the robot (R); 1 m rings; x up, y left"
    parts: list[RenderableType] = [Panel(canvas, title=title, expand=False)]
    if note is not None:
        parts.append(Text(note, style="bold red"))
    others = {f: n for f, n in (elsewhere or {}).items() if f != frame_id and n}
    if not people and others:
        said = ", ".join(f"{f} ({n})" for f, n in sorted(others.items()))
        first = sorted(others)[0]
        parts.append(
            Text(
                f"nobody in frame {frame_id}; people are tracked in {said}: "
                f"watch --base-frame {first}",
                style="bold yellow",
            )
        )
    parts.append(table)
    if groups:
        said = "; ".join(
            f"{g.id}: {', '.join(g.members)}" + (" and the robot" if g.robot else "")
            for g in groups
        )
        parts.append(Text(f"groups (o): {said}", style="magenta"))
    return Group(*parts)


def _map(
    people: list[PersonView],
    radius_m: float,
    width: int,
    height: int,
    groups: Sequence[GroupState],
) -> Text:
    """The top-down map: 1 m rings, the o-space centres, the robot, each person an arrow
    along their heading, named as far as it fits."""
    grid = [[" "] * width for _ in range(height)]
    styles: dict[tuple[int, int], str] = {}
    cx, cy = width // 2, height // 2
    scale_x, scale_y = (width // 2) / radius_m, (height // 2) / radius_m
    for row in range(height):  # range rings at 1 m
        for col in range(width):
            r = math.hypot((col - cx) / scale_x, (row - cy) / scale_y)
            if abs(r - round(r)) < 0.06 and 0 < round(r) <= radius_m:
                grid[row][col] = "·"
                styles[(row, col)] = "grey35"
    for group in groups:  # o-space centres, under the people drawn over them
        col, row = cx - round(group.centre.y * scale_x), cy - round(group.centre.x * scale_y)
        if 0 <= row < height and 0 <= col < width:
            grid[row][col] = "o"
            styles[(row, col)] = "bold magenta"
    grid[cy][cx] = "R"
    styles[(cy, cx)] = "bold cyan"
    for person in sorted(people, key=lambda p: keys.natural_order(p.body_id)):
        col, row = cx - round(person.y * scale_x), cy - round(person.x * scale_y)
        if not (0 <= row < height and 0 <= col < width):
            continue
        style = "bold green" if person.facing else "yellow"
        grid[row][col] = arrow(person.yaw_deg)
        styles[(row, col)] = style
        room = width - col - 1  # the columns right of the arrow, up to the map's edge
        for i, char in enumerate(person.body_id[:room]):  # every arrow named, as far as fits
            grid[row][col + 1 + i] = char
            styles[(row, col + 1 + i)] = "green" if person.facing else "yellow"
    canvas = Text()
    for row in range(height):
        for col in range(width):
            canvas.append(grid[row][col], styles.get((row, col), ""))
        if row < height - 1:
            canvas.append("\n")
    return canvas


def fitted(
    draw: Callable[[int, int, str | None], RenderableType],
    legend: str,
    columns: int,
    lines: int,
) -> RenderableType:
    """``draw(map_width, map_rows, legend)`` made to fit a terminal of ``columns`` x
    ``lines`` with every person's row (on 80x24 the table's rows were cut after
    its header): measured with the smallest map, the legend goes first, then the map
    takes what is left, between MAP_ROWS' bounds (odd: the robot on the middle row)."""
    low, high = MAP_ROWS
    for shown in (legend, None):
        spare = lines - 1 - _lines(draw(_map_width(low, columns), low, shown), columns)
        if spare >= 0 or shown is None:  # (Live keeps the last line for its cursor)
            rows = max(low, min(high, low + spare))
            rows -= 1 - rows % 2
            return draw(_map_width(rows, columns), rows, shown)
    raise AssertionError("unreachable: the last try takes what it gets")


def _map_width(rows: int, columns: int) -> int:
    """As wide as a round map of ``rows`` looks in a terminal's cells, within the screen."""
    return max(min(2 * rows + 3, columns - 2), 5)


def _lines(renderable: RenderableType, columns: int) -> int:
    console = Console(width=columns, file=io.StringIO(), color_system=None)
    return len(console.render_lines(renderable, console.options, pad=False))


def _table(
    people: list[PersonView], frame_id: str, groups: Sequence[GroupState], legend: str | None
) -> Table:
    """One row a person: facing, angle, distance, how long it held, engagement, group."""
    table = Table(title=f"frame {frame_id}", caption=legend, caption_justify="left", expand=False)
    group_of = {m: g.id + (" +R" if g.robot else "") for g in groups for m in g.members}
    for name in ("id", "facing", "angle °", "distance m", "held s", "engagement", "group"):
        table.add_column(name, justify="left" if name == "id" else "right")
    for person in sorted(people, key=lambda p: keys.natural_order(p.body_id)):
        table.add_row(
            person.body_id,
            "yes" if person.facing else "no",
            _number(person.angle_deg, 1),
            _number(person.distance_m, 2),
            ("" if person.since_seen or person.since_s is None else "≥")
            + _number(person.since_s, 1),
            Text(
                person.engagement or "-",
                style="bold magenta" if person.engagement == "ENGAGED" else "",
            ),
            group_of.get(person.body_id, "-"),
            style="bold green" if person.facing else None,
        )
    return table


def _number(value: float | None, digits: int) -> str:
    return "-" if value is None else f"{value:.{digits}f}"


class Watcher:
    """Gathers what ``render`` needs from the service's outputs alone (results, levels,
    aggregates, groups), so it draws people on any input, a robot's ROS 2 topics too."""

    def __init__(self, client: FacingClient, frame: str) -> None:
        self.client = client
        self.frame = frame
        self._lock = threading.Lock()
        # body -> (facing, pose time it began, whether the view saw it begin, latest time)
        self._since: dict[str, tuple[bool, float, bool, float]] = {}
        self._levels: dict[str, str] = {}
        self._frames: dict[str, int] = {}  # frame -> people tracked there (aggregates)
        self.legend = LEGEND + ENGAGEMENT_LEGENDS["service"]  # the service's mode: ask_frames
        self.condition = InputCondition(client)  # asked by ask_frames, and while live
        # Already tracked when the view opened: their decision began before it, so held
        # is "at least"; anyone else's first result is when their decision began.
        self._there_before = set(client.bodies(frame)) if frame != keys.ALL_FRAMES else set()
        aggregates = keys.frame_key(client.namespace, keys.ALL_FRAMES)
        levels = keys.engagement_key(client.namespace, body_id=keys.ALL_FRAMES, frame_id=frame)
        for key, handle in ((aggregates, self._on_frame), (levels, self._on_engagement)):
            client.hear(key, handle)  # closed with the client
        client.on_change(self._on_result)
        client.on_lost(self._on_lost)

    def _on_frame(self, sample: zenoh.Sample) -> None:
        """Every frame's aggregate: which frames have people (said when this one has none)."""
        with contextlib.suppress(ValueError, KeyError, TypeError):
            message = json.loads(sample.payload.to_bytes())
            with self._lock:
                self._frames[message["frame_id"]] = len(message["bodies_tracked"])

    def frames(self) -> dict[str, int]:
        """How many people each frame tracks, as the aggregates last said."""
        with self._lock:
            return dict(self._frames)

    def ask_frames(self) -> None:
        """Ask the service which frames have people now (the aggregates are also
        published on every change; this answers at once), and how it decides engagement
        (its status: the legend explains that mode's)."""
        with contextlib.suppress(FacingError, zenoh.ZError):
            statuses = self.client.status()
            self.condition.refresh(statuses)
            modes = {str(s.config.get("engagement", "service")) for s in statuses}
            if len(modes) == 1 and (mode := modes.pop()) in ENGAGEMENT_LEGENDS:
                self.legend = LEGEND + ENGAGEMENT_LEGENDS[mode]
        with contextlib.suppress(zenoh.ZError):
            for reply in self.client.session.get(
                keys.frame_key(self.client.namespace, keys.ALL_FRAMES), timeout=2.0
            ):
                if reply.ok is not None:
                    self._on_frame(reply.ok)

    def _on_engagement(self, sample: zenoh.Sample) -> None:
        self._update(self._levels, sample, lambda message: message["level"])

    def _update(
        self, store: dict[str, Any], sample: zenoh.Sample, read: Callable[[Any], Any]
    ) -> None:
        """Keep what ``read`` takes from each body's latest message; a DELETE forgets it.
        Unreadable input is skipped: the service counts bad input, the view just draws."""
        body_id = keys.body_of(str(sample.key_expr)).body_id
        with self._lock:
            if sample.kind == zenoh.SampleKind.DELETE:
                store.pop(body_id, None)
                return
            with contextlib.suppress(ValueError, KeyError, TypeError):
                store[body_id] = read(json.loads(sample.payload.to_bytes()))

    def _on_result(self, state: FacingState) -> None:
        """How long each decision has held, in the poses' own time (so a replayed
        recording reads right, and ``--once`` does not say "1.0" for everyone)."""
        if state.frame_id != self.frame:
            return
        t = Time.from_model(state.stamp).seconds
        with self._lock:
            previous = self._since.get(state.body_id)
            if previous is None:
                seen_begin = state.body_id not in self._there_before
                self._since[state.body_id] = (state.facing, t, seen_begin, t)
            elif previous[0] != state.facing:
                self._since[state.body_id] = (state.facing, t, True, t)
            else:
                self._since[state.body_id] = (*previous[:3], max(previous[3], t))

    def _on_lost(self, body: keys.BodyRef) -> None:
        if body.frame_id == self.frame:
            with self._lock:
                self._since.pop(body.body_id, None)
                self._there_before.discard(body.body_id)  # back later: seen from its start

    def people(self) -> list[PersonView]:
        states = self.client.bodies(self.frame)
        with self._lock:
            since = dict(self._since)
            levels = dict(self._levels)
        people = []  # one a participant: the service says a person's face and body as one
        for body_id, state in states.items():
            changed = since.get(body_id)
            people.append(
                PersonView(
                    body_id,
                    state.position.x,
                    state.position.y,
                    state.heading_deg,
                    state.facing,
                    state.angle_deg,
                    state.distance_m,
                    state.threshold_deg,
                    None if changed is None else changed[3] - changed[1],
                    levels.get(body_id),
                    changed is None or changed[2],
                )
            )
        return people

    def view(self, size: tuple[int, int] | None = None) -> RenderableType:
        """The screen; ``size`` (columns, lines): fitted to a terminal of that size."""
        groups, people, elsewhere = self.client.groups(self.frame), self.people(), self.frames()

        note = self.condition.note

        def draw(width: int, height: int, legend: str | None) -> RenderableType:
            return render(people, self.frame, width=width, height=height,
                          elsewhere=elsewhere, groups=groups, legend=legend, note=note)  # fmt: skip

        return draw(41, 19, self.legend) if size is None else fitted(draw, self.legend, *size)

    def live(self, keep_going: Callable[[], bool], period_s: float = 0.1) -> None:
        """Redraw in the terminal every ``period_s`` while ``keep_going()``, fitted to its
        size (read each time: a resized window refits); the last frame stays on screen.
        Not a terminal (a file, a pipe): a whole frame every ``FRAME_S`` as it goes, where
        rich's live display wrote nothing until the end."""
        console = Console()
        with self.condition:
            if not console.is_terminal:
                self._write_frames(console, keep_going, period_s)
                return
            with Live(self.view(console.size), console=console,
                      refresh_per_second=1 / period_s) as screen:  # fmt: skip
                while keep_going():
                    time.sleep(period_s)
                    screen.update(self.view(console.size))
                screen.update(self.view(console.size))

    def _write_frames(
        self, console: Console, keep_going: Callable[[], bool], period_s: float
    ) -> None:
        """A frame now, one every ``FRAME_S`` while ``keep_going()``, and the last one."""
        due = 0.0
        while True:
            going = keep_going()
            if not going or time.monotonic() >= due:
                console.print(self.view(console.size))
                console.line()
                console.file.flush()
                due = time.monotonic() + FRAME_S
            if not going:
                return
            time.sleep(period_s)

    def save_svg(self, path: Path) -> None:
        """The current frame as an SVG image (rich's export), e.g. for documentation."""
        console = Console(record=True, width=100, file=io.StringIO())
        console.print(self.view())
        console.save_svg(str(path), title="facing-service watch")
