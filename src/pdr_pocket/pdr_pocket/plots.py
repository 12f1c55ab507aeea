"""PNG figures of pdr_pocket (Matplotlib, Agg backend): the attitude errors, the heading
error and the gyro biases with their ±σ, as Muñoz Díaz 2016, Figs. 3.10 and 3.14-3.17;
the magnetometer's raw cloud and the fitted sphere, as Fig. 3.20."""
from __future__ import annotations

from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import LineCollection

from pdr_core.evaluation.plot_layout import (
    figure_title,
    height_axis,
    lay_out,
    top_view,
    walk_summary,
)
from pdr_core.vocabulary import STAIRS_ACTIVITIES, Activity
from pdr_pocket.orientation import FIELD_JUDGEMENTS, AttitudeEstimate

AXES = ("x", "y", "z")
COLOURS = ("tab:blue", "tab:red", "tab:green")


def attitude_png(estimate: AttitudeEstimate, errors_deg: np.ndarray | None,
                 heading_deg: np.ndarray | None, true_bias: np.ndarray | None, path: Path,
                 source: str | Path) -> None:
    """Three panels against minutes: roll and pitch errors [°] with ±σ (±σ alone without
    a truth); the heading error [°] (pdr_core.evaluation.attitude_metrics) with ±σ, the samples
    whose field reading was refused as disturbed shaded; the three gyro biases [°/s] with ±σ and
    the true values. The title: ``source``'s name and the final roll, pitch, yaw and
    heading errors (or "no truth")."""
    t_s = estimate.t
    step = max(1, len(t_s) // 20000)
    t = t_s[::step] / 60.0
    sigma = np.degrees(estimate.euler_sigma)[::step]
    fig, ax = plt.subplots(3, 1, figsize=(12, 11), sharex=True)
    for i, name in enumerate(("roll", "pitch")):
        if errors_deg is not None:
            ax[0].plot(t, errors_deg[::step, i], color=COLOURS[i], lw=0.8, label=f"{name} error")
        ax[0].plot(t, sigma[:, i], ":", color=COLOURS[i], lw=0.8)
        ax[0].plot(t, -sigma[:, i], ":", color=COLOURS[i], lw=0.8)
    ax[0].set(ylabel="[deg]", title="tilt: roll and pitch error (dotted: ±σ)"
              if errors_deg is not None else "roll and pitch ±σ (no truth in the bag)")
    if errors_deg is not None:
        ax[0].legend(loc="upper left")
    heading_sigma = np.degrees(estimate.heading_sigma)[::step]
    if heading_deg is not None:
        ax[1].plot(t, heading_deg[::step], color="tab:green", lw=0.8, label="heading error")
    ax[1].plot(t, heading_sigma, ":", color="tab:green", lw=0.8)
    ax[1].plot(t, -heading_sigma, ":", color="tab:green", lw=0.8)
    disturbed = (estimate.field_judgement() ==
                 FIELD_JUDGEMENTS.index("field_disturbed"))[::step]
    if disturbed.any():
        ax[1].fill_between(t, 0, 1, where=disturbed, color="tab:red", alpha=0.15, lw=0,
                           transform=ax[1].get_xaxis_transform(),
                           label="field refused as disturbed")
    ax[1].set(ylabel="[deg]", title="heading error of the most level axis, relative to the "
              "first seconds (dotted: ±σ)" if heading_deg is not None else "heading ±σ")
    if heading_deg is not None or disturbed.any():
        ax[1].legend(loc="upper left")
    bias, bias_sigma = np.degrees(estimate.bias)[::step], np.degrees(estimate.bias_sigma)[::step]
    for i, name in enumerate(AXES):
        ax[2].plot(t, bias[:, i], color=COLOURS[i], label=f"b_{name}")
        ax[2].plot(t, bias[:, i] + bias_sigma[:, i], ":", color=COLOURS[i], lw=0.8)
        ax[2].plot(t, bias[:, i] - bias_sigma[:, i], ":", color=COLOURS[i], lw=0.8)
        if true_bias is not None:
            ax[2].axhline(true_bias[i], color=COLOURS[i], ls="--", lw=0.8)
    ax[2].set(xlabel="t [min]", ylabel="[deg/s]", title="gyroscope biases (dotted: ±σ, "
              "dashed: truth)")
    ax[2].legend(loc="upper left")
    final = "no truth" if errors_deg is None else "final error " + ", ".join(
        f"{name} {errors_deg[-1, i]:+.2f}°" for i, name in enumerate(("roll", "pitch", "yaw")))
    if heading_deg is not None:
        final += f", heading {heading_deg[-1]:+.2f}°"
    lay_out(fig, figure_title(source, "the orientation filter's attitude and gyro biases",
                              f"{t_s[-1] - t_s[0]:.0f} s, {final}"))
    fig.savefig(path, dpi=90)
    plt.close(fig)


def magnetometer_png(raw_ut: np.ndarray, calibrated_ut: np.ndarray, path: Path,
                     source: str | Path) -> None:
    """The raw readings and the calibrated ones, which the fit brings to a sphere; the
    title: ``source``'s name and the number of readings."""
    step = max(1, len(raw_ut) // 5000)
    fig = plt.figure(figsize=(12, 6))
    for k, (points, name) in enumerate(((raw_ut, "raw"), (calibrated_ut, "calibrated"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        ax.scatter(*points[::step].T, s=2, color="tab:blue" if k == 0 else "tab:red")
        if k == 1:
            radius = float(np.median(np.linalg.norm(calibrated_ut, axis=1)))
            u, v = np.mgrid[0:2 * np.pi:30j, 0:np.pi:15j]
            ax.plot_wireframe(radius * np.cos(u) * np.sin(v), radius * np.sin(u) * np.sin(v),
                              radius * np.cos(v), color="grey", lw=0.3)
        ax.set(xlabel="x [µT]", ylabel="y [µT]", zlabel="z [µT]", title=name)
    lay_out(fig, figure_title(source, "magnetometer calibration, the raw cloud and the "
                                      "fitted sphere", f"{len(raw_ut)} readings"))
    fig.savefig(path, dpi=90)
    plt.close(fig)


ELLIPSES_PER_WALK = 10  # about as many 1σ ellipses in a top view, the last step's among them
ELLIPSE_INTERVALS = (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000)   # steps between ellipses
ZOOM_ABOVE_S = 60.0     # a longer pitch trace gets a zoom on a few gait cycles
ZOOM_CYCLES = 4         # gait cycles (the sensor leg's steps) in the zoom


def navigation_png(positions: np.ndarray, covariances: np.ndarray, activity: np.ndarray,
                   truth: np.ndarray | None, t_s: np.ndarray, pitch_deg: np.ndarray,
                   step_t: np.ndarray, true_step_t: np.ndarray | None, path: Path,
                   source: str | Path, landmarks: np.ndarray | None = None,
                   associations: list[tuple[np.ndarray, np.ndarray]] = (), *,
                   final_error_m: float | None = None, loop_gap_m: float | None = None,
                   warnings: list[str] = ()) -> None:
    """The 3D path (``positions`` (N + 1, 3) [m] from the start, one point per step,
    coloured by activity (pdr_core.vocabulary.Activity.colour); the height axis fitted to
    them, a floor high at least with stairs steps, pdr_core.evaluation.plot_layout), the top view
    with the 1σ position ellipses of :func:`ellipse_steps` (to scale unless it is a strip,
    then stretched and labelled so; the limits are the path's and the truth's, so
    ellipses wider than the walk are cut at the frame rather than shrinking the path to a
    line), and the thigh pitch [deg] against ``t_s`` [s] with the detected steps
    (``step_t``) and the true ones, and beyond :data:`ZOOM_ABOVE_S` a zoom on
    :data:`ZOOM_CYCLES` gait cycles in the middle. Decimated to at most 20,000 points per
    line, so an hour plots in seconds. With the drift estimator's ``landmarks`` (N, 3)
    and ``associations`` (pairs of positions), the top view marks them, as Muñoz Díaz
    2016, Figs. 6.8-6.9. The title: ``source``'s name, the steps and ``final_error_m``
    (against a truth) or ``loop_gap_m`` (the report's); the report's ``warnings`` in full
    in a box below the axes (pdr_core.evaluation.plot_layout.lay_out)."""
    fig = plt.figure(figsize=(15, 10))
    grid = fig.add_gridspec(2, 4)
    ax3 = fig.add_subplot(grid[0, :2], projection="3d")
    top = fig.add_subplot(grid[0, 2:])
    zoom = len(step_t) > ZOOM_CYCLES and t_s[-1] - t_s[0] > ZOOM_ABOVE_S
    pitch_ax = fig.add_subplot(grid[1, :3] if zoom else grid[1, :])
    for a in Activity:
        mask = activity == a
        if mask.any():
            ax3.scatter(*positions[mask].T, s=4, color=a.colour, label=a.label)
    if truth is not None:
        ax3.plot(*truth.T, color="k", lw=0.6, label="truth")
        top.plot(truth[:, 0], truth[:, 1], color="k", lw=0.6, label="truth")
    ax3.set(xlabel="east [m]", ylabel="north [m]", zlabel="up [m]", title="3D path")
    height_axis(ax3, positions[:, 2] if truth is None else np.r_[positions[:, 2], truth[:, 2]],
                floors=bool(np.isin(activity, STAIRS_ACTIVITIES).any()))
    ax3.legend(loc="upper left", fontsize=8)
    top.plot(positions[:, 0], positions[:, 1], color="tab:blue", lw=1, label="estimate")
    marked = ellipse_steps(len(positions) - 1)
    top.add_collection(LineCollection(_ellipses(positions[marked], covariances[marked]),
                                      colors="tab:red", linewidths=0.6), autolim=False)
    if landmarks is not None and len(landmarks):
        top.plot(landmarks[:, 0], landmarks[:, 1], "o", mfc="none", color="tab:green", ms=8,
                 label="landmarks")
    for k, (first, revisit) in enumerate(associations):
        top.plot([first[0], revisit[0]], [first[1], revisit[1]], "-", color="tab:green", lw=2,
                 label="associations" if k == 0 else None)
    top.set_title(f"top view, {_ellipses_said(marked)}")
    top_view(top)
    top.legend(loc="best", fontsize=8)
    step = max(1, len(t_s) // 20000)
    pitch_ax.plot(t_s[::step], pitch_deg[::step], color="tab:blue", lw=0.6, label="thigh pitch")
    _steps_on_pitch(pitch_ax, t_s, pitch_deg, step_t, true_step_t)
    pitch_ax.set(xlabel="time [s]", ylabel="pitch [deg]", title="thigh pitch and steps")
    pitch_ax.legend(loc="upper right", fontsize=8)
    if zoom:
        _pitch_zoom(fig.add_subplot(grid[1, 3]), pitch_ax, t_s, pitch_deg, step_t, true_step_t)
    lay_out(fig, figure_title(source, "the pocket navigator" + (
        ", landmarks and associations" if landmarks is not None else ""),
        walk_summary(len(positions) - 1, final_error_m, loop_gap_m)), list(warnings))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def ellipse_steps(steps: int) -> np.ndarray:
    """The steps (indices into the N + 1 positions of ``steps`` steps) whose 1σ ellipse the
    top view draws: every n-th, n the first of :data:`ELLIPSE_INTERVALS` that gives at
    most :data:`ELLIPSES_PER_WALK`, and the last step (13 steps: 2, 4, ..., 12, 13; none
    without a step: the start's ellipse is a point)."""
    if steps <= 0:
        return np.zeros(0, int)
    every = next((n for n in ELLIPSE_INTERVALS if steps <= n * ELLIPSES_PER_WALK),
                 ELLIPSE_INTERVALS[-1])
    return np.unique(np.r_[np.arange(every, steps + 1, every), steps])


def _ellipses_said(marked: np.ndarray) -> str:
    """What the top view's title says of the ellipses at steps ``marked``
    (:func:`ellipse_steps`)."""
    if len(marked) == 0:
        return "no steps, no 1σ ellipse"
    every = int(marked[0])
    if every == 1:
        return "1σ ellipse at every step"
    last = "" if marked[-1] % every == 0 else f" and at the last ({marked[-1]})"
    return f"1σ ellipses every {every} steps{last}"


def _ellipses(positions: np.ndarray, covariances: np.ndarray) -> list[np.ndarray]:
    """The 1σ horizontal ellipse (60, 2) [m] about each of ``positions`` (K, 3) [m], from
    its covariance's upper 2×2 (``covariances`` (K, 3, 3) [m²])."""
    angles = np.linspace(0, 2 * np.pi, 60)
    circle = np.stack([np.cos(angles), np.sin(angles)])
    rings = []
    for position, covariance in zip(positions, covariances, strict=True):
        values, vectors = np.linalg.eigh(covariance[:2, :2])
        ring = vectors @ (np.sqrt(np.maximum(values, 0))[:, None] * circle)
        rings.append((position[:2, None] + ring).T)
    return rings


def _steps_on_pitch(ax, t_s: np.ndarray, pitch_deg: np.ndarray, step_t: np.ndarray,
                    true_step_t: np.ndarray | None) -> None:
    """The detected steps on the pitch (▼) and the true ones below it (|)."""
    ax.plot(step_t, np.interp(step_t, t_s, pitch_deg), "v", color="tab:red", ms=4,
            label="detected steps")
    if true_step_t is not None:
        ax.plot(true_step_t, np.full(len(true_step_t), np.nanmin(pitch_deg)), "|",
                color="k", ms=8, label="true steps (cycle ends)")


def _pitch_zoom(ax, whole, t_s: np.ndarray, pitch_deg: np.ndarray, step_t: np.ndarray,
                true_step_t: np.ndarray | None) -> None:
    """:data:`ZOOM_CYCLES` gait cycles around the middle detected step at full rate, the
    steps marked, and a box on the whole trace (``whole``) where they are."""
    k = min(max(len(step_t) // 2 - ZOOM_CYCLES // 2, 0), len(step_t) - 1 - ZOOM_CYCLES)
    first, last = step_t[k], step_t[k + ZOOM_CYCLES]
    pad = 0.5 * (last - first) / ZOOM_CYCLES
    low, high = first - pad, last + pad
    inside = (t_s >= low) & (t_s <= high)
    ax.plot(t_s[inside], pitch_deg[inside], color="tab:blue", lw=0.8)
    marks = step_t[(step_t >= low) & (step_t <= high)]
    truth = None if true_step_t is None else \
        true_step_t[(true_step_t >= low) & (true_step_t <= high)]
    _steps_on_pitch(ax, t_s, pitch_deg, marks, truth)
    ax.set(xlim=(low, high), xlabel="time [s]",
           title=f"zoom: {ZOOM_CYCLES} gait cycles, {low:.0f}-{high:.0f} s")
    bottom, top = ax.get_ylim()
    whole.indicate_inset([low, bottom, high - low, top - bottom], inset_ax=ax,
                         edgecolor="k")
