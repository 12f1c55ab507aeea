"""PNG figures of the simulator: trajectory and signals (like Zampella et al. 2011, Figs. 1
and 4), the pocket walk's route, thigh pitch and yaw (like Muñoz Díaz 2016, Figs. 4.4 and
5.2) and Allan deviations. Matplotlib with the Agg backend (no display)."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from pdr_core.evaluation.plot_layout import (
    figure_title,
    height_axis,
    lay_out,
    top_view,
    walk_summary,
)
from pdr_core.vocabulary import STAIRS_ACTIVITIES, Activity, LandmarkType
from pdr_sim.trajectory import Trajectory


def step_count(model) -> int:
    """The steps of a simulated walk: the swings of a foot's
    :class:`pdr_sim.foot_trajectory.FootTrajectory`, the true steps of a thigh's
    :class:`pdr_sim.thigh_trajectory.ThighTrajectory`."""
    from pdr_sim.foot_pieces import SWING
    from pdr_sim.foot_trajectory import PIECE, REST

    steps = getattr(model, "true_steps", None)
    if steps is not None:
        return len(steps.length)
    kind = model.phases.kind
    return int(np.sum((kind != REST) & (kind != PIECE))
               + np.sum((kind == PIECE) & (model.phases.pieces.kind == SWING)))


def _route_title(title: str, shows: str, traj: Trajectory, steps: int | None) -> str:
    """The figure's title: the run's ``title``, what it shows, the steps and where the
    route ends (the simulation is the truth)."""
    gap = float(np.linalg.norm(traj.position[-1] - traj.position[0]))
    return figure_title(title, shows, walk_summary(steps, loop_gap_m=gap, of_truth=True))


SPEED_WINDOW_S = 5.0        # the speed panel's window [s]: a few strides, whose mean varies little
MAX_SPEED_WINDOWS = 300     # a longer walk gets longer windows


def windowed_speed(t: np.ndarray, speed: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                             np.ndarray, float]:
    """The mean and the peak of ``speed`` (N,) [m/s] at ``t`` (N,) [s] over consecutive
    windows of :data:`SPEED_WINDOW_S` (longer when the walk would have more than
    :data:`MAX_SPEED_WINDOWS`): a foot's speed at the sample rate swings from 0 to 5 m/s
    every stride, drawn whole it is a solid block. Returns the windows' centres [s], their
    mean and peak speeds [m/s] and the window [s]."""
    window = max(SPEED_WINDOW_S, (t[-1] - t[0]) / MAX_SPEED_WINDOWS)
    index = ((t - t[0]) // window).astype(int)
    counts = np.bincount(index)
    filled = counts > 0
    mean = np.bincount(index, speed)[filled] / counts[filled]
    peak = np.full(len(counts), -np.inf)
    np.maximum.at(peak, index, speed)
    centres = t[0] + (np.flatnonzero(filled) + 0.5) * window
    return centres, mean, peak[filled], window


def trajectory_png(traj: Trajectory, path: Path, title: str, *, steps: int | None = None,
                   foot: bool = True) -> None:
    """Top view (to scale unless it is a strip, pdr_core.evaluation.plot_layout), position and
    attitude against time, the speed's mean and peak per window (:func:`windowed_speed`).
    ``foot``: a foot's trajectory, whose position and attitude panels are Zampella et al.
    2011's Figs. 1a and 1b (a thigh's are not)."""
    paper = (" (Fig. 1a)", " (Fig. 1b)") if foot else ("", "")
    fig, ax = plt.subplots(2, 2, figsize=(12, 8))
    ax[0, 0].plot(traj.position[:, 0], traj.position[:, 1])
    ax[0, 0].set_title("top view")
    top_view(ax[0, 0])
    for i, name in enumerate("ENU"):
        ax[0, 1].plot(traj.t, traj.position[:, i], label=name)
    ax[0, 1].set(xlabel="t [s]", ylabel="position [m]", title="position" + paper[0])
    ax[0, 1].legend()
    for i, name in enumerate(("roll", "pitch", "yaw")):
        ax[1, 0].plot(traj.t, np.degrees(traj.euler[:, i]), label=name)
    ax[1, 0].set(xlabel="t [s]", ylabel="[deg]", title="attitude" + paper[1])
    ax[1, 0].legend()
    centres, mean, peak, window = windowed_speed(traj.t, np.linalg.norm(traj.velocity, axis=1))
    ax[1, 1].plot(centres, peak, color="tab:orange", lw=0.8, label="peak")
    ax[1, 1].plot(centres, mean, color="tab:blue", label="mean")
    ax[1, 1].set(xlabel="t [s]", ylabel="|v| [m/s]", ylim=(0, None),
                 title=f"speed, per {window:.3g} s window")
    ax[1, 1].legend()
    lay_out(fig, _route_title(title, f"the simulated {'foot' if foot else 'sensor'}'s "
                                     "trajectory", traj, steps))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def pocket_png(model, traj: Trajectory, path: Path, title: str) -> None:
    """A pocket walk: the route in 3D coloured by activity (stairs stand out) and from
    above with its landmarks; the thigh pitch with the true steps and the rests and the
    route heading with the thigh's yaw (the hip sway); close-ups of a few level and stairs
    steps (Muñoz Díaz 2016, Figs. 4.1-4.3). ``model`` is a
    :class:`pdr_sim.thigh_trajectory.ThighTrajectory`."""
    from pdr_sim.compiled_thigh import HEADING, SWAY

    steps, route = model.true_steps, model.route
    fig = plt.figure(figsize=(14, 15))
    ax3 = fig.add_subplot(3, 2, 1, projection="3d")
    points = route["start"] + route["step"]
    for activity in np.unique(steps.activity):
        sel = steps.activity == activity
        ax3.scatter(*points[sel].T, s=4, color=Activity(activity).colour,
                    label=Activity(activity).label)
    ax3.plot(*traj.position[::10].T, color="grey", lw=0.4)
    ax3.set(xlabel="east [m]", ylabel="north [m]", zlabel="up [m]", title="route (3D)")
    height_axis(ax3, np.r_[points[:, 2], traj.position[:, 2]],
                floors=bool(np.isin(steps.activity, STAIRS_ACTIVITIES).any()))
    ax3.legend(fontsize=8)
    top = fig.add_subplot(3, 2, 2)
    top.plot(traj.position[:, 0], traj.position[:, 1], color="grey", lw=0.6)
    for mark in model.landmarks:
        top.plot(*mark.position[:2], LandmarkType(mark.type).marker, ms=6)
    top.set_title("top view, landmarks (▲ corner, ■ stairs)")
    top_view(top)
    whole = fig.add_subplot(3, 1, 2)
    _pitch_panel(whole, model, traj.t)
    twin = whole.twinx()
    channels = model.spline(traj.t)
    twin.plot(traj.t, np.degrees(channels[:, HEADING]), "k--", lw=0.6, label="route heading")
    twin.plot(traj.t, np.degrees(channels[:, HEADING] + channels[:, SWAY]), "m", lw=0.4,
              label="thigh yaw (with hip sway)")
    twin.set_ylabel("yaw [deg]")
    twin.legend(loc="upper right", fontsize=8)
    whole.set_title("thigh pitch and yaw; shaded: standing and sitting, in their colours")
    for column, activities in ((1, (Activity.WALKING,)), (2, STAIRS_ACTIVITIES)):
        chosen = np.flatnonzero(np.isin(steps.activity, activities))
        ax = fig.add_subplot(3, 2, 4 + column)
        if len(chosen) >= 3:
            middle = chosen[len(chosen) // 3]
            start = steps.end_s[middle] - 4 * steps.duration[middle]
            window = traj.t[(traj.t >= start) & (traj.t <= steps.end_s[middle] + 2.0)]
            _pitch_panel(ax, model, window)
        ax.set_title("level steps" if column == 1 else "stairs steps")
    lay_out(fig, _route_title(title, "the simulated pocket walk", traj, len(steps.length)))
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _pitch_panel(ax, model, t: np.ndarray) -> None:
    """θ(t) with the true steps' heel strikes, rests shaded, stairs steps marked."""
    steps = model.true_steps
    inside = (steps.end_s >= t[0]) & (steps.end_s <= t[-1])
    ax.plot(t, np.degrees(model.pitch(t)), lw=0.8, label="thigh pitch θ")
    ax.plot(steps.end_s[inside], np.degrees(model.pitch(steps.end_s[inside])), "k.", ms=5,
            label="true step (heel strike)")
    for period in model.periods:
        if period.activity != Activity.WALKING and period.end_s > t[0] \
                and period.start_s < t[-1]:
            ax.axvspan(max(period.start_s, t[0]), min(period.end_s, t[-1]), alpha=0.15,
                       color=Activity(period.activity).colour)
    for activity in STAIRS_ACTIVITIES:
        ends = steps.end_s[inside & (steps.activity == activity)]
        if len(ends):
            ax.plot(ends, np.full(len(ends), -20.0), "|", color=activity.colour, ms=8,
                    label=activity.label)
    ax.set(xlabel="t [s]", ylabel="pitch [deg]")
    ax.legend(loc="upper left", fontsize=8)


def signals_png(t: np.ndarray, gyro: np.ndarray, accel: np.ndarray, mag: np.ndarray,
                path: Path, title: str, window_s: float = 4.0) -> None:
    """Accelerometer, gyroscope and magnetometer over the first strides (Fig. 4)."""
    first_motion = np.flatnonzero(np.abs(gyro).max(axis=1) > 0.5)
    start = t[first_motion[0]] - 0.5 if len(first_motion) else t[0]
    sel = (t >= start) & (t <= start + window_s)
    fig, ax = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    for i, name in enumerate("xyz"):
        ax[0].plot(t[sel], accel[sel, i], label=name)
        ax[1].plot(t[sel], gyro[sel, i], label=name)
        ax[2].plot(t[sel], mag[sel, i] * 1e6, label=name)
    ax[0].set(ylabel="specific force [m/s²]", title="accelerometer (Fig. 4a)")
    ax[1].set(ylabel="rate [rad/s]", title="gyroscope (Fig. 4b)")
    ax[2].set(ylabel="field [µT]", xlabel="t [s]", title="magnetometer")
    for a in ax:
        a.legend(loc="upper right")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def step_fit_png(times: list[np.ndarray], xyz: list[np.ndarray], along, up, path: Path,
                 title: str) -> None:
    """Aligned recorded steps (dotted) and the fitted patterns (like Zampella et al. 2011,
    Fig. 2a)."""
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    for t, p in zip(times, xyz, strict=True):
        ax[0].plot(t, p[:, 0], ":", color="grey", lw=0.8)
        ax[1].plot(t, p[:, 2], ":", color="grey", lw=0.8)
    grid = np.linspace(0, max(t[-1] for t in times), 300)
    ax[0].plot(grid, along(grid).f, "r", lw=2, label="Eq. (4) fit")
    ax[1].plot(grid, up(grid).f, "r", lw=2, label="Eq. (3) fit")
    ax[0].set(xlabel="t since swing start [s]", ylabel="along-track [m]", title="P_x")
    ax[1].set(xlabel="t since swing start [s]", ylabel="height [m]", title="P_z")
    for a in ax:
        a.legend()
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def allan_png(curves: dict[str, tuple[np.ndarray, np.ndarray]], path: Path, ylabel: str,
              title: str) -> None:
    """Log-log Allan deviation curves, one per axis."""
    fig, ax = plt.subplots(figsize=(8, 6))
    for name, (taus, adev) in curves.items():
        ax.loglog(taus, adev, label=name)
    ax.set(xlabel="τ [s]", ylabel=ylabel, title=title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
