"""Physical activities of the steps from the thigh pitch (Muñoz Díaz 2016, Section 4.1.3),
and at rest standing or sitting.

Two classifiers of a step's activity, chosen by ``activity.model`` (:data:`MODELS`):

- ``thesis`` (:class:`ThesisActivity`), the algorithm of Section 4.1.3 as written: θ_min,
  θ_max and Δθ = θ_max − θ_min (Eq. (4.1)) against the running means of the last level
  steps, learned as the person walks (the walk starts on level ground).
  - upstairs when Δθ ≫ mean Δθ_H and θ_max ≫ mean θ_Hmax: Δθ above the mean by
    ``up_amplitude_margin_deg`` and θ_max above it by ``up_max_margin_deg``. Beyond the
    thesis, θ_min must also not fall below its mean by more than ``up_min_tolerance_deg``:
    a faster level stride swings the leg further both ways, a step up only forwards
    (|θ_Umin| slightly smaller than |θ_Hmin|, Section 4.1.2);
  - downstairs when Δθ ≪ mean Δθ_H and θ_min ≫ mean θ_Hmin: Δθ below
    ``down_amplitude_ratio`` times the mean and θ_min above it by ``down_min_margin_deg``,
    and θ_min below mean θ_Hmax (a swing wholly above it is the phone turned about the
    flexion axis in the pocket);
  - else walking, and the step joins the running means. The first
    ``level_history_steps`` steps are level by the thesis' assumption.

  It reproduces the thesis' tables in simulation; on real walks it labels level steps as
  stairs (docs/pocket.md): a reference made of the first steps is wrong when the walk
  starts on a staircase, and every step is judged alone.

- ``level_prior`` (:class:`LevelPriorActivity`, the default), beyond the thesis: the same
  signatures (Section 4.1.2: on stairs the thigh stays flexed, θ_Umax almost doubles and
  θ_Dmin turns positive), weighed as evidence in a hidden Markov model whose states are
  level walking, upstairs and downstairs, filtered forward one step at a time (Rabiner,
  "A tutorial on hidden Markov models and selected applications in speech recognition",
  1989, the forward algorithm). What makes it hold on real walks:

  - the level floor is the strong prior: a level step is followed by stairs with
    probability ``enter_stairs_probability`` (1 %), so a staircase must show itself by one
    unmistakable step or several consistent ones, while a level step ends it at once;
  - each step's evidence is measured against the person's level gait: the running means
    of the last ``level_history_steps`` level steps, seeded with a population level gait
    (``level_*_deg``: θ_max ≈ 24°, θ_min ≈ −8°, Δθ ≈ 32°, which the thesis' volunteer
    (H1: θ_Hmax 26°, Δθ_H 32°) and the walks of docs/pocket.md bracket) weighing
    ``prior_weight_steps`` steps, so a walk that starts on a staircase is judged against
    a level gait, not against its own first steps;
  - the level gait at the step's amplitude: a faster or slower level stride swings the
    thigh further or less both ways, so the level gait's θ_max and θ_min are scaled by the
    step's amplitude ratio r = Δθ/Δθ_H before the step is compared with them (without
    this a walk that speeds up from 2.5 to 4.8 km/h, Δθ doubled, read as 47 steps up on
    the simulated H2 at two of three seeds). Against it a step on stairs is the same
    swing shifted forward (the thigh stays flexed, both ways): by 8–10° up, 11–14° down,
    in simulation and on the real thigh board alike;
  - the evidence: the cycle's mid pitch (θ_max + θ_min)/2 above the scaled level one,
    ln r (up: larger), and θ_min: above the scaled level one up, about ``down_min_deg``
    down (Section 4.1.2: θ_Dmin is positive, the thigh no longer swings behind the
    vertical); Gaussian per state with the means and spreads of ``up_*``, ``down_*`` and
    ``level_*_sigma``;
  - the cycle's duration: stairs are walked, not run (a cycle shorter than
    ``stairs_cycle_min_s`` counts against them);
  - a step's pitch is no surer than the attitude's tilt: its σ over the cycle (large
    across a gap in the data) widens every state's spread of the mid pitch and θ_min,
    and a step whose tilt σ exceeds ``learn_max_tilt_sigma_deg`` teaches the person's
    level gait nothing (its pitch may be off by the tilt's error: steps right after a gap
    in the data, read as level, would shift the level gait and hide the next staircase);
  - the level state's evidence has heavy tails (a mixture, :meth:`_likelihood`), and a
    step that turned by more than ``turn_max_deg`` from the last one (the end of a
    corridor, a landing) is level with ``turn_sigma_factor`` times the spread: the pitch
    of a turning step is not a straight step's.

Standing and sitting are decided only when no step has come for ``rest_after_s``: from
the pitch, about 0° standing, 45°–90° sitting (:func:`rest_activity`). Activities are the
pdr_msgs/Step constants (:class:`pdr_core.vocabulary.Activity`).
"""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from pdr_core.vocabulary import Activity
from pdr_pocket.config import ActivityConfig


@dataclass(frozen=True)
class StepShape:
    """What a classifier sees of one step: θ_max, θ_min of its cycle and the turn of its
    heading since the last step [rad], the cycle's duration [s], and the largest σ of the
    attitude's tilt over the cycle [rad] (large after a gap in the data)."""

    pitch_max: float
    pitch_min: float
    turn: float
    duration: float
    tilt_sigma: float = 0.0


class ThesisActivity:
    """Step activities with the running level-step means (the thesis' algorithm)."""

    name = "thesis"

    def __init__(self, config: ActivityConfig) -> None:
        self.config = config
        self.level: deque = deque(maxlen=self.config.level_history_steps)

    def restart(self) -> None:
        """Forget the level steps (the phone was moved: θ is measured anew, and the steps
        while it turned were not the gait's)."""
        self.level.clear()

    def classify(self, shape: StepShape) -> Activity:
        """WALKING, UPSTAIRS or DOWNSTAIRS for one step."""
        c = self.config
        hi, lo = np.degrees(shape.pitch_max), np.degrees(shape.pitch_min)
        amplitude = hi - lo
        if len(self.level) == self.level.maxlen:
            mean_hi, mean_lo, mean_amp = np.mean(np.asarray(self.level), axis=0)
            if amplitude > mean_amp + c.up_amplitude_margin_deg and \
                    hi > mean_hi + c.up_max_margin_deg and \
                    lo > mean_lo - c.up_min_tolerance_deg:
                return Activity.UPSTAIRS
            if amplitude < c.down_amplitude_ratio * mean_amp and \
                    mean_lo + c.down_min_margin_deg < lo < mean_hi:
                return Activity.DOWNSTAIRS
        self.level.append((hi, lo, amplitude))
        return Activity.WALKING


STATES = (Activity.WALKING, Activity.UPSTAIRS, Activity.DOWNSTAIRS)   # the hidden states, in order


class LevelPriorActivity:
    """The hidden Markov model of the module docstring, filtered forward per step."""

    name = "level_prior"

    def __init__(self, config: ActivityConfig) -> None:
        c = self.config = config
        stay = c.stay_on_stairs_probability
        enter = c.enter_stairs_probability
        # transition[i, j]: P(state j at this step | state i at the last); up and down
        # meet only through a level step
        self.transition = np.array([[1.0 - 2.0 * enter, enter, enter],
                                    [1.0 - stay, stay, 0.0],
                                    [1.0 - stay, 0.0, stay]])
        self.means = np.array([[0.0, 0.0, 0.0],
                               [c.up_mid_excess_deg, np.log(c.up_amplitude_ratio),
                                c.up_min_excess_deg],
                               [c.down_mid_excess_deg, np.log(c.down_amplitude_ratio_mean),
                                c.down_min_deg]])
        # the features the means are counted from: the level gait's, but for θ_min of a
        # step down, which is absolute (the thigh no longer swings behind the vertical)
        self.relative = np.ones((3, 3))
        self.relative[2, 2] = 0.0
        self.sigmas = np.array([[c.level_mid_sigma_deg, c.level_log_amplitude_sigma,
                                 c.level_min_sigma_deg],
                                [c.stairs_mid_sigma_deg, c.stairs_log_amplitude_sigma,
                                 c.stairs_min_sigma_deg],
                                [c.stairs_mid_sigma_deg, c.stairs_log_amplitude_sigma,
                                 c.stairs_min_sigma_deg]])
        self.prior = np.array([(c.level_max_deg + c.level_min_deg) / 2.0,
                               np.log(c.level_max_deg - c.level_min_deg), c.level_min_deg])
        self.restart()

    def restart(self) -> None:
        """Level walking, the person's level gait not yet seen (a new walk, or the phone
        moved in the pocket)."""
        self.posterior = np.array([1.0, 0.0, 0.0])
        self.level: deque = deque(maxlen=self.config.level_history_steps)

    def reference(self) -> np.ndarray:
        """The level gait the steps are measured against: [mid pitch °, ln Δθ, θ_min °],
        the population's weighing ``prior_weight_steps`` steps and the person's last level
        steps."""
        w = self.config.prior_weight_steps
        return (w * self.prior + np.sum(self.level, axis=0)) / (w + len(self.level))

    def level_at(self, log_amplitude: float) -> np.ndarray:
        """The level gait at a step's amplitude (ln Δθ, Δθ in degrees): the
        :meth:`reference`'s mid pitch and θ_min scaled by r = Δθ/Δθ_H, its ln Δθ_H."""
        mid, log_level, low = self.reference()
        ratio = np.exp(log_amplitude - log_level)
        return np.array([mid * ratio, log_level, low * ratio])

    def classify(self, shape: StepShape) -> Activity:
        """WALKING, UPSTAIRS or DOWNSTAIRS for one step: the state of highest posterior
        probability after the step's evidence."""
        hi, lo = np.degrees(shape.pitch_max), np.degrees(shape.pitch_min)
        features = np.array([(hi + lo) / 2.0, np.log(max(hi - lo, 1e-3)), lo])
        predicted = self.transition.T @ self.posterior
        turning = abs(np.degrees(shape.turn)) > self.config.turn_max_deg
        sigmas = self.sigmas.copy()
        if turning:
            sigmas[0] *= self.config.turn_sigma_factor
        # the pitch is no surer than the tilt: its σ adds to the mid pitch's and θ_min's
        tilt_deg = np.degrees(shape.tilt_sigma)
        sigmas[:, [0, 2]] = np.hypot(sigmas[:, [0, 2]], tilt_deg)
        likelihood = self._likelihood(features - self.relative * self.level_at(features[1]),
                                      sigmas)
        posterior = predicted * likelihood * self._cadence(shape.duration)
        self.posterior = posterior / posterior.sum()
        state = int(np.argmax(self.posterior))
        if state == 0 and not turning and tilt_deg <= self.config.learn_max_tilt_sigma_deg \
                and self.posterior[0] >= self.config.learn_min_probability:
            self.level.append(features)
        return STATES[state]

    def _cadence(self, duration_s: float) -> np.ndarray:
        """p(cycle duration | state), relative: stairs are walked, not run, at a steady
        cadence; a cycle shorter than ``stairs_cycle_min_s`` is less likely on stairs by
        a Gaussian tail of ``stairs_cycle_sigma_s`` (a jog's 0.8 s cycle by 7×); longer
        cycles tell level and stairs apart no better than the pitch does."""
        c = self.config
        z = min(duration_s - c.stairs_cycle_min_s, 0.0) / c.stairs_cycle_sigma_s
        stairs = np.exp(-0.5 * z * z)
        return np.array([1.0, stairs, stairs])

    def _likelihood(self, excess: np.ndarray, sigmas: np.ndarray) -> np.ndarray:
        """p(features | state) per state, up to a common factor: Gaussian, the level
        state's a mixture with a ``level_outlier_sigma_factor`` times wider part of weight
        ``level_outlier_probability`` (a level step with a stumble, a door, a kerb: no
        one step is unmistakable stairs by being far from level alone)."""
        c = self.config
        wide = sigmas[0] * c.level_outlier_sigma_factor
        means = np.vstack([self.means, self.means[:1]])
        spreads = np.vstack([sigmas, wide])
        z = (np.vstack([excess, excess[:1]]) - means) / spreads
        log_density = -0.5 * np.sum(z * z, axis=1) - np.sum(np.log(spreads), axis=1)
        density = np.exp(log_density - log_density.max())
        level = (1.0 - c.level_outlier_probability) * density[0] + \
            c.level_outlier_probability * density[3]
        return np.array([level, density[1], density[2]])


class LevelOnlyActivity:
    """Every step level: without a gyroscope the pitch from the gravity direction alone
    has the legs' accelerations in it (its swing about half the thigh's, its mean
    shifted), and neither model's evidence holds on it."""

    name = "level only"

    def __init__(self, config: ActivityConfig) -> None:
        self.config = config

    def restart(self) -> None:
        """Nothing is learned."""

    def classify(self, shape: StepShape) -> Activity:
        return Activity.WALKING


MODELS = {"thesis": ThesisActivity, "level_prior": LevelPriorActivity}


def activity_classifier(config: ActivityConfig, gyroscope: bool = True):
    """The configured step activity classifier (``activity.model``); without a gyroscope
    :class:`LevelOnlyActivity`."""
    return MODELS[config.model](config) if gyroscope else LevelOnlyActivity(config)


def rest_activity(pitch: np.ndarray, config: ActivityConfig) -> np.ndarray:
    """STANDING or SITTING per sample from |θ| [rad] (N,)."""
    sitting = np.abs(np.degrees(pitch)) >= config.sitting_min_pitch_deg
    return np.where(sitting, Activity.SITTING, Activity.STANDING).astype(np.uint8)
