"""A driven wheel whose soil resistance exceeds its thrust (docs/soil.md, "Limitations": "A hub that
does not advance is pushed as if it did").

The forces are the forward-travel steady state. A wheel carrying more than the soil's thrust can
move (1,050 N on the HIT-MRII's fitted loose preset: the drawbar pull is -40 to -68 N at every slip)
and spinning forward stays where it is or digs in; it has no soil face behind it to be pushed by.
The model drives it backward at about its rim speed instead. ``SoilWheels(rut_behind=True)`` drops
the steady state's negative drawbar pull while the hub does not advance; it is off by default until
the stored results are re-made with it, so the strict xfail holds the default's contract open: it
fails (XPASS) once the default changes, and the marker must then go."""

import mujoco
import pytest

from terrabench.soil.mujoco_soil import SoilWheels
from terrabench.soil.table import cached_table
from terrabench.systems.srwmr import soils as S

_XML = """<mujoco><option timestep="0.00025"/>
<worldbody><body name="cart" pos="0 0 0.2">
 <joint name="x" type="slide" axis="1 0 0"/><joint name="z" type="slide" axis="0 0 1"/>
 <inertial pos="0 0 0" mass="{mass}" diaginertia="1 1 1"/>
 <body name="wheel"><joint name="spin" type="hinge" axis="0 1 0"/>
  <geom type="cylinder" size="0.15 0.06" euler="90 0 0" mass="2"/></body>
</body></worldbody></mujoco>"""


def _spin(load, seconds=5.0, rim=0.025, rut_behind=False):
    """Settle one wheel carrying ``load`` (N) on the fitted loose soil, then turn it forward at
    ``rim`` m/s for ``seconds``; returns (the hub's travel in x (m), the last drawbar pull (N))."""
    m = mujoco.MjModel.from_xml_string(_XML.format(mass=load / 9.81 - 2.0))
    d = mujoco.MjData(m)
    sw = SoilWheels(m, d, ["wheel"], S.HIT_MRII_WHEEL, cached_table(S.LOOSE, S.HIT_MRII_WHEEL), refresh=True,
                    rut_behind=rut_behind)
    dt = m.opt.timestep
    for _ in range(int(1.0 / dt)):
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
    x0 = float(d.qpos[0])
    for _ in range(int(seconds / dt)):
        d.qvel[2] = rim / S.HIT_MRII_WHEEL.radius
        sw.before_substep(m, d)
        mujoco.mj_step(m, d)
    return float(d.qpos[0]) - x0, float(sw.truth["DP"][0])


def test_a_wheel_with_thrust_to_spare_drives_forward_with_or_without_the_rut_behind():
    travel, dp = _spin(380.0)
    assert travel > 0.05  # 5 s at a 25 mm/s rim, slip ~0.2
    assert _spin(380.0, rut_behind=True) == (travel, dp)  # its drawbar pull is never negative: the same bits


def test_with_the_rut_behind_a_wheel_without_thrust_to_spare_digs_in_place():
    travel, dp = _spin(1050.0, rut_behind=True)
    assert abs(travel) < 0.005 and dp == 0.0


@pytest.mark.xfail(strict=True, reason="the soil coupling pushes a hub that does not advance as if it did "
                                       "(docs/soil.md, Limitations): the wheel backs away at ~its rim speed")
def test_a_wheel_without_thrust_to_spare_does_not_back_away():
    travel, dp = _spin(1050.0)
    assert travel > -0.01, f"the hub moved {travel * 1000:+.0f} mm under a forward-turning rim (DP {dp:+.0f} N)"
