"""``pdr-sim generate`` and ``pdr-sim allan`` as a user runs them (issue 3)."""
from __future__ import annotations

import csv

import numpy as np
import pytest
import yaml

from pdr_core.io.bag import BagReader


def test_two_hour_static_allan_recovers_the_xsens_mtw_noise(procs, tmp_path):
    """Acceptance 2: ARW, VRW and bias instability within 10 % of the configuration."""
    scenario = tmp_path / "static.yaml"
    scenario.write_text("segments: [{type: standing, duration_s: 7200}]\n")
    made = procs.run("pdr-sim", "generate", "--scenario", str(scenario), "--imu", "xsens_mtw",
                     "--rate", "100", "--seed", "5", "--out", str(tmp_path / "bag"))
    assert made.returncode == 0, made.stderr
    result = procs.run("pdr-sim", "allan", str(tmp_path / "bag"), "--out", str(tmp_path / "a"))
    assert result.returncode == 0, result.stderr
    print(result.stdout)
    rows = list(csv.reader((tmp_path / "a" / "allan.csv").read_text().splitlines()))
    gyro = {r[0]: dict(zip(rows[0], r, strict=True)) for r in rows[1:4]}
    accel = {r[0]: dict(zip(rows[4], r, strict=True)) for r in rows[5:8]}
    for row in gyro.values():
        assert float(row["arw_deg_per_sqrt_h"]) == pytest.approx(0.6, rel=0.1)
        assert float(row["bias_instability_deg_per_h"]) == pytest.approx(10.0, rel=0.1)
    for row in accel.values():
        assert float(row["vrw_ug_per_sqrt_hz"]) == pytest.approx(200.0, rel=0.1)
        assert float(row["bias_instability_mg"]) == pytest.approx(0.1, rel=0.1)
    assert (tmp_path / "a" / "allan.png").stat().st_size > 10_000


def test_generate_records_its_configuration_and_plots(procs, tmp_path):
    result = procs.run("pdr-sim", "generate", "--scenario", "figure_eight", "--imu", "vn200",
                       "--rate", "200", "--seed", "9", "--set", "step.length_m=1.2",
                       "--imu-set", "gyro.arw_deg_per_sqrt_h=0.5", "--out",
                       str(tmp_path / "bag"), "--plot", str(tmp_path / "png"))
    assert result.returncode == 0, result.stderr
    assert "path 24.00 m" in result.stdout, "20 strides of the overridden 1.2 m"
    meta = yaml.safe_load((tmp_path / "bag" / "metadata.yaml").read_text())
    record = yaml.safe_load(meta["rosbag2_bagfile_information"]["custom_data"]["pdr.simulation"])
    assert record["imu_profile"] == "vn200" and record["seed"] == 9 and record["rate_hz"] == 200
    assert record["scenario"]["step"]["length_m"] == 1.2
    assert record["imu_overrides"] == {"gyro": {"arw_deg_per_sqrt_h": 0.5}}
    reader = BagReader(tmp_path / "bag")
    imu, pose = reader.read("/imu/data"), reader.read("/ground_truth/pose")
    assert len(imu) == len(pose) == len(reader.read("/imu/mag"))
    np.testing.assert_array_equal(imu.stamp_ns, pose.stamp_ns)
    assert np.diff(imu.stamp_ns).max() == 5_000_000
    for png in ("trajectory.png", "signals.png"):
        assert (tmp_path / "png" / png).stat().st_size > 10_000


def test_generate_pocket_writes_truth_topics_and_plots(procs, tmp_path):
    result = procs.run("pdr-sim", "generate", "--placement", "pocket", "--scenario",
                       "sit_stand", "--rate", "50", "--out", str(tmp_path / "bag"), "--plot",
                       str(tmp_path / "png"))
    assert result.returncode == 0, result.stderr
    assert "66 steps" in result.stdout
    reader = BagReader(tmp_path / "bag")
    assert set(reader.topics) == {"/imu/data", "/imu/mag", "/ground_truth/pose",
                                  "/ground_truth/step", "/ground_truth/landmarks", "/tf",
                                  "/tf_static"}
    steps = reader.read("/ground_truth/step")
    assert len(steps) == 66 and set(steps["activity"]) == {1}
    record = reader.custom_data("pdr.simulation")
    assert record["placement"] == "pocket" and record["true_gyro_bias_deg_per_s"]
    assert [p["activity"] for p in record["periods"]] == [
        "standing", "walking", "sitting", "walking", "standing", "walking", "sitting", "standing"]
    for png in ("trajectory.png", "signals.png", "pocket.png"):
        assert (tmp_path / "png" / png).stat().st_size > 10_000


@pytest.mark.parametrize("args, message", [
    (["--imu", "mti_9000"], "--imu: unknown profile 'mti_9000'"),
    (["--rate", "20"], "--rate: must be within 50-1000 Hz"),
    (["--set", "step.height_m=-0.1"], "step.height_m: must be >= 0.0"),
    (["--set", "step.swing_s=0"], "step.swing_s: must be > 0.0"),
    (["--set", "segments[0].duration_s=-2"], "segments[0].duration_s: must be > 0.0"),
    (["--set", "stride.length_m=1"], "stride: unknown key"),
    (["--imu-set", "gyro.arw=1"], "xsens_mtw.gyro.arw: unknown key"),
    (["--placement", "pocket", "--scenario", "straight"], "straight: no such scenario file"),
    (["--placement", "pocket", "--set", "segments[1].speed_kmh=20"],
     "h1_rectangle (with --set): segments[1].speed_kmh: 20 is beyond walking speed (0.5-7)"),
    (["--placement", "pocket", "--scenario", "up_dw", "--set", "segments[2].riser_m=0.4"],
     "segments[2].riser_m: 0.4 is beyond a human-range riser (0.05-0.25)"),
    (["--placement", "foot", "--scenario", "up_dw"], "up_dw: no such scenario file"),
])
def test_generate_refuses_bad_input_by_name(procs, tmp_path, args, message):
    result = procs.run("pdr-sim", "generate", "--out", str(tmp_path / "bag"), *args)
    assert result.returncode == 2
    [line] = result.stderr.strip().splitlines()
    assert line.startswith("pdr-sim: error: ") and message in line
    assert not (tmp_path / "bag").exists()


def test_allan_reads_a_csv_and_names_missing_columns(procs, tmp_path):
    rng = np.random.default_rng(0)
    n = 60_000  # 10 min at 100 Hz
    data = np.column_stack([np.arange(n) / 100.0, rng.normal(0, 0.01, (n, 3)),
                            rng.normal(0, 0.02, (n, 3)) + [0, 0, 9.81]])
    csv_path = tmp_path / "static.csv"
    np.savetxt(csv_path, data, delimiter=",", header="t,gx,gy,gz,ax,ay,az", comments="")
    result = procs.run("pdr-sim", "allan", str(csv_path), "--time-col", "t",
                       "--gyro-cols", "gx,gy,gz", "--acc-cols", "ax,ay,az")
    assert result.returncode == 0, result.stderr
    rows = result.stdout.strip().splitlines()
    assert [r.split()[0] for r in rows] == ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y",
                                            "accel_z"]
    arw = float(rows[0].split("arw_deg_per_sqrt_h=")[1].split()[0])
    assert arw == pytest.approx(0.01 * 0.1 * 180 / np.pi * 60, rel=0.1), "σ/√f_s in °/√h"
    missing = procs.run("pdr-sim", "allan", str(csv_path), "--time-col", "t")
    assert missing.returncode == 2 and "--acc-cols: required for a CSV source" in missing.stderr


@pytest.mark.parametrize("case", ["missing", "corrupt", "unknown_topic"])
def test_bag_errors_are_one_line_naming_the_file(procs, tmp_path, case):
    bag = tmp_path / "bag"
    if case != "missing":
        made = procs.run("pdr-sim", "generate", "--scenario", "square_loop", "--out", str(bag))
        assert made.returncode == 0, made.stderr
    if case == "corrupt":
        mcap = bag / "bag.mcap"
        mcap.write_bytes(mcap.read_bytes()[:5000])
    args = ["--topic", "/nope"] if case == "unknown_topic" else []
    result = procs.run("pdr-sim", "allan", str(bag), *args)
    assert result.returncode == 2
    *warned, line = result.stderr.strip().splitlines()
    expected = {"missing": f"{bag}: no such bag",
                "corrupt": f"{bag}: 0 samples are too few",
                "unknown_topic": f"{bag}: no topic /nope (the bag has: "}[case]
    assert line.startswith(f"pdr-sim: error: {expected}")
    assert warned == ([f"pdr-sim: warning: {bag / 'bag.mcap'}: cut short or unindexed: "
                       "readable to byte 43 of 5000, 0 messages: those are used, the rest is "
                       "lost"] if case == "corrupt" else [])
