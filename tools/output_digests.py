"""Digests of everything the navigators output, to show that a change of structure changes
no byte (issue 56): run it before and after, and ``diff`` the two files.

    ./ws python tools/output_digests.py --out before.txt   # on the old commit
    ./ws python tools/output_digests.py --out after.txt    # on the new one
    diff before.txt after.txt

Inputs: the sample bags (bags/), a simulated walk with a barometer (:data:`SIMULATED`) and,
when the shared recordings are beside the repository
(``../shared/data`` or ``PDR_SHARED_DATA``), every one of them with a navigator
(test/wstest.py's SHARED_RECORDINGS: the pyshoe VICON trials, the x-io walk, the thigh
and Oxford pocket recordings), imported into a temporary folder. Each goes through its
navigator three ways:

- ``run``: ``pdr-ekf run`` or ``pdr-pocket run`` (the shipped configuration), every
  message of the output bag as raw CDR bytes with its topic and stamp, and report.json;
- ``drift``: the same with ``--drift online`` (the pocket with config/pocket_pdr_no_mag.yaml,
  the thesis' setting, whose landmarks correct it), the late corrections' replay included;
- ``chunks``: the streaming navigator a node runs (pdr_ins_ekf.streaming.StreamingNavigator,
  pdr_pocket.streaming.StreamingPocket), pushed blocks of ``--block`` IMU samples (37) with
  the other sensors' readings up to each block's end; its estimates packed as the nodes
  pack them, as CDR bytes.

One line per input and way: the name, the way, the first 16 hex digits of the SHA-256 and
what it covers (messages, or the refusal's exit status). A report's ``elapsed`` timings and
paths are left out: they change from run to run.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "test"))

from pdr_core import topics  # noqa: E402
from pdr_core.io import cdr  # noqa: E402
from pdr_core.io.bag import BagReader  # noqa: E402
from pdr_core.io.batch import MessageBatch  # noqa: E402
from pdr_core.io.csv_export import has_gyroscope  # noqa: E402
from wstest import SHARED_RECORDINGS, cli  # noqa: E402

SAMPLE_BAGS = {"foot_walk": "foot", "vicon_walk": "foot", "pocket_walk": "pocket"}
# simulated here, for what the sample bags lack: a barometer (four floors up and down)
SIMULATED = {"up_dw_barometer": (["--placement", "pocket", "--scenario", "up_dw", "--rate",
                                  "50", "--pressure", "--seed", "1"], "pocket")}
NO_MAG = ROOT / "src" / "pdr_pocket" / "config" / "pocket_pdr_no_mag.yaml"
RUN = {"foot": ("pdr-ekf", ()), "pocket": ("pdr-pocket", ())}
DRIFT = {"foot": ("pdr-ekf", ("--drift", "online")),
         "pocket": ("pdr-pocket", ("--drift", "online", "--config", str(NO_MAG)))}
VOLATILE = ("elapsed", "path", "out", "bag", "wall")


def inputs(work: Path) -> Iterator[tuple[str, Path, str]]:
    """(name, bag, navigator) of the sample bags, then of the shared recordings found."""
    for name, navigator in SAMPLE_BAGS.items():
        yield name, ROOT / "bags" / name, navigator
    for name, (args, navigator) in SIMULATED.items():
        bag = work / "simulated" / name
        result = cli("pdr-sim", "generate", *args, "--out", bag)
        if result.returncode != 0:
            raise SystemExit(f"output_digests: pdr-sim generate {name} failed: {result.stderr}")
        yield name, bag, navigator
    for name, (csv, args, navigator) in SHARED_RECORDINGS.items():
        if not csv.exists():
            continue
        bag = work / "imported" / name
        result = cli("pdr-sim", "import-csv", csv, "--out", bag, *args)
        if result.returncode != 0:
            raise SystemExit(f"output_digests: {csv}: import-csv failed: {result.stderr}")
        yield name, bag, navigator


def report_digest(h, report: Path) -> None:
    """report.json without the keys that change from run to run."""
    def kept(value):
        if isinstance(value, dict):
            return {k: kept(v) for k, v in value.items()
                    if not any(word in k for word in VOLATILE)}
        if isinstance(value, list):
            return [kept(v) for v in value]
        return value
    h.update(json.dumps(kept(json.loads(report.read_text())), sort_keys=True).encode())


def bag_digest(h, bag: Path) -> int:
    """Every message of ``bag``: topic, log time and CDR bytes, by topic and time."""
    messages = sorted((m.topic, m.log_time_ns, m.data) for m in BagReader(bag).raw_messages())
    for topic, stamp, data in messages:
        h.update(topic.encode() + stamp.to_bytes(8, "little", signed=True) + data)
    return len(messages)


def offline(bag: Path, out: Path, program: str, args: tuple[str, ...]) -> tuple[str, str]:
    """The digest of a run of ``program run BAG ARGS`` and what it covers."""
    h = hashlib.sha256()
    result = cli(program, "run", bag, "--out", out, *args)
    if result.returncode != 0:
        h.update(f"{result.returncode} {result.stderr.splitlines()[:1]}".encode())
        return h.hexdigest()[:16], f"refused, exit {result.returncode}"
    count = bag_digest(h, out)
    report_digest(h, out / "report.json")
    return h.hexdigest()[:16], f"{count} messages"


def encoded(h, batches: dict) -> int:
    """The batches' messages (MessageBatch, or LazyBatch built whole) as CDR bytes, by
    topic name."""
    count = 0
    for topic in sorted(batches):
        batch = batches[topic]
        for data in cdr.encode(batch if isinstance(batch, MessageBatch) else
                               batch.take(slice(0, len(batch)))):
            h.update(topic.encode() + data)
            count += 1
    return count


def foot_chunks(bag: Path, block: int) -> tuple[str, str]:
    """zupt_ekf's streaming navigator in blocks: what the node publishes of each block
    (pose, velocity, odometry, stance; the strides and their poses)."""
    from pdr_ins_ekf.config import load_run_config
    from pdr_ins_ekf.offline import output_batches, stride_batches
    from pdr_ins_ekf.streaming import StreamingNavigator

    imu = BagReader(bag).read(topics.IMU_DATA)
    navigator, h = StreamingNavigator(load_run_config()), hashlib.sha256()

    def digest(run) -> int:
        if not len(run.stamp_ns):
            return 0
        return encoded(h, output_batches(run)) + encoded(h, stride_batches(run.strides))

    count = sum(digest(navigator.push_many(imu.stamp_ns[start:start + block],
                                           imu["linear_acceleration"][start:start + block],
                                           imu["angular_velocity"][start:start + block]))
                for start in range(0, len(imu), block))
    count += digest(navigator.flush())
    return h.hexdigest()[:16], f"{count} messages"


def pocket_chunks(bag: Path, block: int) -> tuple[str, str]:
    """pocket_pdr's streaming navigator in blocks: each step's step, pose and odometry
    fields as the node packs them, and the attitude, gyro bias and covariance per sample."""
    from pdr_core.io.msgtypes import ODOMETRY
    from pdr_pocket.config import load_pocket_config
    from pdr_pocket.messages import odometry_step_fields, step_fields
    from pdr_pocket.sensor_inputs import SENSOR_INPUTS
    from pdr_pocket.streaming import StreamingPocket

    reader = BagReader(bag)
    imu = reader.read(topics.IMU_DATA)
    mag = reader.read(topics.IMU_MAG) if topics.IMU_MAG in reader.topics else None
    others = [(s, reader.read(s.topic)) for s in SENSOR_INPUTS if s.topic in reader.topics]
    gyro = has_gyroscope(imu)
    navigator, h, count = StreamingPocket(load_pocket_config()), hashlib.sha256(), 0

    def digest(processed) -> int:
        steps = 0
        for chunk in processed:
            attitude = chunk.output.attitude
            for array in (chunk.stamp_ns, attitude.attitude, attitude.bias, attitude.covariance):
                h.update(np.ascontiguousarray(array).tobytes())
            if chunk.output.steps:
                rotations = np.array([a for a, _ in chunk.step_attitude])
                covariances = np.array([c for _, c in chunk.step_attitude])
                stamps = [chunk.stamp_of(s.t_confirm) for s in chunk.output.steps]
                h.update(json.dumps({k: np.asarray(v).tolist() for k, v in
                                     step_fields(chunk.output.steps).items()}).encode())
                encoded(h, {"odometry": MessageBatch(ODOMETRY, stamps, "map", odometry_step_fields(
                    chunk.output.steps, rotations, covariances, "base_link"))})
                steps += len(chunk.output.steps)
        return steps

    taken = {id(batch): 0 for batch in [mag, *(b for _, b in others)] if batch is not None}
    for start in range(0, len(imu), block):
        part = slice(start, start + block)
        end = imu.stamp_ns[part][-1]
        if mag is not None:
            first, taken[id(mag)] = taken[id(mag)], np.searchsorted(mag.stamp_ns, end, "right")
            count += digest(navigator.push_mags(mag.stamp_ns[first:taken[id(mag)]],
                                                mag["magnetic_field"][first:taken[id(mag)]]))
        for sensor, batch in others:
            first, taken[id(batch)] = taken[id(batch)], np.searchsorted(batch.stamp_ns, end,
                                                                        "right")
            count += digest(navigator.push_readings(
                sensor.name, batch.stamp_ns[first:taken[id(batch)]],
                batch[sensor.field][first:taken[id(batch)]]))
        count += digest(navigator.push_imus(
            imu.stamp_ns[part], imu["linear_acceleration"][part],
            imu["angular_velocity"][part] if gyro else None))
    count += digest(navigator.flush())
    return h.hexdigest()[:16], f"{count} steps"


def digests(name: str, bag: Path, navigator: str, work: Path, block: int
            ) -> Iterator[tuple[str, str, str]]:
    """(way, digest, what it covers) of one input, each of the three ways."""
    program, args = RUN[navigator]
    yield "run", *offline(bag, work / f"{name}_run", program, args)
    program, args = DRIFT[navigator]
    yield "drift", *offline(bag, work / f"{name}_drift", program, args)
    yield "chunks", *(foot_chunks if navigator == "foot" else pocket_chunks)(bag, block)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="output_digests", description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, help="also write the lines to this file")
    parser.add_argument("--block", type=int, default=37, help="IMU samples per pushed block")
    args = parser.parse_args(argv)
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name, bag, navigator in inputs(work):
            for way, value, covers in digests(name, bag, navigator, work, args.block):
                lines.append(f"{name:<22} {navigator:<6} {way:<6} {value} {covers}")
                print(lines[-1], flush=True)
    if args.out:
        args.out.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
