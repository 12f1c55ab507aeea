"""The foot's strides (pdr_ins_ekf.strides): one per footfall, whatever the blocks."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdr_core.vocabulary import Activity
from pdr_ins_ekf.strides import StrideTracker
from pdr_ins_ekf.zupt_ekf import FilterOutput


def estimates(position: np.ndarray) -> FilterOutput:
    """Filter estimates (N samples) at these positions, level and still otherwise."""
    n = len(position)
    eye = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    return FilterOutput(position, np.zeros((n, 3)), eye, np.zeros((n, 6)),
                        np.full((n, 9), 1e-4), eye * 1e-4, eye * 1e-4)


def walk(footfalls: list[tuple[float, float, float]], samples: int = 10):
    """Stamps, stance and estimates of a foot that lands at ``footfalls`` [m] in turn:
    each stride ``samples`` of swing then ``samples`` of stance at the footfall."""
    stance, position = [True] * samples, [np.zeros(3)] * samples
    for point in footfalls:
        start = position[-1]
        for k in range(samples):
            position.append(start + (np.asarray(point) - start) * (k + 1) / samples)
            stance.append(False)
        position += [np.asarray(point, float)] * samples
        stance += [True] * samples
    stamps = np.arange(len(stance), dtype=np.int64) * 10_000_000
    return stamps, np.array(stance), estimates(np.array(position, float))


def pushed(stamps, stance, output, cuts) -> list:
    tracker, strides, start = StrideTracker(), [], 0
    for stop in [*cuts, len(stamps)]:
        part = slice(start, stop)
        strides += tracker.push(stamps[part], stance[part], FilterOutput(
            *(getattr(output, f)[part] for f in FilterOutput.__dataclass_fields__)))
        start = stop
    return strides


def test_a_stride_per_footfall_with_its_length_heading_and_activity():
    footfalls = [(1.3, 0, 0), (1.3, 1.3, 0), (1.35, 1.3, 0.0), (1.3, 2.6, 0.35),
                 (1.3, 3.9, 0.0)]
    stamps, stance, output = walk(footfalls)
    strides = pushed(stamps, stance, output, [])
    # the third footfall is 5 cm from the second: no stride, the next runs from the second
    assert [s.index for s in strides] == [0, 1, 2, 3]
    np.testing.assert_allclose([s.length_m for s in strides], [1.3, 1.3, 1.3, 1.3])
    np.testing.assert_allclose(np.degrees([s.heading_rad for s in strides]), [0, 90, 90, 90],
                               atol=1e-9)
    assert [s.activity for s in strides] == [Activity.WALKING, Activity.WALKING,
                                             Activity.UPSTAIRS, Activity.DOWNSTAIRS]
    # stamped at the footfall: the first stance sample after the swing
    assert stance[np.searchsorted(stamps, strides[0].stamp_ns)]
    assert not stance[np.searchsorted(stamps, strides[0].stamp_ns) - 1]
    assert strides[0].duration_s == pytest.approx(0.2)    # from the aligned start


@settings(max_examples=30, deadline=None)
@given(st.lists(st.integers(1, 129), max_size=6, unique=True))
def test_any_blocks_give_the_same_strides(cuts):
    stamps, stance, output = walk([(1.3 * k, 0.1 * k, 0.0) for k in range(1, 7)])
    whole = pushed(stamps, stance, output, [])
    parts = pushed(stamps, stance, output, sorted(cuts))
    assert [(s.stamp_ns, s.length_m, s.heading_rad) for s in parts] == \
        [(s.stamp_ns, s.length_m, s.heading_rad) for s in whole]
