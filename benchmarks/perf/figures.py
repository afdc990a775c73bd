"""Line charts as plain SVG, for figures in docs/ without a plotting dependency."""

from __future__ import annotations

from collections.abc import Sequence
from html import escape

WIDTH, PANEL_H, MARGIN_L, MARGIN_R, GAP = 640, 110, 60, 20, 34


def line_panels(
    xs: Sequence[float],
    panels: Sequence[tuple[str, Sequence[float]]],
    marks: Sequence[float] = (),
    x_label: str = "",
) -> str:
    """One panel per series over the same x, stacked; each y axis from 0 to 1.2 times its peak
    so a flat line looks flat; ``marks`` are dashed vertical lines (events)."""
    x_max = max(xs) if xs and max(xs) > 0 else 1.0
    plot_w = WIDTH - MARGIN_L - MARGIN_R
    height = len(panels) * (PANEL_H + GAP) + GAP
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" '
        f'font-family="sans-serif" font-size="11">',
        f'<rect width="{WIDTH}" height="{height}" fill="white"/>',
    ]

    def sx(x: float) -> float:
        return MARGIN_L + plot_w * x / x_max

    for i, (title, ys) in enumerate(panels):
        top = GAP + i * (PANEL_H + GAP)
        y_max = 1.2 * max(ys) if ys and max(ys) > 0 else 1.0

        def sy(y: float, top: float = top, y_max: float = y_max) -> float:
            return top + PANEL_H * (1 - y / y_max)

        out.append(f'<text x="{MARGIN_L}" y="{top - 6}">{escape(title)}</text>')
        out.append(
            f'<rect x="{MARGIN_L}" y="{top}" width="{plot_w}" height="{PANEL_H}" '
            'fill="none" stroke="#999"/>'
        )
        for tick in (0.0, y_max / 2, y_max):
            out.append(
                f'<text x="{MARGIN_L - 4}" y="{sy(tick) + 4:.1f}" text-anchor="end">'
                f"{tick:.0f}</text>"
            )
        for mark in marks:
            out.append(
                f'<line x1="{sx(mark):.1f}" y1="{top}" x2="{sx(mark):.1f}" '
                f'y2="{top + PANEL_H}" stroke="#c33" stroke-dasharray="3,3"/>'
            )
        points = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(xs, ys, strict=True))
        out.append(f'<polyline points="{points}" fill="none" stroke="#236" stroke-width="1.5"/>')
    bottom = height - GAP + 14
    for frac in (0.0, 0.5, 1.0):
        out.append(
            f'<text x="{sx(frac * x_max):.1f}" y="{bottom}" text-anchor="middle">'
            f"{frac * x_max:.0f}</text>"
        )
    out.append(
        f'<text x="{MARGIN_L + plot_w / 2}" y="{bottom + 14}" text-anchor="middle">'
        f"{escape(x_label)}</text>"
    )
    out.append("</svg>")
    return "\n".join(out) + "\n"
