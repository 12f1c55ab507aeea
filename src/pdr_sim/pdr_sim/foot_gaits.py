"""Foot gaits beyond level walking, with a stance that is not a perfectly still foot.

The segment types ``walk``, ``run``, ``stairs`` (up or down), ``in_place``,
``side_steps`` (left or right), ``back_steps`` and ``crawl`` of a foot scenario
(:mod:`pdr_sim.scenario`) are built here as :mod:`pdr_sim.foot_pieces`: each stride is

1. a *loading* roll about the first contact, from the landing pitch θ_L to the stance
   pitch θ_S: about the heel (θ_L < 0, toes up: a heel strike), or about the ball of the
   foot (θ_L ≥ 0, a toe-first landing), starting with the landing impact;
2. a *foot flat* for ``flat_s`` seconds at θ_S (0: none): still, unless the foot everts;
3. a *push-off* roll from θ_S to the toe-off pitch θ_T: about the ball (θ_T ≥ 0,
   heel-off, the sensor on the instep moving with ω × r while the toes are still) or
   about the heel (θ_T < 0, rolling back on the heel when stepping backwards);
4. a *swing* to the next contact: a quintic Hermite path of the sensor between the
   toe-off and the landing states, lifted by ``clearance_m`` at mid-swing. With
   ``swing_sway_deg`` the foot also turns through the swing as a leg lifted high does
   (the hip and knee rotating it): its roll rises to that angle and back (64·x³(1 − x)³)
   while its yaw swings to ± half of it and back (:data:`SWAY`), x = τ/T, so that the
   foot never moves without turning, as the real slow
   swings of the pyshoe trial that climbs do (docs/foot_ins.md, "The foot on real
   stairs"); 0 for every built-in gait.

Through the stance the foot also rolls about its long axis (the line through heel and
ball, so a change of pivot keeps velocity and acceleration continuous): inverted by
``eversion_deg``/2 at contact and toe-off, everted as much at mid-stance, as the rearfoot
does (``φ = e/2·cos(2πτ/S)``, S the stance time, also through the foot flat). With
eversion, or without a foot flat, the foot never has a zero velocity in stance.

The stance and cadence figures each gait's defaults are based on, and the assumptions
where the literature gives none, are in :data:`GAITS` and docs/simulator.md. Rates at
the knots: the landing pitch rate is 0 (or, for a stance rolling about one contact
without a foot flat whose θ_S lies between θ_L and θ_T, the mean rate (θ_T − θ_L)/S,
which it keeps through θ_S); θ̇ = θ̈ = 0 at θ_S otherwise, where a change of pivot
happens; the toe-off rate is 2·(θ_T − θ_S)/t_push, continued into the swing. The last
stance of a segment ends at rest once its impact is over.

A gait segment starts and ends with the foot at rest in the standing pose. With a stance
pitch θ_S ≠ 0 (a tilted stance on a stair, the toes tucked under in a crawl), the foot
first rolls about the ball into it over ``settle_s`` (kneeling down, for the crawl) and
back at the end.

Foot geometry (an adult foot of 0.26 m in a shoe, the sensor on the instep, 0.13 m from
the back of the heel and 0.07 m above the sole; an assumption): lever from the heel
contact to the sensor (0.10, 0, 0.07) m, from the ball (metatarsal heads, 0.19 m from
the heel) (−0.07, 0, 0.07) m, body frame FLU.
"""
from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from pdr_sim.foot_pieces import BUMP, ROLL, SWING, Pieces, PieceState, evaluate, quintic
from pdr_sim.step_pattern import Channel

GAIT_TYPES = ("walk", "run", "stairs", "in_place", "side_steps", "back_steps", "crawl")
HEEL_TO_SENSOR_M = np.array([0.10, 0.0, 0.07])
BALL_TO_SENSOR_M = np.array([-0.07, 0.0, 0.07])
UP = np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class GaitSpec:
    """One stride of a gait. Lengths [m], times [s], angles [°] (pitch + toes down,
    relative to the standing pose), impact velocity [m/s] and rate [rad/s]."""

    stride_m: float             # travel per stride (stairs: 2·tread_m, derived)
    cycle_s: float              # stride period (1/cadence)
    stance_fraction: float      # contact time / cycle
    clearance_m: float          # swing lift above the chord from lift-off to landing
    landing_pitch_deg: float    # θ_L at first contact (< 0: heel first, else the ball)
    stance_pitch_deg: float     # θ_S (0: foot flat)
    toe_off_pitch_deg: float    # θ_T at lift-off (≥ 0: over the ball, else the heel)
    loading_s: float            # duration of the loading roll
    flat_s: float               # foot flat at θ_S (still unless eversion_deg > 0)
    eversion_deg: float         # roll range about the long axis in stance
    impact_mps: float           # velocity absorbed at landing (downwards)
    impact_radps: float         # pitch-rate step at landing (its sign: towards θ_S)
    impact_hz: float            # ringing frequency of the impact
    impact_s: float             # the impact is over (exactly at rest) after this
    cycle_variation: float = 0.02   # stride-time coefficient of variation (in the swing)
    settle_s: float = 0.0       # roll between standing and a stance pitch θ_S ≠ 0
    riser_m: float = 0.0        # stairs: riser height (a stride climbs two)
    tread_m: float = 0.0        # stairs: tread depth
    swing_sway_deg: float = 0.0     # roll (and half as much yaw) the foot turns in swing


# Defaults per gait; the sources are in docs/simulator.md ("Foot gaits").
GAITS = {
    # Level walking (Perry 1992): stance 0.60 of a 1.1 s cycle; heel strike with the toes
    # ~20° up, foot flat from ~10 % to ~30 % of the cycle (still 0.2 s), heel rise to
    # toe-off at ~60 %; impact of ~3 g (Lafortune 1991, tibia 2.7–3.7 g walking).
    "walk": GaitSpec(stride_m=1.3, cycle_s=1.1, stance_fraction=0.6, clearance_m=0.12,
                     landing_pitch_deg=-20.0, stance_pitch_deg=0.0, toe_off_pitch_deg=45.0,
                     loading_s=0.10, flat_s=0.20, eversion_deg=0.0, impact_mps=0.3,
                     impact_radps=0.5, impact_hz=15.0, impact_s=0.10),
    # Running at 3 m/s (Novacheck 1998: stance 0.31–0.39 of the cycle; 85 strides/min,
    # Lieberman et al. 2015), rearfoot strike (Kasmer et al. 2013), a foot flat of 0.07 s
    # that keeps everting: no still instant (the pyshoe running trials never go below
    # 10–30 °/s), impact ~10 g (Lafortune 1991); impacts ring at 15 Hz (all gaits).
    "run": GaitSpec(stride_m=2.1, cycle_s=0.70, stance_fraction=0.38, clearance_m=0.25,
                    landing_pitch_deg=-12.0, stance_pitch_deg=0.0, toe_off_pitch_deg=60.0,
                    loading_s=0.04, flat_s=0.07, eversion_deg=3.0, impact_mps=0.9,
                    impact_radps=2.0, impact_hz=15.0, impact_s=0.10),
    # Stairs at 30° (17/29 cm, Riener et al. 2002): forefoot first in both directions,
    # 0.8 Hz (Muñoz Díaz 2016), stance 0.66 up and 0.60–0.70 down (McFadyen & Winter
    # 1988, Beaulieu et al. 2008); the heel over the nosing, the foot balanced on the ball.
    "stairs_up": GaitSpec(stride_m=0.58, cycle_s=1.25, stance_fraction=0.66,
                          clearance_m=0.05, landing_pitch_deg=12.0, stance_pitch_deg=4.0,
                          toe_off_pitch_deg=35.0, loading_s=0.15, flat_s=0.0,
                          eversion_deg=6.0, impact_mps=0.2, impact_radps=0.5,
                          impact_hz=15.0, impact_s=0.10, settle_s=0.3, riser_m=0.17,
                          tread_m=0.29),
    "stairs_down": GaitSpec(stride_m=0.58, cycle_s=1.25, stance_fraction=0.64,
                            clearance_m=0.04, landing_pitch_deg=22.0, stance_pitch_deg=6.0,
                            toe_off_pitch_deg=30.0, loading_s=0.20, flat_s=0.0,
                            eversion_deg=6.0, impact_mps=0.3, impact_radps=0.8,
                            impact_hz=15.0, impact_s=0.10, settle_s=0.3, riser_m=0.17,
                            tread_m=0.29),
    # Stepping in place on the balls of the feet (an assumption: 1 Hz, stance 0.6, lift
    # 0.12 m; toe-first landing, the heel lowered but not to rest).
    "in_place": GaitSpec(stride_m=0.0, cycle_s=1.0, stance_fraction=0.6, clearance_m=0.12,
                         landing_pitch_deg=15.0, stance_pitch_deg=3.0, toe_off_pitch_deg=25.0,
                         loading_s=0.15, flat_s=0.0, eversion_deg=4.0, impact_mps=0.25,
                         impact_radps=0.5, impact_hz=15.0, impact_s=0.10, settle_s=0.3),
    # Side steps (an assumption: 0.4 m, 1.2 s, stance 0.62, a flat foot set down on its ball).
    "side_steps": GaitSpec(stride_m=0.4, cycle_s=1.2, stance_fraction=0.62,
                           clearance_m=0.06, landing_pitch_deg=5.0, stance_pitch_deg=0.0,
                           toe_off_pitch_deg=15.0, loading_s=0.10, flat_s=0.25,
                           eversion_deg=0.0, impact_mps=0.2, impact_radps=0.3,
                           impact_hz=15.0, impact_s=0.10),
    # Backward walking: the forward gait reversed in time (Lee et al. 2013), shorter
    # strides and swing at the same cadence (Laufer 2005): ball first, off over the heel.
    "back_steps": GaitSpec(stride_m=0.8, cycle_s=1.1, stance_fraction=0.66,
                           clearance_m=0.08, landing_pitch_deg=15.0, stance_pitch_deg=0.0,
                           toe_off_pitch_deg=-15.0, loading_s=0.12, flat_s=0.20,
                           eversion_deg=0.0, impact_mps=0.2, impact_radps=0.5,
                           impact_hz=15.0, impact_s=0.10),
    # Crawling on hands and knees (Patrick et al. 2009: the stance lengthens at low
    # speed, the swing stays ~0.5 s; an assumption: 0.45 m per 1.5 s, stance 0.7), knee
    # and toes on the floor, the toes tucked under (foot pitched 65°), the foot turning
    # slowly about the toes through the stance while the shin lies still.
    "crawl": GaitSpec(stride_m=0.45, cycle_s=1.5, stance_fraction=0.7, clearance_m=0.04,
                      landing_pitch_deg=72.0, stance_pitch_deg=65.0, toe_off_pitch_deg=56.0,
                      loading_s=0.45, flat_s=0.0, eversion_deg=0.0, impact_mps=0.1,
                      impact_radps=0.3, impact_hz=15.0, impact_s=0.10, settle_s=1.5),
}
GAIT_KEYS = tuple(f.name for f in fields(GaitSpec))
STAIRS_ONLY = ("riser_m", "tread_m")


def gait_defaults(segment_type: str, direction: str) -> GaitSpec:
    """The default stride of a gait segment (stairs by direction)."""
    return GAITS[f"stairs_{direction}" if segment_type == "stairs" else segment_type]


def gait_keys(segment_type: str) -> tuple[str, ...]:
    """The keys a segment's ``gait:`` mapping may set."""
    if segment_type == "stairs":
        return tuple(k for k in GAIT_KEYS if k != "stride_m")
    return tuple(k for k in GAIT_KEYS if k not in STAIRS_ONLY
                 and not (segment_type == "in_place" and k == "stride_m"))


def stride_vector(segment_type: str, direction: str, spec: GaitSpec, yaw: float) -> np.ndarray:
    """Displacement of the foot per stride, ENU [m]."""
    forward = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    left = np.array([-np.sin(yaw), np.cos(yaw), 0.0])
    if segment_type == "stairs":
        rise = 2 * spec.riser_m * (1 if direction == "up" else -1)
        return 2 * spec.tread_m * forward + rise * UP
    if segment_type == "back_steps":
        return -spec.stride_m * forward
    if segment_type == "side_steps":
        return spec.stride_m * (left if direction == "left" else -left)
    return spec.stride_m * forward


def stance_timing(spec: GaitSpec) -> tuple[float, float]:
    """Stance time S and push-off time [s] of a stride."""
    stance = spec.stance_fraction * spec.cycle_s
    return stance, stance - spec.loading_s - spec.flat_s


@dataclass
class PieceRow:
    """One piece as built: start [s], duration [s], kind, Euler polynomial (3, 7),
    position polynomial (3, 7), lever (3,)."""

    start: float
    duration: float
    kind: int
    euler: np.ndarray
    position: np.ndarray
    lever: np.ndarray

    def state(self, tau: float) -> PieceState:
        pieces = Pieces(np.array([self.kind]), self.euler[None], self.position[None],
                        self.lever[None])
        return evaluate(pieces, np.array([0]), np.array([float(tau)]),
                        np.array([self.duration]))


def _channel3(value, rate=(0.0, 0.0, 0.0), acc=(0.0, 0.0, 0.0)) -> Channel:
    return Channel(np.asarray(value, float), np.asarray(rate, float), np.asarray(acc, float))


def _roll(start: float, duration: float, pivot: np.ndarray, lever: np.ndarray,
          euler0: Channel, euler1: Channel) -> PieceRow:
    position = np.zeros((3, 7))
    position[:, 0] = pivot
    return PieceRow(start, duration, ROLL, quintic(euler0, euler1, duration), position,
                    lever)


# x²(1 − x)²(2x − 1)·25√5/2: 0 with its slope at both ends, ±1/2 at x = 1/2 ∓ 1/√20
SWAY = 12.5 * np.sqrt(5.0) * np.array([0.0, 0.0, -1.0, 4.0, -5.0, 2.0, 0.0])


def _swing(start: float, duration: float, leave: PieceState, land: PieceState,
           clearance_m: float, sway_rad: float = 0.0) -> PieceRow:
    def one(channel: Channel) -> Channel:
        return Channel(channel.f[0], channel.d1[0], channel.d2[0])

    position = quintic(one(leave.position), one(land.position), duration)
    position[2] += clearance_m * BUMP
    euler = quintic(one(leave.euler), one(land.euler), duration)
    euler[0] += sway_rad * BUMP
    euler[2] += sway_rad * SWAY
    return PieceRow(start, duration, SWING, euler, position, np.zeros(3))


@dataclass
class GaitSegment:
    """The pieces and landing impacts of one gait segment, and where it ends."""

    pieces: list[PieceRow]
    impacts: list[tuple]
    end_time: float
    end_position: np.ndarray


def _eversion(spec: GaitSpec, tau: float, stance: float) -> tuple[float, float, float]:
    """φ, φ̇, φ̈ of the eversion profile e/2·cos(2πτ/S) [rad, rad/s, rad/s²]."""
    half, k = np.radians(spec.eversion_deg) / 2, 2 * np.pi / stance
    return half * np.cos(k * tau), -half * k * np.sin(k * tau), -half * k**2 * np.cos(k * tau)


def gait_segment(segment_type: str, direction: str, steps: int, spec: GaitSpec,
                 start_time: float, position: np.ndarray, yaw: float,
                 base_roll: float, base_pitch: float, rng: np.random.Generator) -> GaitSegment:
    """Build a gait segment of ``steps`` strides from rest at ``position`` (the sensor,
    ENU [m]) with heading ``yaw`` and the standing attitude (``base_roll``,
    ``base_pitch``) [rad] (a short loop over strides, not samples). Each stride's swing
    is drawn from ``rng`` so that the stride time scatters by ``cycle_variation`` (the
    landings then fall anywhere between two samples, as they do on a real sensor)."""
    stance, push = stance_timing(spec)
    swings = spec.cycle_s - stance + spec.cycle_variation * spec.cycle_s * \
        rng.standard_normal(steps)
    theta_l, theta_s, theta_t = (base_pitch + np.radians(a) for a in (
        spec.landing_pitch_deg, spec.stance_pitch_deg, spec.toe_off_pitch_deg))
    step = stride_vector(segment_type, direction, spec, yaw)

    def euler(pitch: float, pitch_rate: float = 0.0, tau: float | None = None) -> Channel:
        """Euler angles, rates and second derivatives with the pitch θ, θ̇ (θ̈ = 0) and
        the eversion profile at ``tau`` into the stance (None: φ at rest, 0)."""
        phi = (0.0, 0.0, 0.0) if tau is None else _eversion(spec, tau, stance)
        return _channel3((base_roll + phi[0], pitch, yaw), (phi[1], pitch_rate, 0.0),
                         (phi[2], 0.0, 0.0))

    tilt = rotation_matrix(base_roll, theta_s, yaw)
    ball0 = np.asarray(position, float) - rotation_matrix(base_roll, base_pitch, yaw) @ \
        BALL_TO_SENSOR_M

    def contacts(k: int) -> tuple[np.ndarray, np.ndarray]:
        """Heel and ball contact points of stance k (0: the start): the ball k strides on,
        the heel where it is with the foot at (θ_S, φ = 0) about the ball."""
        ball = ball0 + k * step
        return ball + tilt @ (BALL_TO_SENSOR_M - HEEL_TO_SENSOR_M), ball

    levers = (HEEL_TO_SENSOR_M, BALL_TO_SENSOR_M)
    loading_pivot = 0 if spec.landing_pitch_deg < 0 else 1     # 0: heel, 1: ball
    push_pivot = 0 if spec.toe_off_pitch_deg < 0 else 1
    through = (spec.flat_s == 0 and loading_pivot == push_pivot
               and min(theta_l, theta_t) < theta_s < max(theta_l, theta_t))
    mid_rate = (theta_t - theta_l) / stance if through else 0.0
    theta_rate_t = 2 * (theta_t - theta_s) / push
    flat_end = spec.loading_s + spec.flat_s
    slap = np.sign(theta_s - theta_l) * spec.impact_radps

    pieces: list[PieceRow] = []
    impacts: list[tuple] = []
    t = start_time
    heel, ball = contacts(0)
    if theta_s != base_pitch:
        pieces.append(_roll(t, spec.settle_s, ball, BALL_TO_SENSOR_M, euler(base_pitch),
                            euler(theta_s)))
        t += spec.settle_s
    toe_off = euler(theta_t, theta_rate_t, stance)
    pieces.append(_roll(t, push, (heel, ball)[push_pivot], levers[push_pivot],
                        euler(theta_s), toe_off))
    t += push
    for k in range(1, steps + 1):
        heel, ball = contacts(k)
        last = k == steps
        knot = euler(theta_s) if last else euler(theta_s, mid_rate, spec.loading_s)
        t_land = t + swings[k - 1]
        loading = _roll(t_land, spec.loading_s, (heel, ball)[loading_pivot],
                        levers[loading_pivot], euler(theta_l, mid_rate, 0.0), knot)
        leave, land = pieces[-1].state(pieces[-1].duration), loading.state(0.0)
        impact_v = -spec.impact_mps * UP
        impact_w = np.array([0.0, slap, 0.0])
        land = PieceState(Channel(land.position.f, land.position.d1 + impact_v,
                                  land.position.d2),
                          Channel(land.euler.f, land.euler.d1 + impact_w, land.euler.d2))
        pieces.append(_swing(t, swings[k - 1], leave, land, spec.clearance_m,
                             np.radians(spec.swing_sway_deg)))
        pieces.append(loading)
        impacts.append((t_land, impact_v, impact_w, spec.impact_hz, spec.impact_s))
        t = t_land + spec.loading_s
        if last:
            if spec.impact_s > spec.loading_s:      # at rest once the impact is over
                pieces.append(_roll(t, spec.impact_s - spec.loading_s,
                                    (heel, ball)[push_pivot], levers[push_pivot], knot, knot))
                t += spec.impact_s - spec.loading_s
            break
        if spec.flat_s > 0:
            flat = euler(theta_s, 0.0, flat_end)
            pieces.append(_roll(t, spec.flat_s, (heel, ball)[push_pivot], levers[push_pivot],
                                knot, flat))
            knot = flat
            t += spec.flat_s
        pieces.append(_roll(t, push, (heel, ball)[push_pivot], levers[push_pivot], knot,
                            toe_off))
        t += push
    if theta_s != base_pitch:
        pieces.append(_roll(t, spec.settle_s, ball, BALL_TO_SENSOR_M, euler(theta_s),
                            euler(base_pitch)))
        t += spec.settle_s
    end = pieces[-1].state(pieces[-1].duration).position.f[0]
    return GaitSegment(pieces, impacts, t, end)


def rotation_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """C_b^n = Rz(ψ)·Ry(θ)·Rx(φ) (3, 3) of one attitude [rad]."""
    cr, sr, cp, sp, cy, sy = (np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch),
                              np.cos(yaw), np.sin(yaw))
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    return rz @ ry @ rx


def with_overrides(spec: GaitSpec, values: dict) -> GaitSpec:
    """``spec`` with the validated keys of a segment's ``gait:`` mapping."""
    spec = replace(spec, **values)
    if "tread_m" in values:
        spec = replace(spec, stride_m=2 * spec.tread_m)
    return spec
