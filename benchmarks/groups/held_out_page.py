"""The tables docs/groups.md shows of the frame-by-frame rules held out by dataset
(``held_out``'s results), and the command prints."""

from __future__ import annotations

import statistics
from typing import Any

#: The rules compared, from the simplest (fewest lengths searched and learnt) up.
RULES = {
    "gcff": "GCFF's rule (one stride), in metres",
    "ring": "the ring's centre, in metres",
    "metres": "each person's stride, in metres",
    "room_gcff": "GCFF's rule, in the room's unit",
    "room": "each person's stride, in the room's unit (the last default's rule)",
}
#: The baseline every rule is set beside: GCFF's fixed stride in metres.
INCUMBENT = "gcff"


def worst_held_out(results: dict[str, Any], rule: str) -> float:
    """A rule's worst sequence, each held out by dataset (F1, T = 2/3)."""
    return min(held(results, s, rule)["f1_23"] for s in results["sequences"])


def held(results: dict[str, Any], sequence: str, rule: str) -> dict[str, Any]:
    """A rule's figures on a sequence, its set chosen without that sequence's dataset."""
    figures: dict[str, Any] = results["sequences"][sequence][rule]["dataset"]
    return figures


def _params(c: dict[str, Any]) -> str:
    g, s = c["groups"], c["scale"]
    unit = (
        "m"
        if s["min_m"] == s["max_m"]
        else f"room ({s['window_s']:g} s, {s['min_m']:g} to {s['max_m']:g} m)"
    )
    if g["stride_min"] == g["stride_max"]:
        stride = f"stride {g['stride_min']:g}"
    elif g.get("ring"):
        stride = (f"the ring's centre ({g['stride_k']:g} of the reach), within "
                  f"[{g['stride_min']:g}, {g['stride_max']:g}]")  # fmt: skip
    else:
        stride = f"stride {g['stride_k']:g}x [{g['stride_min']:g}, {g['stride_max']:g}]"
    return f"{stride}, MDL {g['mdl']:g}, unit {unit}"


def tables(results: dict[str, Any]) -> list[str]:
    """The Markdown tables docs/groups.md shows (and the command prints)."""
    return _held_out(results) + _by_sequence(results) + _steps(results) + _scenes(results)


def _held_out(results: dict[str, Any]) -> list[str]:
    """Each rule held out by dataset, the shipped one with its interval."""
    rows, best = results["sequences"], results["preferred"]
    others = [r for r in RULES if r != best]
    name = {r: RULES[r] for r in RULES}
    lines = [
        f"Held out by dataset (each dataset scored with the set chosen on the other three), F1 at"
        f" T = 2/3; the shipped rule, {name[best]}, with its 95 % interval over frames, T = 1"
        f" and the same people 1.5x farther apart beside it:",
        "",
        "| sequence | frames | no groups | **shipped**, T = 2/3 | T = 1 | 1.5x wider | "
        + " | ".join(name[r] for r in others)
        + " | GCFF one set | GCFF median set (port) | GCFF tuned |",
        "| --- | ---: | ---: | --- | ---: | ---: |" + " ---: |" * (len(others) + 3),
    ]
    for s, r in rows.items():
        ours = r[best]["dataset"]
        lo, hi = ours["f1_23_interval"]
        lines.append(
            f"| {s} | {r['frames']} | {r['floor']:.2f} | **{ours['f1_23']:.2f}** [{lo:.2f},"
            f" {hi:.2f}] | {ours['f1_1']:.2f} | {ours['wider_f1_23']:.2f} | "
            + " | ".join(f"{r[o]['dataset']['f1_23']:.2f}" for o in others)
            + f" | {r['gcff_one_set']:.2f} | {r['gcff_median_port']:.2f} | {r['gcff_tuned']:.2f} |"
        )
    lines.append(
        "| **worst** | | | **"
        + f"{worst_held_out(results, best):.2f}** | | | "
        + " | ".join(f"{worst_held_out(results, o):.2f}" for o in others)
        + " | "
        + " | ".join(
            f"{min(r[k] for r in rows.values()):.2f}"
            for k in ("gcff_one_set", "gcff_median_port", "gcff_tuned")
        )
        + " |"
    )
    lines.append(
        "| mean | | | "
        + f"{statistics.mean(r[best]['dataset']['f1_23'] for r in rows.values()):.2f} | | | "
        + " | ".join(
            f"{statistics.mean(r[o]['dataset']['f1_23'] for r in rows.values()):.2f}"
            for o in others
        )
        + " | "
        + " | ".join(
            f"{statistics.mean(r[k] for r in rows.values()):.2f}"
            for k in ("gcff_one_set", "gcff_median_port", "gcff_tuned")
        )
        + " |"
    )
    return lines


def _by_sequence(results: dict[str, Any]) -> list[str]:
    """Held out by sequence, and the shipped rule against the baseline."""
    rows, best = results["sequences"], results["preferred"]
    base = RULES[INCUMBENT]
    lines = [
        "",
        f"Held out by sequence (each scored with the set chosen on the other five), and the"
        f" difference shipped - {base} (the baseline), both held out by dataset [paired 95 %"
        f" interval over frames]:",
        "",
        "| sequence | shipped | baseline | difference, as recorded | 1.5x wider |"
        " set chosen without its dataset |",
        "| --- | ---: | ---: | --- | --- | --- |",
    ]
    for s, r in rows.items():
        d, w = r["preferred_minus_baseline"]["recorded"], r["preferred_minus_baseline"]["wider"]
        lines.append(
            f"| {s} | {r[best]['sequence']['f1_23']:.2f} | {r[INCUMBENT]['sequence']['f1_23']:.2f}"
            f" | {d[0]:+.2f} [{d[1]:+.2f}, {d[2]:+.2f}] | {w[0]:+.2f} [{w[1]:+.2f}, {w[2]:+.2f}]"
            f" | {_params(r[best]['dataset'])} |"
        )
    return lines


def _steps(results: dict[str, Any]) -> list[str]:
    """Each richer rule set beside the incumbent, and the default shipped."""
    name, best = RULES, results["preferred"]
    lines = [
        "",
        "From the simplest rule that fails no made scene another passes, each richer one set"
        " beside the incumbent on the incumbent's worst held-out sequence [paired 95 %"
        " interval over frames]:",
        "",
        "| challenger | incumbent | on | difference | |",
        "| --- | --- | --- | --- | --- |",
    ]
    for step in results["steps"]:
        mean, lo, hi = step["difference"]
        lines.append(
            f"| {name[step['challenger']]} | {name[step['incumbent']]} | {step['sequence']}"
            f" | {mean:+.2f} [{lo:+.2f}, {hi:+.2f}] |"
            f" {_verdict(step)} |"
        )
    lines += ["", f"The shipped default (chosen on all six): {_params(results['default'][best])}."]
    return lines


def _scenes(results: dict[str, Any]) -> list[str]:
    """Each rule on the made scenes."""
    name = RULES
    lines = [
        "",
        "On the made scenes (`benchmarks/groups/scenes.py`: not data; a rule failing one that"
        " another passes is not shipped), each rule's set chosen on all six, F1 at T = 2/3"
        " (T = 1):",
        "",
        "| scene | frames | no groups | " + " | ".join(name[r] for r in RULES) + " |",
        "| --- | ---: | ---: |" + " ---: |" * len(RULES),
    ]
    for scene, r in results["scenes"].items():
        lines.append(
            f"| {scene} | {r['frames']} | {r['floor']:.2f} | "
            + " | ".join(f"{r[k]:.2f} ({r[k + '_1']:.2f})" for k in RULES)
            + " |"
        )
    return lines


def _verdict(step: dict[str, Any]) -> str:
    if step["replaces"]:
        return "replaces it"
    if step["difference"][1] > 0:  # better, with its interval above 0, yet not in metres
        return "kept out: not in metres (lost outside)"
    return "kept out"
