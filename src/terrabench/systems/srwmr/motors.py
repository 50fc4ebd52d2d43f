"""Electrical power of the HIT-MRII actuators: DC-motor + gearhead model (issue 27, piece 4).

The trial's energy so far is the mechanical ``sum |tau omega|`` over the actuators; the paper
measures electrical power. This module turns a joint torque and speed into the power drawn at the
motor terminals, per actuator, vectorised over any array shape:

* gear (ratio ``N``, efficiency ``eta``) applied in the direction of power flow: motoring (the
  motor drives the load, ``tau omega > 0``) or holding (``omega = 0``) the motor supplies
  ``tau / (N eta)``; back-driven (``tau omega < 0``, the load drives the motor) it sees
  ``tau eta / N``;
* motor current ``I = tau_m / k_M + I_0 sign(omega_m)``: ``I_0`` (no-load current) is the
  friction and iron-loss torque ``k_M I_0`` expressed as current, acting against the motion, so it
  vanishes at standstill (a loaded joint held still costs ``I^2 R`` only; zero torque and zero
  speed cost nothing);
* terminal voltage ``U = R I + k_E omega_m`` with ``k_E = k_M`` (SI) and ``omega_m = N omega``;
  input power ``P_in = U I``;
* no regeneration by default (``regen=False``): power a back-driven motor generates is not
  recovered, ``P_in`` is clipped at 0. Assumption: a standard H-bridge driver without an energy
  recovering supply (the paper does not say; its "12 brushed DC motors" carry FAULHABER's product
  code letter ``B``, which FAULHABER's catalogue defines as "Type of commutation (brushless)"; a
  block-commutated brushless motor obeys the same DC-equivalent equations with the phase-phase
  terminal resistance).

Only the motor constant ``k_M / sqrt(R)`` and the friction torque ``k_M I_0`` enter ``P_in`` (the
winding, i.e. ``k_M`` for a given frame, cancels): ``P_in = tau omega / eta^{+-1} + k_M I_0
|omega_m| + R I^2``.

Motor values: the seed names the motors (FAULHABER 3056K024B-K1838 in the wheels, 4490K024B-K1155
at the rocker hinges) but no data sheet of either series is in the stored reference corpora, so
both are scaled (:func:`scaled_motor`) from the one data sheet of the family that is: series
3564 ... B, 3564 K 024 B (same maker, same 24 V winding code, same gearheads 38/1, 38/2 and the
seed's IE3-1024(L) encoder listed for it). Gear ratios and efficiencies: the seed gives none; they
are ours, sized so that the seed's wheel loads and speeds lie inside the motor+gear continuous
rating (:data:`WHEEL_DESIGN`, :data:`HINGE_DESIGN`, tested). Every value and its source:
``docs/assumptions-srwmr.md``, section "Electrical energy (motors.py)".
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

RPM = 2.0 * math.pi / 60.0  # rad/s per rpm


@dataclass(frozen=True)
class MotorSpec:
    """One DC motor type at 22 C, SI units (data-sheet rows named as FAULHABER names them).

    ``U_N`` nominal voltage (V), ``R`` terminal resistance phase-phase (ohm), ``k_M`` torque
    constant (N m/A; ``k_E = k_M`` in V s/rad), ``I_0`` no-load current (A), ``M_cont`` the
    recommended continuous torque "Torque up to M_e max" (N m), ``omega_max`` "Speed up to
    n_e max" (rad/s), frame ``diameter`` x ``length`` (m, the product code's first four digits).
    """

    name: str
    U_N: float
    R: float
    k_M: float
    I_0: float
    M_cont: float
    omega_max: float
    diameter: float
    length: float
    source: str = ""

    def __post_init__(self) -> None:
        for f in ("U_N", "R", "k_M", "M_cont", "omega_max", "diameter", "length"):
            if not getattr(self, f) > 0.0:
                raise ValueError(f"{self.name}: {f} must be > 0, got {getattr(self, f)}")
        if self.I_0 < 0.0:
            raise ValueError(f"{self.name}: I_0 must be >= 0, got {self.I_0}")

    @property
    def k_E(self) -> float:
        """Back-EMF constant (V s/rad), equal to ``k_M`` in SI units."""
        return self.k_M

    @property
    def motor_constant(self) -> float:
        """``k_M / sqrt(R)`` (N m/sqrt(W)): torque per square root of copper loss."""
        return self.k_M / math.sqrt(self.R)

    @property
    def friction_torque(self) -> float:
        """``k_M I_0`` (N m): the no-load loss as a torque against the motion."""
        return self.k_M * self.I_0

    @property
    def omega_0(self) -> float:
        """No-load speed at ``U_N`` (rad/s): ``(U_N - R I_0) / k_E``."""
        return (self.U_N - self.R * self.I_0) / self.k_E

    @property
    def stall_torque(self) -> float:
        """Stall torque at ``U_N`` (N m): ``k_M (U_N / R - I_0)``."""
        return self.k_M * (self.U_N / self.R - self.I_0)

    @property
    def eta_max(self) -> float:
        """Maximum efficiency at ``U_N`` on the linear n-M curve: ``(1 - sqrt(I_0 R / U_N))^2``."""
        return (1.0 - math.sqrt(self.I_0 * self.R / self.U_N)) ** 2

    def speed_at(self, torque, U=None):
        """Shaft speed (rad/s) at shaft ``torque`` (N m, motoring) on the n-M line at voltage
        ``U`` (default ``U_N``): ``(U - R I) / k_E`` with ``I = torque / k_M + I_0``."""
        u = self.U_N if U is None else U
        i = np.asarray(torque, float) / self.k_M + self.I_0
        return (u - self.R * i) / self.k_E


@dataclass(frozen=True)
class ActuatorSpec:
    """A motor with its gear train: joint = ``ratio`` x slower, ``eta`` = gear efficiency."""

    name: str
    motor: MotorSpec
    ratio: float
    eta: float
    source: str = ""

    def __post_init__(self) -> None:
        if not self.ratio > 0.0:
            raise ValueError(f"{self.name}: ratio must be > 0, got {self.ratio}")
        if not 0.0 < self.eta <= 1.0:
            raise ValueError(f"{self.name}: eta must be in (0, 1], got {self.eta}")

    @property
    def continuous_torque(self) -> float:
        """Joint torque (N m) at the motor's continuous torque, motoring: ``N eta M_cont``."""
        return self.ratio * self.eta * self.motor.M_cont

    @property
    def max_speed(self) -> float:
        """Joint speed (rad/s) at the motor's ``omega_max``."""
        return self.motor.omega_max / self.ratio


def scaled_motor(ref: MotorSpec, name: str, diameter: float, length: float, source: str = "") -> MotorSpec:
    """``ref`` scaled to a ``diameter`` x ``length`` frame (m), for a motor whose data sheet is not at
    hand. Linear scale ``lam = (d^2 l / (d_ref^2 l_ref))^(1/3)`` of geometrically similar motors:

    * same winding class (``U_N``, ``k_M`` kept);
    * motor constant ``k_M/sqrt(R) ~ lam^2.5`` (torque ~ lam^3 per ampere-turn density, copper
      resistance per turn^2 ~ 1/lam): ``R = R_ref lam^-5``;
    * friction/iron-loss torque ~ rotor volume: ``I_0 = I_0,ref lam^3``;
    * continuous torque limited by heat through the surface (loss ~ lam^2):
      ``M_cont = M_cont,ref lam^3.5``;
    * maximum speed at equal rotor tip speed: ``omega_max = omega_max,ref / lam``.
    """
    lam = ((diameter**2 * length) / (ref.diameter**2 * ref.length)) ** (1.0 / 3.0)
    return MotorSpec(
        name=name,
        U_N=ref.U_N,
        R=ref.R * lam**-5,
        k_M=ref.k_M,
        I_0=ref.I_0 * lam**3,
        M_cont=ref.M_cont * lam**3.5,
        omega_max=ref.omega_max / lam,
        diameter=diameter,
        length=length,
        source=source or f"scaled from {ref.name} by lam = {lam:.4f}",
    )


#: the one FAULHABER data sheet of the family found: "Brushless DC-Servomotors 47,1 mNm ... Series
#: 3564 ... B", column 3564 K 024 B: U_N 24 V, R 1,2 ohm, n_0 11 300 rpm, I_0 0,189 A, k_M 20,12
#: mNm/A (k_E 2,107 mV/rpm), eta_max 81 %, n_e max 27 000 rpm, M_e max 44,0 mNm, I_e max 2,50 A.
FAULHABER_3564K024B = MotorSpec(
    name="FAULHABER 3564 K 024 B",
    U_N=24.0,
    R=1.2,
    k_M=20.12e-3,
    I_0=0.189,
    M_cont=44.0e-3,
    omega_max=27_000 * RPM,
    diameter=0.035,
    length=0.064,
    source="data sheet, series 3564 ... B (paperzz.com/doc/7763922)",
)

#: its data-sheet rows the model does not take as inputs (for the consistency tests)
FAULHABER_3564K024B_SHEET = {"n_0_rpm": 11_300.0, "eta_max": 0.81, "I_e_max": 2.50, "M_H": 371e-3}

#: wheel drive and steering motor (seed: "12 brushed DC motors (FAULHABER 3056K024B-K1838) in the
#: wheels"); data sheet not found: scaled from the 3564 K 024 B to the 30 x 56 mm frame
FAULHABER_3056K024B = scaled_motor(
    FAULHABER_3564K024B, "FAULHABER 3056 K 024 B (estimate)", 0.030, 0.056,
    source="our estimate: 3564 K 024 B data sheet scaled to the 30 x 56 mm frame (scaled_motor)",
)

#: rocker hinge motor (seed: "installing a motor (FAULHABER 4490K024B-K1155) ... at the hinge point
#: between the suspension and body box"); data sheet not found: scaled to the 44 x 90 mm frame
FAULHABER_4490K024B = scaled_motor(
    FAULHABER_3564K024B, "FAULHABER 4490 K 024 B (estimate)", 0.044, 0.090,
    source="our estimate: 3564 K 024 B data sheet scaled to the 44 x 90 mm frame (scaled_motor)",
)


@dataclass(frozen=True)
class DesignPoint:
    """The continuous joint torque (N m) and the largest joint speed (rad/s) an actuator must carry."""

    torque: float
    speed: float
    note: str = ""


#: wheel: nominal load 380 N [S "the average wheel load was measured to be approximately 380 N"] x
#: (traction PC 0.6 [S "the PC values for the right front and left rear wheels were approximately
#: 0.6"] + rolling resistance 0.1, ours) x r 0.15 m [S]; speed 2 x the top commanded 25 mm/s [S, T1]
#: over r (the factor 2, ours: IK corrections and slip on top of the command)
WHEEL_DESIGN = DesignPoint(380.0 * (0.6 + 0.1) * 0.150, 2.0 * 0.025 / 0.150,
                           "wheel drive: 380 N x (0.6 + 0.1) x 0.15 m; 2 x 25 mm/s / 0.15 m")

#: rocker hinge: holding the chassis at the nominal state, virtual work of the nominal wheel loads
#: (380 N [S]) over the reconstructed drop rates 0.352 m/rad (front wheel) and 0.387 m/rad (bogie
#: pivot, two wheels) per side; speed 2 x (7.2 mm/s chassis speed of our RCM cycle, 2 x the seed's
#: 3.6 mm/s) / 0.37 m/rad
HINGE_DESIGN = DesignPoint(380.0 * (0.352 + 2 * 0.387), 2.0 * 0.0072 / 0.37,
                           "rocker hinge: 380 N x (0.352 + 2 x 0.387) m/rad; 2 x 7.2 mm/s / 0.37 m/rad")

#: gear efficiency of the multi-stage reductions (ours): FAULHABER lists 70 % for a 43:1 planetary
#: (gearhead FAQ, 16/7); ratios in the thousands take more stages
GEAR_ETA = 0.60

#: wheel drive: N = 2600 (ours) gives N eta M_cont = 41.0 N m >= WHEEL_DESIGN.torque and 8,300 rpm
#: at WHEEL_DESIGN.speed (tested: within omega_max and reachable at U_N)
WHEEL_DRIVE = ActuatorSpec("wheel drive", FAULHABER_3056K024B, ratio=2600.0, eta=GEAR_ETA,
                           source="ratio, eta ours (seed silent): sized to WHEEL_DESIGN")

#: steering: same part number as the drive (12 motors of one type in the wheels) -> same gear (ours)
WHEEL_STEER = ActuatorSpec("wheel steering", FAULHABER_3056K024B, ratio=2600.0, eta=GEAR_ETA,
                           source="ratio, eta ours: the drive's (same part 3056K024B-K1838)")

#: rocker hinge: N = 7000 (ours) gives N eta M_cont = 470 N m >= HINGE_DESIGN.torque (10 % margin)
ROCKER_HINGE = ActuatorSpec("rocker hinge", FAULHABER_4490K024B, ratio=7000.0, eta=GEAR_ETA,
                            source="ratio, eta ours (seed silent): sized to HINGE_DESIGN")


def _sign_flow(tau, omega):
    """True where the joint back-drives its motor (``tau omega < 0``); standstill counts as motoring."""
    return tau * omega < 0.0


def motor_current(spec: ActuatorSpec, tau_joint, omega_joint) -> np.ndarray:
    """Motor current (A) for joint torque ``tau_joint`` (N m) and speed ``omega_joint`` (rad/s),
    broadcast: ``I = tau / (N eta^s k_M) + I_0 sign(N omega)``, ``s = +1`` motoring or holding,
    ``-1`` back-driven."""
    tau, w = np.broadcast_arrays(np.asarray(tau_joint, float), np.asarray(omega_joint, float))
    m = spec.motor
    tau_m = np.where(_sign_flow(tau, w), tau * spec.eta, tau / spec.eta) / spec.ratio
    return tau_m / m.k_M + m.I_0 * np.sign(w)


def motor_voltage(spec: ActuatorSpec, tau_joint, omega_joint) -> np.ndarray:
    """Terminal voltage (V): ``U = R I + k_E N omega``."""
    i = motor_current(spec, tau_joint, omega_joint)
    return spec.motor.R * i + spec.motor.k_E * spec.ratio * np.asarray(omega_joint, float)


def electrical_power(spec: ActuatorSpec, tau_joint, omega_joint, regen: bool = False) -> np.ndarray:
    """Electrical input power ``P_in = U I`` (W) of one actuator per element of the broadcast
    ``tau_joint`` (N m) x ``omega_joint`` (rad/s). ``regen=False`` (default): generated power is
    not recovered, ``P_in >= 0``; ``regen=True``: negative ``P_in`` is power returned to the supply.
    """
    tau, w = np.broadcast_arrays(np.asarray(tau_joint, float), np.asarray(omega_joint, float))
    i = motor_current(spec, tau, w)
    p = (spec.motor.R * i + spec.motor.k_E * spec.ratio * w) * i
    return p if regen else np.maximum(p, 0.0)


def integrate_power(t, power) -> float:
    """Trapezoid integral (J) of ``power`` (W; shape ``(T, ...)``, summed over the trailing axes)
    over the sample times ``t`` (s, shape ``(T,)``, non-decreasing)."""
    t = np.asarray(t, float)
    p = np.asarray(power, float)
    if t.ndim != 1 or p.shape[:1] != t.shape:
        raise ValueError(f"power must have the log length {t.shape} first, got {p.shape}")
    if t.size < 2:
        return 0.0
    dt = np.diff(t)
    if (dt < 0.0).any():
        raise ValueError("sample times must be non-decreasing")
    p = p.reshape(p.shape[0], -1).sum(axis=1)
    return float(np.sum(0.5 * (p[1:] + p[:-1]) * dt))


#: actuators per group on HIT-MRII: "12 ... motors in the wheels" = 6 drive + 6 steering ("Each wheel
#: is equipped with a [driving] motor ... and a steering motor"), one hinge motor per side
GROUP_SIZES = {"drive": 6, "steer": 6, "rocker": 2}


@dataclass(frozen=True)
class Drivetrain:
    """The actuator groups of the rover and their specs (:data:`GROUP_SIZES` actuators each)."""

    drive: ActuatorSpec = WHEEL_DRIVE
    steer: ActuatorSpec = WHEEL_STEER
    rocker: ActuatorSpec = ROCKER_HINGE

    def groups(self) -> dict[str, ActuatorSpec]:
        return {"drive": self.drive, "steer": self.steer, "rocker": self.rocker}

    def power(self, tau: Mapping[str, object], omega: Mapping[str, object], regen: bool = False) -> dict:
        """Per group, the per-actuator input power (W) of ``tau[g]`` x ``omega[g]`` (last axis = the
        group's actuators); groups missing from ``tau`` are skipped."""
        out = {}
        for g, spec in self.groups().items():
            if g not in tau:
                continue
            p = electrical_power(spec, tau[g], omega[g], regen)
            if p.shape[-1:] != (GROUP_SIZES[g],):
                raise ValueError(f"group {g}: last axis must hold {GROUP_SIZES[g]} actuators, got {p.shape}")
            out[g] = p
        return out

    def total_power(self, tau: Mapping[str, object], omega: Mapping[str, object], regen: bool = False):
        """Input power (W) summed over every actuator of every group given (shape: the leading axes)."""
        parts = [p.sum(axis=-1) for p in self.power(tau, omega, regen).values()]
        return np.sum(parts, axis=0) if parts else np.float64(0.0)

    def power_of(self, actuator_force, actuator_velocity, ids: Mapping[str, object], regen: bool = False):
        """Total input power (W) from the simulator's actuator arrays (``data.actuator_force`` /
        ``actuator_velocity``, last axis = actuator id; joint transmissions of gear 1, so these
        are joint torques and speeds) with ``ids[g]`` the actuator ids of group ``g``."""
        f, v = np.asarray(actuator_force, float), np.asarray(actuator_velocity, float)
        tau = {g: f[..., np.asarray(i)] for g, i in ids.items()}
        omega = {g: v[..., np.asarray(i)] for g, i in ids.items()}
        return self.total_power(tau, omega, regen)


HIT_MRII = Drivetrain()


def electrical_energy(spec, t, tau, omega, regen: bool = False) -> float:
    """Electrical energy (J) over a log: power per sample, then the trapezoid rule over ``t`` (s).

    ``spec`` an :class:`ActuatorSpec` with ``tau``, ``omega`` arrays of shape ``(T, ...)`` (summed
    over the trailing axes), or a :class:`Drivetrain` with mappings group -> ``(T, n_group)``.
    Power is evaluated per sample before integrating (it is not linear in torque)."""
    if isinstance(spec, Drivetrain):
        p = spec.total_power(tau, omega, regen)
    else:
        p = electrical_power(spec, tau, omega, regen)
    return integrate_power(t, p)
