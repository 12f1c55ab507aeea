"""Benchmark: the pocket orientation filter beside the peers a user would pick instead.

Run on purpose (``make bench``, which installs the peers of tools/requirements-bench.in),
not in CI. On the same simulated pocket walks, in one run:

- ours: pdr_pocket's UKF (Muñoz Díaz 2016, chapter 3) with its shipped updates
  (absolute gravity, differential magnetic field, ZARU, mean gravity) and the noise of
  the simulated sensor (config/pocket_pdr_xsens_mtw.yaml's ``imu_profile: xsens_mtw``);
- VQF (``vqf``, 9D, its rest and motion bias estimation), x-io Fusion (``imufusion``:
  AHRS with magnetometer, and its gyroscope bias algorithm), ``ahrs``' Madgwick and
  Mahony with magnetometer, and ``ahrs``' UKF (for its speed).

It prints roll, pitch and yaw RMSE [°] against the truth, the final z gyro bias estimate
[°/s] (— for filters without one) and samples per second. The peers' navigation frames
(NWU, NED, ...) differ from ENU by a constant rotation, and the yaw reference is
arbitrary without a compass convention in common, so every estimate is aligned to the
truth by the one constant rotation that best maps the whole walk onto it (the mean of
the rotation differences); what is left is the error that changes over the walk.
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from pdr_pocket.config import OrientationConfig
from pdr_pocket.orientation import OrientationFilter
from pdr_sim.pocket_scenario import load_pocket_scenario, pocket_scenario_from_dict
from pdr_sim.simulation import SimulationConfig, simulate

RATE_HZ = 100.0
G = 9.80665
NO_STOP = load_pocket_scenario(Path(__file__).with_name("no_stop_walk.yaml"))[1]


def walks() -> dict:
    _, thesis = load_pocket_scenario("theresienhoehe")
    out = {}
    for name, data, imu in (("20 min, no stop (Table 3.2 errors)", NO_STOP, "thesis_table_3_2"),
                            ("Theresienhöhe 22 min (Xsens MTw)", thesis, "xsens_mtw")):
        out[name] = simulate(SimulationConfig(pocket_scenario_from_dict(data, name), data, imu,
                                              {}, RATE_HZ, 1, placement="pocket"))
    return out


def ours(gyr, acc, mag):
    f = OrientationFilter(OrientationConfig(imu_profile="xsens_mtw"))
    est = f.run(np.arange(len(gyr)) / RATE_HZ, gyr, acc, mag)
    return Rotation.from_matrix(est.attitude), est.bias[-1, 2]


def vqf_9d(gyr, acc, mag):
    from vqf import VQF

    out = VQF(1.0 / RATE_HZ).updateBatch(gyr, acc, mag * 1e6)
    return Rotation.from_quat(out["quat9D"][:, [1, 2, 3, 0]]), out["bias"][-1, 2]


def fusion(gyr, acc, mag):
    import imufusion

    ahrs, bias = imufusion.Ahrs(), imufusion.Bias()
    settings = imufusion.AhrsSettings()
    settings.sample_rate = RATE_HZ
    ahrs.set_settings(settings)
    bias_settings = imufusion.BiasSettings()
    bias_settings.sample_rate = RATE_HZ
    bias.set_settings(bias_settings)
    gyr_deg, acc_g, mag_ut = np.degrees(gyr), acc / G, mag * 1e6
    quats = np.empty((len(gyr), 4))
    for k in range(len(gyr)):
        ahrs.update(bias.update(gyr_deg[k]), acc_g[k], mag_ut[k])
        quats[k] = ahrs.get_quaternion()
    return Rotation.from_quat(quats[:, [1, 2, 3, 0]]), np.radians(bias.get_offset()[2])


def madgwick(gyr, acc, mag):
    from ahrs.filters import Madgwick

    q = Madgwick(gyr=gyr, acc=acc, mag=mag * 1e6, frequency=RATE_HZ).Q
    return Rotation.from_quat(q[:, [1, 2, 3, 0]]), None


def mahony(gyr, acc, mag):
    from ahrs.filters import Mahony

    q = Mahony(gyr=gyr, acc=acc, mag=mag * 1e6, frequency=RATE_HZ).Q
    return Rotation.from_quat(q[:, [1, 2, 3, 0]]), None


def ahrs_ukf(gyr, acc, mag):
    from ahrs.filters import UKF

    q = UKF(gyr=gyr, acc=acc, mag=mag * 1e6, frequency=RATE_HZ).Q
    return Rotation.from_quat(q[:, [1, 2, 3, 0]]), None


FILTERS = {"ours (pdr_pocket UKF)": ours, "VQF 9D": vqf_9d, "x-io Fusion": fusion,
           "ahrs Madgwick": madgwick, "ahrs Mahony": mahony, "ahrs UKF": ahrs_ukf}


def rmse_deg(estimate: Rotation, truth: Rotation) -> np.ndarray:
    """Roll, pitch, yaw RMSE after the best constant navigation-frame alignment."""
    align = (truth * estimate.inv()).mean()
    est = (align * estimate).as_euler("ZYX")[:, ::-1]
    err = np.angle(np.exp(1j * (est - truth.as_euler("ZYX")[:, ::-1])))
    return np.degrees(np.sqrt(np.mean(err**2, axis=0)))


def main() -> None:
    sims = walks()
    print(f"{'walk':<36}{'filter':<24}{'roll':>7}{'pitch':>7}{'yaw':>8}"
          f"{'b_z end':>10}{'b_z true':>10}{'samples/s':>12}")
    ours(np.zeros((50, 3)), np.tile([0.0, 0.0, G], (50, 1)),
         np.tile([0.0, 2e-5, -4e-5], (50, 1)))    # compile (numba caches it) outside the timing
    for walk, sim in sims.items():
        gyr = np.ascontiguousarray(sim.imu["angular_velocity"])
        acc = np.ascontiguousarray(sim.imu["linear_acceleration"])
        mag = np.ascontiguousarray(sim.mag["magnetic_field"])
        truth = sim.trajectory.attitude
        for name, run in FILTERS.items():
            try:
                start = time.perf_counter()
                estimate, bz = run(gyr, acc, mag)
                seconds = time.perf_counter() - start
            except Exception as exc:
                print(f"{walk:<36}{name:<24} failed: {exc}")
                continue
            r, p, y = rmse_deg(estimate, truth)
            bz_text = "—" if bz is None else f"{np.degrees(bz):.4f}"
            print(f"{walk:<36}{name:<24}{r:>7.2f}{p:>7.2f}{y:>8.2f}{bz_text:>10}"
                  f"{np.degrees(sim.gyro_bias[2]):>10.3f}{len(gyr) / seconds:>12,.0f}",
                  flush=True)


if __name__ == "__main__":
    main()
