"""The tables docs/groups.md shows of where the robot should stand (``join``'s results),
and the command prints."""

from __future__ import annotations

import math
from typing import Any


def _m(value: float | None) -> str:
    return "—" if value is None or math.isnan(value) else f"{value:.2f}"


def _deg(value: float | None) -> str:
    return "—" if value is None else f"{value:.0f}"


def tables(results: dict[str, Any]) -> list[str]:
    lines = [
        "Each member of each annotated group of three or more left out in turn (SALSA: every"
        " third frame), the robot at each of ten places around the remaining members (four"
        " directions at 2 and 4 m, and 30 m away on two sides); the join held out by dataset"
        " (its parameters chosen on the other datasets, among"
        f" {results['settings_compared']} settings), the first rule (the free arc nearest the"
        " robot) before it, and the two baselines on the same cases: share given a place,"
        " median distance to where the member stood [95 % interval], share within 0.5 m,"
        " median heading error, and how far the median moves with where the robot stands"
        " (over every case; over the groups with one clear gap):",
        "",
        "| sequence | cases | found | median m | within 0.5 m | heading ° | robot moves it m"
        " (one gap) | before: found | median m | robot moves it m (one gap) | centroid m"
        " | naive slot m |",
        "| --- | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for s, r in results["sequences"].items():
        j, b, c, n = r["join"], r["before"], r["centroid"], r["naive_slot"]
        lo, hi = j["median_m_interval"]
        lines.append(
            f"| {s} | {r['cases']} | {j['found']:.0%} | **{_m(j['median_m'])}** [{_m(lo)},"
            f" {_m(hi)}] | {j['within_half_m']:.0%} | {_deg(j['heading_deg'])}"
            f" | {_m(j['robot_spread_m'])} ({_m(j['one_gap_robot_spread_m'])})"
            f" | {b['found']:.0%} | {_m(b['median_m'])}"
            f" | {_m(b['robot_spread_m'])} ({_m(b['one_gap_robot_spread_m'])})"
            f" | {_m(c['median_m'])} | {_m(n['median_m'])} |"
        )
    for key, intro in (("live", LIVE), ("replayed", REPLAYED)):
        if key in results:
            lines += ["", *_live_table(results[key], intro)]
    lines += ["", *_pair_table(results)]
    d = results["chosen_on_all"]
    lines += [
        "",
        f"Overall median (the set chosen on all six): {results['overall_median_m']:.2f} m."
        f" The shipped set: stride {d['stride_k']:g}x the members' spacing, clearance"
        f" {d['clearance_k']:g}x their nearest spacing and at least {d['min_clearance_m']:g} m,"
        f" the ring at least {d['min_radius_m']:g} m,"
        + (
            " the widest free arc, the robot breaking exact ties."
            if d["tie"] == 1
            else f" the widest free arc, the robot choosing among arcs at least {d['tie']:g}"
            " of its width."
        ),
    ]
    return lines


LIVE = (
    "Through the live service (JSON poses at 30 Hz; `hri/groups/<frame>` queried at the"
    " end), the robot at four places 3 m around the remaining members and one 30 m away:"
    " *stays*, each case's frame without the member from the start, held 0.6 s (the"
    " place is inferred from the remaining people alone); *walks away*, the whole frame"
    " held 0.6 s, then the member gone for 0.6 s (as a robot sees it happen). A place is"
    " given only for a group the service found holding the remaining members; its"
    " distance to where the member stood, beside the centroid's and the naive slot's on"
    " the same cases [95 % intervals over cases]:"
)
REPLAYED = (
    "The same through the service's own scene alone (`FrameScene` worked out at the"
    " service's rate, no zenoh: the same places as the live service case for case, which"
    " a test holds), over every case of every sequence (`--replayed`):"
)


def _live_table(live: dict[str, Any], intro: str) -> list[str]:
    lines = [
        intro,
        "",
        "| sequence | cases | stays: given a place | median m | robot moves it m | walks away:"
        " given a place | median m | centroid m | naive slot m |",
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for s, r in live.items():
        st, wa = r["stays"], r["walks_away"]
        lines.append(
            f"| {s} | {r['cases']} | {_share(st)} | {_median(st)}"
            f" | {_m(st['robot_spread_m'])} | {_share(wa)} | {_median(wa)}"
            f" | {_m(r['centroid_median_m'])} | {_m(r['naive_slot_median_m'])} |"
        )
    return lines


def _share(run: dict[str, Any]) -> str:
    lo, hi = run["placed_interval"]
    return f"{run['placed']:.0%} [{lo:.0%}, {hi:.0%}]"


def _median(run: dict[str, Any]) -> str:
    lo, hi = run["median_m_interval"]
    return f"{_m(run['median_m'])} [{_m(lo)}, {_m(hi)}]"


def _pair_table(results: dict[str, Any]) -> list[str]:
    """What the remaining pair says, per sequence."""
    intro = (
        "Where two members remain (every such case above): the left-out member more along"
        " the pair's axis than beside it, the pair's headings pointing to the member's"
        " side (of the cases where they point to a side), and the pair on a ring (0.25 to"
        " 2 m) both face within 45° and within 60° of its centre (`pair_ring.py`: what the"
        " pair alone says of a group):"
    )
    header = (
        "| sequence | two remain | along the axis | headings point to a side | to the right side"
        " | a ring both face, 45° | 60° |"
    )
    rows = [_pair_row(s, r["pair_sides"]) for s, r in results["sequences"].items()]
    return [intro, "", header, "| --- | ---: | ---: | ---: | ---: | ---: | ---: |", *rows]


def _pair_row(sequence: str, ps: dict[str, int]) -> str:
    ring_45, ring_60 = (ps[k] / max(ps["pairs"], 1) for k in ("ring_45", "ring_60"))
    right = ps["right_side"] / max(ps["pointing"], 1)
    return (
        f"| {sequence} | {ps['pairs']} | {ps['along']} | {ps['pointing']}"
        f" | {ps['right_side']} ({right:.0%}) | {ring_45:.0%} | {ring_60:.0%} |"
    )
