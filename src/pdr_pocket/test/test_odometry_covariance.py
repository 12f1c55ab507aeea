"""The covariance of ``pdr/pocket/odometry`` (issue 55, point 1): a vertical variance that
is never 0, a twist from each step's velocity with its covariance, a pose and twist
covariance positive definite at every step, and the terms only the published covariance
P̃ holds (the stride line's offset, the heading's fall, a flight's first step), with the
filter's own P, which the corrections and the drift loop use, left as it was
(pdr_pocket.position, step_assembly, messages)."""
from __future__ import annotations

from functools import cache

import numpy as np

from pdr_core import topics
from pdr_core.io.odometry import UNKNOWN_VARIANCE
from pdr_core.vocabulary import STAIRS_ACTIVITIES
from pdr_pocket.config import PocketConfig, PositionConfig
from pdr_pocket.messages import step_batches
from pdr_pocket.navigator import PocketNavigator
from pdr_pocket.position import N_POSITION_STATE, PSI, B, PositionFilter
from pdr_pocket.step_assembly import step_velocity
from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate
from wstest import samples_of


@cache
def up_dw():
    """The simulated UP/DW walk (level, up a flight, level, down), xsens_mtw errors, seed
    0, the default navigator, and its odometry and pose."""
    _, data = load_pocket_scenario("up_dw")
    sim = simulate(SimulationConfig(pocket_scenario_from_dict(data, "up_dw"), data,
                                    "xsens_mtw", {}, 100.0, 0, placement="pocket"))
    out = PocketNavigator(PocketConfig()).process(samples_of(sim))
    batches = step_batches(out, sim.imu.stamp_ns)
    return sim, out, batches[topics.POCKET_ODOMETRY], batches[topics.POCKET_POSE]


def test_a_level_step_climbs_nothing_give_or_take_its_grade():
    config = PositionConfig()
    f = PositionFilter(config)
    for _ in range(4):
        f.step(1.2, 0.0, 0.3, 1e-4, 0.03**2, (config.level_grade_sigma * 1.2) ** 2, 1.1)
    assert f.position[2] == 0.0
    assert np.isclose(f.covariance[2, 2], 4 * (config.level_grade_sigma * 1.2) ** 2)


def test_the_vertical_variance_is_never_zero_and_holds_the_climbs_held_back():
    """Every step's z variance is at least one level step's, and the height error within
    4σ at every step, the first stairs steps too, whose climb the flight check holds back
    (it publishes it a step late): the pose's (the filter's) against the climbs of the
    steps as the classifier labels them; the odometry's against the true climbs at every
    step the classifier labels as the truth does, the steps after a flight's first step
    called level (its level prior, pdr_pocket.activity) too (what the variance cannot
    know is that step itself, before the flight shows)."""
    sim, out, odometry, pose = up_dw()
    truth = sim.model.true_steps
    assert len(out.steps) == len(truth.length)
    floor = (PositionConfig().level_grade_sigma * min(s.length for s in out.steps)) ** 2
    variances = [m["pose.covariance"].reshape(-1, 6, 6)[:, 2, 2] for m in (pose, odometry)]
    assert min(v.min() for v in variances) >= floor > 0
    stairs = np.isin([s.activity for s in out.steps], list(STAIRS_ACTIVITIES))
    assert np.mean(stairs == np.isin(truth.activity, list(STAIRS_ACTIVITIES))) > 0.9
    labelled = np.cumsum(np.where(stairs, truth.vertical_displacement, 0.0))
    ratio = np.abs(pose["pose.pose.position"][:, 2] - labelled) / np.sqrt(variances[0])
    assert ratio.max() <= 4, ratio.max()
    error = odometry["pose.pose.position"][:, 2] - np.cumsum(truth.vertical_displacement)
    same = np.array([s.activity for s in out.steps]) == truth.activity
    assert same.mean() > 0.9
    ratio = np.abs(error[same]) / np.sqrt(variances[1][same])
    assert ratio.max() <= 4, ratio.max()


def test_a_steps_velocity_is_its_stride_over_its_duration_with_their_variances():
    length, climb, heading, duration = 1.3, 0.17, 0.6, 1.2
    variances = (0.03**2, 0.02**2, np.radians(1.0) ** 2)
    velocity, covariance = step_velocity(length, climb, heading, duration, variances)
    assert np.allclose(velocity, [length * np.cos(heading) / duration,
                                  length * np.sin(heading) / duration, climb / duration])
    along = np.array([np.cos(heading), np.sin(heading), 0.0])
    across = np.array([-np.sin(heading), np.cos(heading), 0.0])
    assert np.isclose(along @ covariance @ along, variances[0] / duration**2)
    assert np.isclose(across @ covariance @ across, length**2 * variances[2] / duration**2)
    assert np.isclose(covariance[2, 2], variances[1] / duration**2)
    assert np.isclose(along @ covariance @ across, 0.0)


def test_the_odometry_twist_is_the_steps_velocity_in_the_body_frame():
    _, out, odometry, _ = up_dw()
    twist = odometry["twist.twist.linear"]
    speed = np.array([np.hypot(s.length, s.velocity[2] * s.duration) / s.duration
                      for s in out.steps])
    assert np.allclose(np.linalg.norm(twist, axis=1), speed)
    cov = odometry["twist.covariance"].reshape(-1, 6, 6)
    for step, linear in zip(out.steps, cov[:, :3, :3], strict=True):
        # turned into the body frame: the same eigenvalues as in the map frame
        assert np.allclose(np.linalg.eigvalsh(linear),
                           np.linalg.eigvalsh(step.velocity_covariance), rtol=1e-9, atol=0)
    assert np.all(np.diagonal(cov[:, 3:, 3:], axis1=1, axis2=2) == UNKNOWN_VARIANCE)


def test_the_odometry_pose_and_twist_covariances_are_positive_definite():
    _, _, odometry, _ = up_dw()
    pose = odometry["pose.covariance"].reshape(-1, 6, 6)
    twist = odometry["twist.covariance"].reshape(-1, 6, 6)
    for cov in (pose, twist[:, :3, :3]):
        assert np.allclose(cov, np.transpose(cov, (0, 2, 1)))
        assert np.linalg.eigvalsh(cov)[:, 0].min() > 0


def test_z_from_the_barometer_has_the_height_filters_variance():
    f = PositionFilter(PositionConfig())
    f.step(1.2, 0.3, 0.0, 1e-4, 0.03**2, 0.02**2, 1.1)
    f.hold_height(0.25**2)
    assert f.covariance[2, 2] == f.published_covariance[2, 2] == 0.25**2
    assert np.all(f.p[2, [0, 1, 3, 4]] == 0)
    assert np.all(f.published[2, [0, 1, 3, 4, 5]] == 0)
    assert np.linalg.eigvalsh(f.p).min() >= -1e-15


def test_the_heading_variance_follows_the_orientation_filters_down_in_the_published_one():
    """A fall of the yaw variance to a quarter: in P̃, ψ's variance and its covariances
    quarter, the position's own variances stay (nothing corrected it); the filter's P
    keeps ψ's variance (its gains and gates as before)."""
    f = PositionFilter(PositionConfig())
    for k in range(5):
        f.step(1.2, 0.0, 0.1 * k, 4e-3, 0.03**2, 1e-4, 1.1)
    before, filter_before = f.published.copy(), f.p.copy()
    f.step(0.0, 0.0, 0.4, 1e-3, 0.0, 0.0, 0.0)      # no time, no stride: the fall alone
    assert np.isclose(f.published[PSI, PSI], before[PSI, PSI] / 4)
    assert np.allclose(f.published[PSI, :3], before[PSI, :3] / 4)
    assert np.allclose(f.published[:3, :3], before[:3, :3])
    assert np.linalg.eigvalsh(f.published).min() >= -1e-15
    assert np.allclose(f.p, filter_before)


def test_the_stride_lines_offset_adds_up_along_the_walk_in_the_published_covariance():
    """N strides of the level line straight ahead, the heading known: P̃ along the walk
    holds (N·σ_b)² beyond the strides' own scatter N·σ_s², which P holds alone; a stairs
    step (off the line) adds no more of b."""
    sigma_b, n = 0.05, 10
    f = PositionFilter(PositionConfig(), stride_offset_sigma_m=sigma_b)
    for _ in range(n):
        f.step(1.2, 0.0, 0.0, 0.0, 0.03**2, 1e-4, 1.1, on_line=True)
    assert np.isclose(f.covariance[0, 0], n * 0.03**2)
    assert np.isclose(f.published_covariance[0, 0], n * 0.03**2 + (n * sigma_b) ** 2)
    assert np.isclose(f.published[0, B], n * sigma_b**2)
    f.step(0.6, 0.17, 0.0, 0.0, 0.03**2, 1e-4, 1.1, on_line=False)
    assert np.isclose(f.published_covariance[0, 0], (n + 1) * 0.03**2 + (n * sigma_b) ** 2)


def test_the_published_covariance_follows_the_filters_updates_with_its_gain():
    """Without the published terms (no offset, no fall of the yaw variance, no missed
    climb) P̃ is P, through steps, a position fix and a heading fix; with them the
    filter's state and P are the same numbers (P̃ follows the gain P gave), and P̃ stays
    symmetric positive semi-definite and at least P."""
    plain = PositionFilter(PositionConfig())
    honest = PositionFilter(PositionConfig(), stride_offset_sigma_m=0.05)
    for f, fall, on_line, missed in ((plain, 1.0, False, 0.0), (honest, 0.5, True, 0.02)):
        for k in range(8):
            f.step(1.2, 0.0, 0.2 * k, 4e-3 * (fall if k >= 5 else 1.0), 0.03**2, 1e-4, 1.1,
                   on_line, missed)
        f.correct_position(f.position + [0.3, -0.2, 0.0], np.diag([0.1, 0.1, 0.01]))
        f.correct_heading(f.x[PSI] + 0.02, 1e-3, 1.5e-3)
    n = N_POSITION_STATE
    assert np.allclose(plain.published[:n, :n], plain.p, rtol=1e-12, atol=1e-15)
    assert np.array_equal(honest.x, plain.x)
    assert np.allclose(honest.p, plain.p, rtol=1e-12, atol=1e-15)
    assert np.linalg.eigvalsh(honest.published).min() >= -1e-12
    assert np.linalg.eigvalsh(honest.published_covariance - honest.covariance).min() >= -1e-12
