"""What a run found without a truth, alike for both navigators (``eval.walk`` of a
report, the summary's columns): steps (gait cycles of the sensor leg), footfalls of both
feet, the distance walked [m] (the sum of the strides), the final floor, the placement and
the barometer's use.

- ``pdr-pocket run``: its report's ``steps``, ``footfalls``, ``step_distance_m``,
  ``final_floor``, ``placement.placement`` and the barometer's ``inputs.barometer.status``
  (or, from a report without it, ``barometer.fused``; ``absent`` without a barometer);
- ``pdr-ekf run``: its output bag's ``pdr/foot/step`` (a stride each: two footfalls),
  their lengths summed, the floor of the last stride's height (round(z /
  pdr_core.vocabulary.FLOOR_HEIGHT_M)), the placement ``foot`` and the barometer ``not
  used`` (the foot filter has none).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from pdr_core import topics
from pdr_core.io.bag import BagReader
from pdr_core.vocabulary import FLOOR_HEIGHT_M


def barometer_use(report: dict) -> str:
    """``fused``, ``not fused`` or ``absent``: what the pocket navigator did with a
    barometer."""
    status = report.get("inputs", {}).get("barometer", {}).get("status")
    if status is not None:
        return status
    if "barometer" not in report:
        return "absent"
    return "fused" if report["barometer"].get("fused") else "not fused"


def pocket_walk(report: dict) -> dict:
    """The figures of a ``pdr-pocket run`` report (see the module)."""
    return {"steps": report.get("steps"), "footfalls": report.get("footfalls"),
            "distance_m": report.get("step_distance_m"),
            "final_floor": report.get("final_floor"),
            "placement": report.get("placement", {}).get("placement"),
            "barometer": barometer_use(report)}


def foot_walk(run_out: Path) -> dict:
    """The figures of a ``pdr-ekf run`` output bag (see the module)."""
    reader = BagReader(run_out)
    strides = reader.read_batches([topics.FOOT_STEP, topics.FOOT_STEP_POSE]) \
        if topics.FOOT_STEP in reader.topics else {}
    if not strides or not len(strides[topics.FOOT_STEP].stamp_ns):
        return {"steps": 0, "footfalls": 0, "distance_m": 0.0, "final_floor": 0,
                "placement": "foot", "barometer": "not used"}
    height = strides[topics.FOOT_STEP_POSE]["pose.pose.position"].reshape(-1, 3)[-1, 2]
    steps = len(strides[topics.FOOT_STEP].stamp_ns)
    return {"steps": steps, "footfalls": 2 * steps,
            "distance_m": float(np.sum(strides[topics.FOOT_STEP]["length"])),
            "final_floor": round(float(height) / FLOOR_HEIGHT_M),
            "placement": "foot", "barometer": "not used"}
