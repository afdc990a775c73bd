"""The tables docs/groups.md shows of groups from the stream (``stream``'s results), and
the command prints."""

from __future__ import annotations

import statistics
from typing import Any


def _memory(m: dict[str, float]) -> str:
    if m["heading_s"] == 0 and m["together_s"] == 0:
        return "none (frame by frame)"
    return f"headings {m['heading_s']:g} s, pairs {m['together_s']:g} s"


def _after(seconds: list[float | None]) -> str:
    if not seconds:
        return "(no change)"
    return ", ".join("never" if s is None else f"{s:.1f} s" for s in seconds)


def _lengths(results: dict[str, Any], key: str) -> str:
    return ", ".join(f"{x:g}" for x in sorted({m[key] for m in results["compared"]}))


def tables(results: dict[str, Any]) -> list[str]:
    """The Markdown tables docs/groups.md shows (and the command prints)."""
    return _sequences(results) + _made(results) + _live(results)


def _sequences(results: dict[str, Any]) -> list[str]:
    """Each shared sequence as a stream, held out by dataset, beside frame by frame."""
    rows = results["sequences"]
    lines = [
        "Each shared sequence as a stream, held out by dataset (its memory chosen on the other"
        " three datasets' sequences), F1 at T = 2/3 with its 95 % interval over frames, beside"
        " the same frames judged frame by frame (the memory off) and GCFF with one set; T = 1"
        " in brackets; the difference stream - frame by frame with its paired interval:",
        "",
        "| sequence | spacing | frames | GCFF one set | frame by frame | **stream** | difference"
        " | memory chosen without its dataset |",
        "| --- | ---: | ---: | ---: | --- | --- | --- | --- |",
    ]
    for s, r in rows.items():
        ours, theirs, d = r["stream"], r["frame_by_frame"], r["difference"]
        lines.append(
            f"| {s} | {r['spacing_s']:g} s | {r['frames']} | {r['gcff_one_set']:.2f}"
            f" | {theirs['f1_23']:.2f} [{theirs['f1_23_interval'][0]:.2f},"
            f" {theirs['f1_23_interval'][1]:.2f}] ({theirs['f1_1']:.2f})"
            f" | **{ours['f1_23']:.2f}** [{ours['f1_23_interval'][0]:.2f},"
            f" {ours['f1_23_interval'][1]:.2f}] ({ours['f1_1']:.2f})"
            f" | {d[0]:+.2f} [{d[1]:+.2f}, {d[2]:+.2f}] | {_memory(ours['memory'])} |"
        )
    for what, pick in (("worst", min), ("mean", statistics.mean)):
        gcff = pick(r["gcff_one_set"] for r in rows.values())
        plain = pick(r["frame_by_frame"]["f1_23"] for r in rows.values())
        ours = pick(r["stream"]["f1_23"] for r in rows.values())
        lines.append(f"| {what} | | | {gcff:.2f} | {plain:.2f} | **{ours:.2f}** | | |")
    return lines


def _made(results: dict[str, Any]) -> list[str]:
    """The memories compared, the one shipped, and the made streams."""
    default = results["default"]["memory"]
    lines = [
        "",
        f"{len(results['compared'])} memories compared (heading time constants"
        f" {_lengths(results, 'heading_s')} s by pair spans {_lengths(results, 'together_s')} s),"
        f" {len(results['eligible'])} of them saying every change of the made streams within"
        f" {results['say_within_s']:g} s; the shipped memory (chosen on all six):"
        f" {_memory(default)}.",
        "",
        "The made streams (`benchmarks/groups/stream_scenes.py`: not data), the shipped memory"
        " beside frame by frame: F1 at T = 2/3 (T = 1), and how long after the first frame"
        " that shows a change the groups said were exactly the true ones:",
        "",
        "| stream | frame by frame | said after | **stream** | said after |",
        "| --- | ---: | --- | ---: | --- |",
    ]
    made = results["scenes"]
    for name, ours in made["stream"].items():
        plain = made["frame_by_frame"][name]
        lines.append(
            f"| {name} | {plain['f1_23']:.2f} ({plain['f1_1']:.2f})"
            f" | {_after(plain['said_after_s'])}"
            f" | **{ours['f1_23']:.2f}** ({ours['f1_1']:.2f}) | {_after(ours['said_after_s'])} |"
        )
    return lines + _spacing(results)


def _spacing(results: dict[str, Any]) -> list[str]:
    """The stated spacings halved and doubled."""
    if "spacing" not in results:
        return []
    rows = results["sequences"]
    factors = list(next(iter(results["spacing"].values())))
    lines = [
        "",
        "Where the data gives no time (CoffeeBreak, GDet's frame rate), the stated spacing"
        " halved and doubled, the shipped memory, F1 at T = 2/3:",
        "",
        "| sequence | stated spacing | at it | " + " | ".join(f"x{f}" for f in factors) + " |",
        "| --- | ---: | ---: |" + " ---: |" * len(factors),
    ]
    at_stated = results["default"]["f1_23"]
    for s, figures in results["spacing"].items():
        lines.append(
            f"| {s} | {rows[s]['spacing_s']:g} s | {at_stated[s]:.2f} | "
            + " | ".join(f"{figures[f]:.2f}" for f in factors)
            + " |"
        )
    return lines


def _live(results: dict[str, Any]) -> list[str]:
    """The shipped memory through the live service, beside the core."""
    lines: list[str] = []
    if "live" in results:
        lines += [
            "",
            "The shipped memory through the live service (JSON poses at 30 Hz, each frame held"
            " its spacing, `hri/groups/<frame>` asked at its end) beside the core replaying the"
            " same frames (in-sample: it shows the service says what the core decides). The"
            " service lists people by id, the replay in the data's order; the grouping reads"
            " neither (its ties go by place), so a frame said otherwise is timing (the"
            " last poses of a hold heard after the ask, the scene's tick against the frame's"
            " change):",
            "",
            "| sequence | live, T = 2/3 | T = 1 | core, T = 2/3 | T = 1 | frames said alike |",
            "| --- | ---: | ---: | ---: | ---: | ---: |",
        ]
        for s, r in results["live"].items():
            lv, core = r["live"], r["core"]
            lines.append(
                f"| {s} | {lv['f1_23']:.2f} | {lv['f1_1']:.2f} | {core['f1_23']:.2f}"
                f" | {core['f1_1']:.2f} | {r['same_frames']} of {r['frames']} |"
            )
    return lines
