"""What the pocket navigator gives (pdr_pocket.navigator): :class:`StepRecord`, one step
with the pose after it, and :class:`NavigatorOutput`, a chunk's results."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdr_core.sensors.barometry import HeightChangeKind
from pdr_core.vocabulary import Ride
from pdr_pocket.orientation import AttitudeEstimate

# pdr_msgs/Step's ride of each kind of ride the height filter finds
RIDES = {HeightChangeKind.LIFT: Ride.LIFT, HeightChangeKind.ESCALATOR: Ride.ESCALATOR}


@dataclass(frozen=True, kw_only=True)
class StepRecord:
    """One step (pdr_msgs/Step fields, SI) with the pose after it; made by keyword."""

    index: int
    t: float                    # the pitch maximum [s]
    t_confirm: float            # when it was known (the navigator's output time) [s]
    length: float
    vertical_displacement: float
    heading: float
    pitch_max: float
    pitch_min: float
    duration: float
    activity: int
    position: np.ndarray
    covariance: np.ndarray
    floor: int
    vertical_force_range: float     # max − min of the vertical specific force [m/s²]
    ride: int = Ride.NONE           # a ride ended before the step (pdr_core.vocabulary.Ride)
    ride_height: float = 0.0        # the height it took [m], in vertical_displacement
    # the step's mean velocity in the map frame [m/s] (3,) and its covariance [m²/s²]
    # (3, 3), pdr_pocket.step_assembly.step_velocity; None: not known (a run read back)
    velocity: np.ndarray | None = None
    velocity_covariance: np.ndarray | None = None
    # the position covariance [m²] (3, 3) of pdr/pocket/odometry, for a fusion node
    # (pdr_pocket.position's P̃; ``covariance`` is the filter's, of pdr/pocket/pose and
    # the drift loop); None: not known (a run read back), the odometry then has
    # ``covariance``
    odometry_covariance: np.ndarray | None = None

    @property
    def pitch_amplitude(self) -> float:
        return self.pitch_max - self.pitch_min


@dataclass
class NavigatorOutput:
    """A chunk's results: the attitude per sample, the thigh pitch and heading [rad] (NaN
    while the axes are unknown), the activity per sample and the steps confirmed."""

    attitude: AttitudeEstimate
    pitch: np.ndarray
    heading: np.ndarray
    activity: np.ndarray
    steps: list[StepRecord] = field(default_factory=list)

    @staticmethod
    def concatenate(outputs: list[NavigatorOutput]) -> NavigatorOutput:
        """One output of consecutive chunks' outputs."""
        a = [o.attitude for o in outputs]
        attitude = AttitudeEstimate(*(np.concatenate([getattr(x, f) for x in a]) for f in
                                      ("t", "attitude", "bias", "covariance", "detected",
                                       "ran")))
        return NavigatorOutput(attitude, np.concatenate([o.pitch for o in outputs]),
                               np.concatenate([o.heading for o in outputs]),
                               np.concatenate([o.activity for o in outputs]),
                               [s for o in outputs for s in o.steps])
