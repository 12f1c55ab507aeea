"""What every PNG of the workspace shares: its title, its top views and its height axes.
The functions take Matplotlib axes (or a figure) and set labels, limits and titles only
(no backend is chosen here: the plotting modules use Agg).

- :func:`figure_title`: the input's name (not its path) and what the figure shows, then a
  line of :func:`walk_summary`: the number of steps and the final error against a truth,
  or without one the final loop gap and "no truth";
- :func:`top_view`: equal aspect while the east and north extents are within
  :data:`MAX_EQUAL_RATIO` of each other; beyond, a strip (80 m × 1.75 m) would be a
  line, so the short axis is stretched to make the view :data:`MAX_EQUAL_RATIO` to 1
  and its label says by how much;
- :func:`height_axis`: a height axis fitted to the heights: a level walk's centred on
  them and at least :data:`MIN_LEVEL_SPAN_M` high (its millimetres of noise drawn flat,
  its decimetres of drift seen), a walk that changes floors at least
  :data:`MIN_FLOORS_SPAN_M` high from just below the lowest;
- :func:`lay_out`: the title, wrapped to the figure's width, and the warnings, wrapped in
  a box below the axes (never cut by the figure's edge), then the axes fitted between.

They are tested in ``src/pdr_core/test/test_plot_layout.py``.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.font_manager import FontProperties

MAX_EQUAL_RATIO = 3.0       # longest to shortest extent of a top view drawn to scale
MIN_TOP_SPAN_M = 1.0        # the least extent of a top view's axis [m]
MIN_FLOORS_SPAN_M = 3.0     # the least span of the height axis of floors [m]: a floor
MIN_LEVEL_SPAN_M = 0.5      # the least span of a level walk's height axis [m]
HEIGHT_MARGIN = 0.05        # above and below the heights, as a fraction of their span
TITLE_FONT_PT = 12.0        # the figure's title
WARNING_FONT_PT = 9.0       # the warnings' box
TEXT_WIDTH_FRACTION = 0.94  # of the figure's width, the longest line of a title or warning
MAX_WARNINGS_SHOWN = 4      # in a figure; the rest are counted (the report has them)


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


def height_axis(ax, heights: np.ndarray, axis: str = "z", *,
                floors: bool = False) -> tuple[float, float]:
    """Limits of ``ax``'s height ``axis`` ("y" or "z") covering ``heights`` [m] (any
    shape, NaN ignored) with :data:`HEIGHT_MARGIN` of their span above and below; a level
    walk's centred on them and at least :data:`MIN_LEVEL_SPAN_M` high, a walk that
    changes ``floors`` (stairs steps, a lift) at least :data:`MIN_FLOORS_SPAN_M` from just
    below the lowest (the way up open); returns them."""
    finite = np.asarray(heights, float)
    finite = finite[np.isfinite(finite)]
    low, high = (float(finite.min()), float(finite.max())) if len(finite) else (0.0, 0.0)
    margin = HEIGHT_MARGIN * (high - low)
    if floors:
        low = low - max(margin, HEIGHT_MARGIN * MIN_FLOORS_SPAN_M)
        high = max(high + margin, low + MIN_FLOORS_SPAN_M)
    else:
        centre, half = (low + high) / 2, max(MIN_LEVEL_SPAN_M / 2, (high - low) / 2 + margin)
        low, high = centre - half, centre + half
    getattr(ax, f"set_{axis}lim")(low, high)
    return low, high


def lay_out(fig, title: str, warnings: list[str] = ()) -> None:
    """``title`` as ``fig``'s title and ``warnings`` (full sentences) in a box at its
    foot, the first :data:`MAX_WARNINGS_SHOWN` each wrapped to
    :data:`TEXT_WIDTH_FRACTION` of the figure's width, the rest counted; then the axes
    laid out in the space between (``tight_layout``). Call it once everything is drawn,
    in place of ``suptitle`` and ``tight_layout``."""
    fig.suptitle(_wrapped(fig, title, TITLE_FONT_PT), fontsize=TITLE_FONT_PT)
    bottom = 0.0
    if warnings:
        shown = [f"warning: {w}" for w in warnings[:MAX_WARNINGS_SHOWN]]
        if len(warnings) > MAX_WARNINGS_SHOWN:
            shown.append(f"and {len(warnings) - MAX_WARNINGS_SHOWN} more warnings in the "
                         "report")
        box = fig.text(0.5, 0.01, "\n".join(_wrapped(fig, w, WARNING_FONT_PT) for w in shown),
                       ha="center", va="bottom", fontsize=WARNING_FONT_PT, color="darkred",
                       bbox={"boxstyle": "round", "facecolor": "lightyellow",
                             "edgecolor": "tab:orange"})
        extent = box.get_window_extent(fig.canvas.get_renderer())
        bottom = (extent.y1 + WARNING_FONT_PT * fig.dpi / 72) / fig.bbox.height
    fig.tight_layout(rect=(0, bottom, 1, 1))


def _wrapped(fig, text: str, fontsize_pt: float) -> str:
    """``text`` with its lines broken between words where they would be wider than
    :data:`TEXT_WIDTH_FRACTION` of ``fig``'s width at ``fontsize_pt`` (measured by its
    renderer)."""
    renderer = fig.canvas.get_renderer()
    font = FontProperties(size=fontsize_pt)
    room = TEXT_WIDTH_FRACTION * fig.bbox.width
    lines = []
    for paragraph in text.split("\n"):
        line = ""
        for word in paragraph.split(" "):
            longer = f"{line} {word}" if line else word
            if line and renderer.get_text_width_height_descent(longer, font, False)[0] > room:
                lines.append(line)
                longer = word
            line = longer
        lines.append(line)
    return "\n".join(lines)
