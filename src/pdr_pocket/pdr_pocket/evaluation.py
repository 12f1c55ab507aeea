"""``pdr-pocket evaluate``: the report of a ``pdr-pocket run`` output against a truth given
afterwards: a bag's ``ground_truth/step`` and ``ground_truth/pose``, a CSV of true
footfall (or gait cycle) times or a foot switch's contacts, a known walked distance.

The figures against a bag are :func:`pdr_pocket.run_report.navigation_report`'s, on
the steps as the run made them: the same numbers ``pdr-pocket run`` reports when its input
holds that truth. Every field: docs/reports.md.

- :func:`read_run`: a run output's steps (:class:`~pdr_pocket.navigator.StepRecord`),
  staircases and footfalls, from ``pdr/pocket/step``, ``pdr/pocket/pose`` and the run
  record of its metadata.yaml (pdr_pocket.pocket_offline.run_record);
- :func:`read_truth_bag`: a bag's truth topics on the run's clock. Times count from
  each bag's first ``imu/data`` message, so the truth of a simulated bag applies to a run
  on its ``pdr-sim export-csv`` log imported again; a truth bag without ``imu/data`` is
  taken to share the run's clock;
- :class:`TruthStepsFormat`, :func:`read_truth_steps`: the true times of a CSV, one a row
  or a foot switch's 0→1 edges, on the time axis it names (:func:`recording_span_s`);
- :func:`step_count_report`: true footfall or gait cycle times against the run's count;
- :func:`known_distance_report`: the distance walked against a known one;
- :func:`evaluate`: the report.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.errors import InputError
from pdr_core.io.batch import MessageBatch
from pdr_core.units import TIME_UNITS_S
from pdr_pocket.config import StairsConfig
from pdr_pocket.pocket_offline import RUN_RECORD
from pdr_pocket.records import StepRecord
from pdr_pocket.run_report import navigation_report, true_floors
from pdr_pocket.stairs import Staircases

# --truth-steps: what one row of the CSV is
STEPS_PER = ("footfall", "cycle")
# --truth-steps-format: what the CSV holds: a true time a row, or a foot switch's contact
# signals (time, left, right), whose 0→1 edges are the footfalls
TRUTH_STEPS_FORMATS = ("times", "foot-switch")
# --truth-steps-time: the time axis of its times: from the input's first imu/data message,
# or the input's message stamps (recording_span_s)
TRUTH_STEPS_TIMES = ("from-start", "stamps")
# The columns each format reads (--truth-steps-cols), by default the first ones in order
TRUTH_STEPS_COLUMNS = {"times": ("time",), "foot-switch": ("time", "left", "right")}
# How far [s] true step times may lie outside the run's samples before a warning
TIME_SPAN_MARGIN_S = 1.0


@dataclass
class RunOutput:
    """A ``pdr-pocket run`` output as :func:`navigation_report` takes it."""

    steps: list[StepRecord]
    stamps: np.ndarray          # (N,) the steps' stamps [ns] (their confirmation)
    staircases: Staircases
    footfalls: int
    start_ns: int               # the first IMU sample used (t = 0)
    end_ns: int                 # the last IMU message
    input_first_ns: int         # the input's first imu/data message


def _not_a_run(path: Path, why: str) -> InputError:
    return InputError(path, f"not a pdr-pocket run output: {why}; evaluate the output "
                            "directory of pdr-pocket run BAG --out OUT")


def read_run(path: Path, *, strict: bool = False) -> RunOutput:
    """The run output at ``path`` (module docstring); InputError when it is none."""
    from pdr_core.io.bag import BagReader

    reader = BagReader(path, strict=strict)
    missing = [t for t in (topics.POCKET_STEP, topics.POCKET_POSE) if t not in reader.topics]
    if missing:
        have = ", ".join(sorted(reader.topics)) or "none"
        raise _not_a_run(path, f"no topic {', '.join(missing)} (the bag has: {have})")
    record = reader.custom_data(RUN_RECORD)
    if not isinstance(record, dict) or "step_t_s" not in record:
        raise _not_a_run(path, f"its metadata.yaml has no {RUN_RECORD} record (a recording "
                               "of pocket_pdr, or a run older than pdr-pocket evaluate)")
    data = reader.read_batches([topics.POCKET_STEP, topics.POCKET_POSE])
    steps, poses = data[topics.POCKET_STEP], data[topics.POCKET_POSE]
    if len(record["step_t_s"]) != len(steps):
        raise _not_a_run(path, f"its {RUN_RECORD} record has {len(record['step_t_s'])} step "
                               f"times for {len(steps)} {topics.POCKET_STEP} messages")
    pose_of = {int(s): i for i, s in enumerate(poses.stamp_ns)}
    unpaired = [int(s) for s in steps.stamp_ns if int(s) not in pose_of]
    if unpaired:
        raise _not_a_run(path, f"{len(unpaired)} steps without their {topics.POCKET_POSE} (the "
                               f"first stamped {unpaired[0]} ns)")
    staircases = Staircases(dataclasses.replace(StairsConfig(),
                                                floor_height_m=record["floor_height_m"]))
    start_ns = int(record["start_ns"])
    records = []
    for k, stamp in enumerate(steps.stamp_ns):
        i = pose_of[int(stamp)]
        position = poses["pose.pose.position"][i]
        t = float(record["step_t_s"][k])
        staircases.add(int(steps["index"][k]), t, int(steps["activity"][k]),
                       float(steps["vertical_displacement"][k]))
        records.append(StepRecord(
            index=int(steps["index"][k]), t=t, t_confirm=(int(stamp) - start_ns) * 1e-9,
            length=float(steps["length"][k]),
            vertical_displacement=float(steps["vertical_displacement"][k]),
            heading=float(steps["heading"][k]), pitch_max=float(steps["pitch_max"][k]),
            pitch_min=float(steps["pitch_min"][k]), duration=float(steps["duration"][k]),
            activity=int(steps["activity"][k]), position=position,
            covariance=poses["pose.covariance"][i].reshape(6, 6)[:3, :3],
            floor=staircases.floor(position[2]), vertical_force_range=float("nan")))
    return RunOutput(records, steps.stamp_ns, staircases, int(record["footfalls"]), start_ns,
                     int(record["end_ns"]), int(record["input_first_ns"]))


@dataclass
class TruthBag:
    """A bag's truth on the run's clock: ground_truth/step and ground_truth/pose (each
    None when the bag has none), the simulated floors, and the shift applied [ns]."""

    steps: MessageBatch | None
    pose: MessageBatch | None
    floors: tuple[int, int] | None
    offset_ns: int


def read_truth_bag(path: Path, run: RunOutput, *, strict: bool = False) -> TruthBag:
    """``path``'s truth topics, their stamps moved onto the run's clock (module
    docstring); InputError when it has neither."""
    from pdr_core.io.bag import BagReader

    reader = BagReader(path, strict=strict)
    wanted = [t for t in (topics.GROUND_TRUTH_STEP, topics.GROUND_TRUTH_POSE)
              if t in reader.topics]
    if not wanted:
        have = ", ".join(sorted(reader.topics)) or "none"
        raise InputError(path, f"no topic {topics.GROUND_TRUTH_STEP} or "
                               f"{topics.GROUND_TRUTH_POSE} to evaluate against (the bag "
                               f"has: {have})")
    offset = 0
    if topics.IMU_DATA in reader.topics:
        imu = reader.read(topics.IMU_DATA)
        if len(imu):
            offset = int(imu.stamp_ns[0]) - run.input_first_ns
    batches = {t: dataclasses.replace(b, stamp_ns=b.stamp_ns - offset)
               for t, b in reader.read_batches(wanted).items()}
    for topic, batch in batches.items():
        if len(batch) == 0:
            raise InputError(path, f"{topic} has no messages")
    return TruthBag(batches.get(topics.GROUND_TRUTH_STEP), batches.get(topics.GROUND_TRUTH_POSE),
                    true_floors(reader.custom_data("pdr.simulation") or {}), offset)


@dataclass(frozen=True)
class TruthStepsFormat:
    """How to read ``--truth-steps``, a CSV with or without a header row. Columns are
    header names or 0-based indices (as str).

    Attributes:
        format: ``times``, one true time a row (a footfall, or a gait cycle: ``per`` of
            :func:`evaluate`); or ``foot-switch``, a foot switch's log with the columns
            time, left and right (contact 0 or 1), each 0→1 edge of either a footfall.
        time: the axis of the times: ``from-start``, from the input's first ``imu/data``
            message; ``stamps``, on the input bag's message stamps, where ``pdr-sim
            import-csv`` puts a CSV log's time column (plus its ``--time-offset-s``).
        unit: of the time column: s, ms, us or ns (pdr_core.units.TIME_UNITS_S).
        cols: the columns of :data:`TRUTH_STEPS_COLUMNS` (the time, and for
            ``foot-switch`` the left and right switches); () for the first ones in order.
    """

    format: str = "times"
    time: str = "from-start"
    unit: str = "s"
    cols: tuple[str, ...] = ()


def _checked(fmt: TruthStepsFormat) -> tuple[str, ...]:
    """The columns ``fmt`` reads; InputError naming the option of a value it cannot take."""
    for option, value, choices in (("--truth-steps-format", fmt.format, TRUTH_STEPS_FORMATS),
                                   ("--truth-steps-time", fmt.time, TRUTH_STEPS_TIMES),
                                   ("--truth-steps-unit", fmt.unit, tuple(TIME_UNITS_S))):
        if value not in choices:
            raise InputError(option, f"one of {', '.join(choices)}, got {value!r}")
    wanted = TRUTH_STEPS_COLUMNS[fmt.format]
    cols = fmt.cols or tuple(str(i) for i in range(len(wanted)))
    if len(cols) != len(wanted):
        raise InputError("--truth-steps-cols", f"--truth-steps-format {fmt.format} reads "
                                               f"{len(wanted)} column(s) ({','.join(wanted)}),"
                                               f" got {','.join(cols)}")
    return cols


def read_truth_steps(path: Path, fmt: TruthStepsFormat = TruthStepsFormat()) -> np.ndarray:
    """The true times [s] of ``path`` on ``fmt.time``'s axis (:class:`TruthStepsFormat`),
    (N,): each row's, or each 0→1 edge's of a foot switch (in the order of the rows, the
    left's before the right's in a row; a foot down in the first row is no footfall, its
    edge came before). InputError for a time that is not a number, a switch that reads
    other than 0 or 1, or a foot switch without a footfall."""
    from pdr_core.io.csv_table import read_columns

    cols = _checked(fmt)
    try:
        table, first_row = read_columns(path, cols, header=False), 1
    except InputError:
        table, first_row = read_columns(path, cols, header=True), 2
    times = table[:, 0] * TIME_UNITS_S[fmt.unit]
    if not np.isfinite(times).all():
        row = int(np.flatnonzero(~np.isfinite(times))[0])
        raise InputError(path, f"row {row + first_row}: step time {table[row, 0]} is not a "
                               "number")
    if fmt.format == "times":
        return times
    switches = table[:, 1:]
    bad = ~np.isin(switches, (0.0, 1.0))
    if bad.any():
        row, col = (int(i[0]) for i in np.nonzero(bad))
        raise InputError(path, f"row {row + first_row}: foot switch column {cols[1 + col]} "
                               f"reads {switches[row, col]:g}, not 0 or 1 (contact): check "
                               "--truth-steps-cols (time,left,right)")
    rows, _ = np.nonzero(np.diff(switches, axis=0) > 0)
    if not len(rows):
        raise InputError(path, f"no footfall: no 0→1 edge in the foot switch columns "
                               f"{cols[1]}, {cols[2]}")
    return times[rows + 1]


def recording_span_s(run: RunOutput, time: str) -> tuple[float, float]:
    """The input's first and last ``imu/data`` message [s] on the axis ``time`` of
    :data:`TRUTH_STEPS_TIMES`: from the first (0 to the duration), or as stamped."""
    if time == "stamps":
        return run.input_first_ns * 1e-9, run.end_ns * 1e-9
    return 0.0, (run.end_ns - run.input_first_ns) * 1e-9


def step_count_report(path: Path, times: np.ndarray, per: str, run: RunOutput) -> dict:
    """The rows of ``path`` (one per footfall of either foot, or per gait cycle of the
    sensor leg) against what the run counted: its footfalls, or its steps."""
    counted = run.footfalls if per == "footfall" else len(run.steps)
    return {"file": str(path), "per": per, "rows": len(times), "counted": counted,
            "error": counted - len(times),
            "error_pct": 100.0 * (counted - len(times)) / len(times)}


def _within(times: np.ndarray, span: tuple[float, float]) -> bool:
    return bool(times.min() >= span[0] - TIME_SPAN_MARGIN_S
                and times.max() <= span[1] + TIME_SPAN_MARGIN_S)


def step_times_warning(path: Path, times: np.ndarray, run: RunOutput,
                       fmt: TruthStepsFormat = TruthStepsFormat()) -> str | None:
    """A warning when the true ``times`` [s], on ``fmt.time``'s axis, lie outside the run's
    samples (another unit or another time axis; it names the options under which they
    would fit, if any), None otherwise."""
    span = recording_span_s(run, fmt.time)
    if _within(times, span):
        return None
    read = times / TIME_UNITS_S[fmt.unit]
    fits = [f"--truth-steps-time {time} --truth-steps-unit {unit}"
            for time in TRUTH_STEPS_TIMES for unit in TIME_UNITS_S
            if _within(read * TIME_UNITS_S[unit], recording_span_s(run, time))]
    axis = "its stamps" if fmt.time == "stamps" else "from its first imu/data message"
    fit = f"they fit with {fits[0]}; " if fits else ""
    return (f"{path}: the step times span {times.min():.3f}-{times.max():.3f} s, the "
            f"recording {span[0]:.3f}-{span[1]:.3f} s ({axis}): in another unit, or on "
            f"another time axis? ({fit}only their count is compared)")


def known_distance_report(step_distance_m: float, distance_m: float) -> dict:
    """The distance walked (the sum of the strides) against a known one [m]."""
    return {"known_distance_m": distance_m,
            "known_distance_error_m": step_distance_m - distance_m,
            "known_distance_error_pct": 100.0 * (step_distance_m - distance_m) / distance_m}


def evaluate(run_out: Path, truth: Path | None = None, truth_steps: Path | None = None,
             steps_per: str = "footfall", distance_m: float | None = None, *,
             steps_format: TruthStepsFormat = TruthStepsFormat(),
             strict: bool = False) -> dict:
    """The report of ``run_out`` against what is given (module docstring); ``truth_steps``
    read as ``steps_format`` says."""
    from pdr_core.evaluation.metrics import truth_at

    if truth is None and truth_steps is None and distance_m is None:
        raise InputError(run_out, "nothing to evaluate against: give --truth BAG, "
                                  "--truth-steps CSV or --distance-m D")
    if distance_m is not None and not (np.isfinite(distance_m) and distance_m > 0):
        raise InputError("--distance-m", f"a walked distance in metres, > 0, got {distance_m}")
    if steps_per not in STEPS_PER:
        raise InputError("--truth-steps-per", f"one of {', '.join(STEPS_PER)}, got "
                                              f"{steps_per!r}")
    if steps_format.format == "foot-switch" and steps_per != "footfall":
        raise InputError("--truth-steps-per", "a foot switch gives footfalls of either foot: "
                                              "footfall, not cycle")
    run = read_run(run_out, strict=strict)
    times = None if truth_steps is None else read_truth_steps(truth_steps, steps_format)
    bag = None if truth is None else read_truth_bag(truth, run, strict=strict)
    truth_positions = None
    if bag is not None and bag.pose is not None:
        truth_positions = truth_at(bag.pose, np.r_[run.start_ns, run.stamps])
    report = {"run": str(run_out)} | navigation_report(
        run.steps, run.staircases, None if bag is None else bag.steps, truth_positions,
        run.start_ns, None if bag is None else bag.floors, run.footfalls)
    warnings = []
    if bag is not None:
        report |= {"truth_bag": str(truth), "truth_time_offset_s": bag.offset_ns * 1e-9}
    if times is not None:
        report["truth_steps"] = step_count_report(truth_steps, times, steps_per, run)
        warnings.append(step_times_warning(truth_steps, times, run, steps_format))
    if distance_m is not None:
        report |= known_distance_report(report["step_distance_m"], distance_m)
    report["warnings"] = [w for w in warnings if w is not None]
    return report
