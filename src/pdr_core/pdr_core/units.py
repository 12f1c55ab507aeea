"""Unit conversions at the edges (parameters, CLI, plots). Everything inside is SI.

Noise densities: angular random walk (ARW) in °/√h and velocity random walk (VRW) in
m/s/√h or µg/√Hz are converted to continuous white-noise densities in rad/s/√Hz
(= rad/√s) and m/s²/√Hz (= m/s/√s). Rate random walk (RRW) in °/s/√h and acceleration
random walk in m/s²/√h become rad/s²/√Hz and m/s³/√Hz.

The units a CSV log's columns may be in (``pdr-sim import-csv --time-unit`` etc.), each a
name -> SI factor table: :data:`TIME_UNITS_S`, :data:`ACC_UNITS_MPS2`,
:data:`GYRO_UNITS_RADPS`, :data:`POS_UNITS_M`, :data:`MAG_UNITS_T`; :data:`UNIT_SYMBOLS`
writes a unit name as messages and --help show it.
"""
import math

from pdr_core.constants import STANDARD_GRAVITY_MPS2

DEG = math.pi / 180.0
SQRT_HOUR = 60.0

TIME_UNITS_S = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9}
ACC_UNITS_MPS2 = {"mps2": 1.0, "m/s2": 1.0, "m/s^2": 1.0, "g": STANDARD_GRAVITY_MPS2}
GYRO_UNITS_RADPS = {"radps": 1.0, "rad/s": 1.0, "degps": DEG, "deg/s": DEG}
POS_UNITS_M = {"m": 1.0, "cm": 0.01, "mm": 0.001}
MAG_UNITS_T = {"t": 1.0, "ut": 1e-6, "nt": 1e-9, "gauss": 1e-4}
UNIT_SYMBOLS = {"s": "s", "ms": "ms", "us": "µs", "ns": "ns",
                "mps2": "m/s²", "m/s2": "m/s²", "m/s^2": "m/s²", "g": "g",
                "radps": "rad/s", "rad/s": "rad/s", "degps": "deg/s", "deg/s": "deg/s",
                "m": "m", "cm": "cm", "mm": "mm",
                "t": "T", "ut": "µT", "nt": "nT", "gauss": "G"}


def arw_to_si(deg_per_sqrt_h: float) -> float:
    """ARW [°/√h] -> rate noise density [rad/s/√Hz]."""
    return deg_per_sqrt_h * DEG / SQRT_HOUR


def arw_from_si(rad_per_sqrt_s: float) -> float:
    """Rate noise density [rad/s/√Hz] -> ARW [°/√h]."""
    return rad_per_sqrt_s / DEG * SQRT_HOUR


def vrw_to_si(mps_per_sqrt_h: float) -> float:
    """VRW [m/s/√h] -> specific-force noise density [m/s²/√Hz]."""
    return mps_per_sqrt_h / SQRT_HOUR


def vrw_from_si(mps2_per_sqrt_hz: float) -> float:
    """Specific-force noise density [m/s²/√Hz] -> VRW [m/s/√h]."""
    return mps2_per_sqrt_hz * SQRT_HOUR


def ug_per_sqrt_hz_to_si(ug_per_sqrt_hz: float) -> float:
    """Accelerometer noise density [µg/√Hz] -> [m/s²/√Hz]."""
    return ug_per_sqrt_hz * 1e-6 * STANDARD_GRAVITY_MPS2


def rrw_to_si(deg_per_s_sqrt_h: float) -> float:
    """RRW [°/s/√h] -> [rad/s²/√Hz]."""
    return deg_per_s_sqrt_h * DEG / SQRT_HOUR


def deg_per_h_to_si(deg_per_h: float) -> float:
    """Gyro bias [°/h] -> [rad/s]."""
    return deg_per_h * DEG / 3600.0


def mg_to_si(mg: float) -> float:
    """Accelerometer bias [mg] -> [m/s²]."""
    return mg * 1e-3 * STANDARD_GRAVITY_MPS2
