"""What every PNG of the workspace shares: its title, its top views and its height axes.
The functions take Matplotlib axes and set labels and limits only (no backend is chosen
here: the plotting modules use Agg).

- :func:`figure_title`: the input's name (not its path) and what the figure shows, then a
  line of :func:`walk_summary`: the number of steps and the final error against a truth,
  or without one the final loop gap and "no truth";
- :func:`top_view`: equal aspect while the east and north extents are within
  :data:`MAX_EQUAL_RATIO` of each other; beyond, a strip (80 m × 1.75 m) would be a
  line, so the short axis is stretched to make the view :data:`MAX_EQUAL_RATIO` to 1
  and its label says by how much;
- :func:`height_axis`: a height axis spanning at least :data:`MIN_HEIGHT_SPAN_M` (a
  floor), so a level walk's millimetres of noise are drawn flat, not as relief.

They are tested in ``src/pdr_core/test/test_plot_layout.py``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

MAX_EQUAL_RATIO = 3.0       # longest to shortest extent of a top view drawn to scale
MIN_TOP_SPAN_M = 1.0        # the least extent of a top view's axis [m]
MIN_HEIGHT_SPAN_M = 3.0     # the least span of a height axis [m]: about a floor


def source_name(source: str | Path) -> str:
    """The name of a bag directory or file (``/tmp/x/up_dw/`` → ``up_dw``)."""
    name = Path(str(source).rstrip("/")).name
    return name or str(source)


def walk_summary(steps: int | None = None, final_error_m: float | None = None,
                 loop_gap_m: float | None = None, *, of_truth: bool = False) -> str:
    """"N steps, final error E m", or without a truth "N steps, no truth, final loop gap
    G m" (or "no truth" alone); ``of_truth``: the figure shows the truth itself (the
    simulator), whose loop gap is said as where it ends."""
    parts = [] if steps is None else [f"{steps} steps"]
    if final_error_m is not None:
        parts.append(f"final error {final_error_m:.2f} m")
    elif of_truth:
        parts.append("the truth" if loop_gap_m is None
                     else f"the truth, ends {loop_gap_m:.2f} m from its start")
    else:
        parts.append("no truth" if loop_gap_m is None
                     else f"no truth, final loop gap {loop_gap_m:.2f} m")
    return ", ".join(parts)


def figure_title(source: str | Path, shows: str, summary: str = "") -> str:
    """``"<name>: <what it shows>"``, and the summary on a second line."""
    head = f"{source_name(source)}: {shows}"
    return f"{head}\n{summary}" if summary else head


def _nice(value: float) -> float:
    """``value`` to two significant digits (a factor a label can state)."""
    return float(f"{value:.2g}")


def top_view(ax, xlabel: str = "east [m]", ylabel: str = "north [m]") -> float:
    """Aspect and labels of a top view, once everything is drawn in ``ax``; returns the
    stretch of the short axis (1: equal aspect). Each axis spans at least
    :data:`MIN_TOP_SPAN_M`."""
    box = ax.dataLim
    centre = (box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2
    width, height = max(box.width, MIN_TOP_SPAN_M), max(box.height, MIN_TOP_SPAN_M)
    if box.width < MIN_TOP_SPAN_M:
        ax.set_xlim(centre[0] - 0.55 * width, centre[0] + 0.55 * width)
    if box.height < MIN_TOP_SPAN_M:
        ax.set_ylim(centre[1] - 0.55 * height, centre[1] + 0.55 * height)
    ratio = max(width, height) / min(width, height)
    if ratio <= MAX_EQUAL_RATIO:
        ax.set(aspect="equal", xlabel=xlabel, ylabel=ylabel)
        return 1.0
    stretch = _nice(ratio / MAX_EQUAL_RATIO)
    note = f", stretched ×{stretch:g} (not to scale)"
    if height < width:
        ax.set(aspect=stretch, xlabel=xlabel, ylabel=ylabel + note)
    else:
        ax.set(aspect=1 / stretch, xlabel=xlabel + note, ylabel=ylabel)
    return stretch


def height_axis(ax, heights: np.ndarray, axis: str = "z",
                min_span_m: float = MIN_HEIGHT_SPAN_M) -> tuple[float, float]:
    """Limits of ``ax``'s height ``axis`` ("y" or "z") covering ``heights`` [m] (any
    shape, NaN ignored) with a 5 % margin, and at least ``min_span_m`` from just below
    the lowest (a level walk is drawn near the floor of the axis, the way up open);
    returns them."""
    finite = np.asarray(heights, float)
    finite = finite[np.isfinite(finite)]
    low, high = (float(finite.min()), float(finite.max())) if len(finite) else (0.0, 0.0)
    if high - low < 0.9 * min_span_m:
        low = low - 0.05 * min_span_m
        high = low + min_span_m
    else:
        margin = 0.05 * (high - low)
        low, high = low - margin, high + margin
    getattr(ax, f"set_{axis}lim")(low, high)
    return low, high
