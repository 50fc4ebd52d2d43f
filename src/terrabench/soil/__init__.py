"""Wheel-soil terramechanics (Bekker / Wong-Reece / Janosi-Hanamoto) as MuJoCo forces.

See docs/soil.md. Modules: terramechanics (the model, one compiled kernel), presets (soils with
sources), table (fast 3-D look-up), mujoco_soil (SoilWheels hook), estimation (what a rover can
measure), rover (six-wheel box rover). The single-wheel testbed, the CMU validation and the
report are the system ``soil`` (terrabench.systems.soil).
"""

from terrabench.soil.estimation import estimated_sinkage, estimated_slip
from terrabench.soil.mujoco_soil import SoilWheels, flat_ground, hfield_ground
from terrabench.soil.presets import SOILS, soil
from terrabench.soil.table import SoilTable
from terrabench.soil.terramechanics import SoilParams, WheelParams, solve_sinkage, steady_state, wheel_forces

__all__ = ["SoilParams", "WheelParams", "SoilTable", "SoilWheels", "flat_ground", "hfield_ground",
           "estimated_slip", "estimated_sinkage", "SOILS", "soil", "solve_sinkage", "steady_state", "wheel_forces"]
