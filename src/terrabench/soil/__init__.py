"""Wheel-soil terramechanics (Bekker / Wong-Reece / Janosi-Hanamoto) as MuJoCo forces.

See docs/soil.md. Modules: terramechanics (the model), presets (soils with sources), table
(fast lookup), mujoco_soil (SoilWheels hook), estimation (what a rover can measure),
testbed (single-wheel rig and sweeps), rover (six-wheel box rover), report (HTML/PNG).
"""

from terrabench.soil.estimation import estimated_sinkage, estimated_slip
from terrabench.soil.mujoco_soil import SoilWheels, flat_ground, hfield_ground
from terrabench.soil.presets import SOILS, soil
from terrabench.soil.table import SoilTable
from terrabench.soil.terramechanics import SoilParams, WheelParams, solve_sinkage, steady_state, wheel_forces

__all__ = ["SoilParams", "WheelParams", "SoilTable", "SoilWheels", "flat_ground", "hfield_ground",
           "estimated_slip", "estimated_sinkage", "SOILS", "soil", "solve_sinkage", "steady_state", "wheel_forces"]
