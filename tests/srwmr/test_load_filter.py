"""The load monitors (MC#10 / MC#11) read a held load (``supervisor.load_tau``, a first-order filter):
a transient of the F/T estimates a few control periods long halts the raw monitor but not the held
one; a load that stays over the limit halts both.

(Until 2026-12-08 this was shown on T4's buried RCM start, where the raw estimates crossed MC#11 at
21.55 s while the soil's own loads stayed inside it. That transient was the 0.5 ms step's chatter of
the loaded middle wheels' soil force; at the 0.25 ms step T4 has none, so the contract is tested here
on the controller with a transient of known length.)"""

import numpy as np
from fake_rover import Obs, controller

from terrabench.systems.srwmr.modes import Step

#: the six loads at rest, and one with W_fmr 1,000 N > MC#11's 700 N (W_diff 1,200 N < MC#10's 1,300)
REST = np.full(6, 380.0)
SPIKE = np.array([1380.0, 180.0, 180.0, 180.0, 180.0, 180.0])


def _reminders(load_tau: float, spike_periods: int) -> list[str]:
    """Reminders over 2 s of an RCLM lift whose loads read SPIKE for ``spike_periods`` periods from 0.5 s."""
    ctl = controller([Step("RCLM", v=0.0, clearance=0.33)], load_tau=load_tau)
    for k in range(200):
        ctl(Obs(0.01 * k, load=SPIKE if 50 <= k < 50 + spike_periods else REST))
    return [e[-1] for e in ctl.info()["events"] if "reminder" in e[-1]]


def test_a_transient_of_the_estimates_halts_the_raw_monitor_but_not_a_held_load():
    assert [r[:22] for r in _reminders(0.0, 3)] == ["reminder 1: MC11 ratio"]
    assert _reminders(0.2, 3) == []  # the default, a 0.2 s held load: 30 ms of a spike is not a load


def test_a_load_that_stays_over_the_limit_halts_the_held_monitor_too():
    held = _reminders(0.2, 100)  # 1 s over MC#11
    assert held and held[0].startswith("reminder 1: MC11 ratio")
