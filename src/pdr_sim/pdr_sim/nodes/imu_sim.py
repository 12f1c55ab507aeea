"""Node ``imu_sim``: publishes a simulated walk live, as ``pdr-sim generate`` writes it.

Parameters (``--params-file config/imu_sim.yaml`` or ``-p name:=value``):
    scenario (str, ""): built-in scenario name or YAML file; empty: the placement's
        default (straight for the foot, h1_rectangle for the pocket).
    imu (str, "xsens_mtw"): IMU error profile.
    rate_hz (float, 100.0): sample rate [Hz], 50-1000.
    seed (int, 0): seed of the sensor errors.
    placement (str, "foot"): foot, or pocket (a phone in the trouser pocket).
    gravity_mps2 (float, 9.80665).
    pressure (bool, false): also the barometer: ``imu/pressure`` (``pdr-sim generate
        --pressure``).
    rate, clock, wait_for_subscribers, wait_timeout_s, ack_every: see
        :mod:`pdr_sim.nodes.playback` (rate 1.0 = real time).

Publishes ``imu/data``, ``imu/mag`` (with ``pressure`` ``imu/pressure``, sensor_msgs/
FluidPressure) and ``ground_truth/pose``, and the foot placement
``ground_truth/stance`` (the pocket placement ``ground_truth/step`` and
``ground_truth/landmarks``) with the stamps of the simulation
(data time, not the wall clock), then exits. The messages are identical to those of
``pdr-sim generate`` with the same configuration.
"""
from __future__ import annotations

from rclpy.node import Node

from pdr_core.constants import STANDARD_GRAVITY_MPS2
from pdr_core.errors import InputError
from pdr_core.io.bag import merged_messages
from pdr_core.ros.node_params import declare
from pdr_core.sensors.imu_profiles import PROFILES
from pdr_sim.nodes.playback import Playback, run_player
from pdr_sim.simulation import PLACEMENTS, SimulationConfig, load_placement_scenario, simulate


class ImuSim(Node):
    """Simulates on start, then publishes; :meth:`run` returns the exit status."""

    def __init__(self) -> None:
        super().__init__("imu_sim")
        self.scenario = declare(self, "scenario", "", "built-in scenario name or a scenario "
                                "YAML file; empty: straight (foot), h1_rectangle (pocket)")
        self.imu = declare(self, "imu", "xsens_mtw", "IMU error profile", tuple(PROFILES))
        self.rate_hz = declare(self, "rate_hz", 100.0, "sample rate [Hz], 50-1000")
        self.seed = declare(self, "seed", 0, "seed of every random draw")
        self.placement = declare(self, "placement", "foot", "where the IMU sits", PLACEMENTS)
        self.gravity = declare(self, "gravity_mps2", STANDARD_GRAVITY_MPS2,
                               "magnitude of gravity [m/s²]")
        self.pressure = declare(self, "pressure", False, "also simulate the barometer and "
                                "publish imu/pressure (sensor_msgs/FluidPressure, Pa)")
        self.playback = Playback(self)

    def run(self) -> int:
        try:
            name = self.scenario or ("h1_rectangle" if self.placement == "pocket"
                                     else "straight")
            scenario, data = load_placement_scenario(name, self.placement)
            sim = simulate(SimulationConfig(scenario, data, self.imu, {}, self.rate_hz,
                                            self.seed, self.gravity, self.placement,
                                            self.pressure))
        except InputError as exc:
            self.get_logger().error(str(exc))
            return 2
        batches = sim.batches
        self.playback.advertise({t: b.msgtype for t, b in batches.items()})
        if not self.playback.wait_for_subscribers_or_timeout():
            return 1
        self.get_logger().info(f"publishing {scenario.name}: {len(sim.imu)} samples at "
                               f"{self.rate_hz:g} Hz, speed x{self.playback.rate:g}")
        self.playback.publish(merged_messages(batches))
        self.playback.wait_acked()
        self.get_logger().info(f"published {self.playback.published} messages")
        return 0


def main(args: list[str] | None = None) -> None:
    run_player("imu_sim", ImuSim, args)

if __name__ == "__main__":
    main()
