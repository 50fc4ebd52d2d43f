"""The load monitors (MC#10 / MC#11) and the F/T estimates' transients: T4's buried RCM start."""

import numpy as np

from terrabench.sim.episode import Episode
from terrabench.systems.srwmr.scenarios import SYSTEM


def _reminders(overrides, until=25.0):
    """The supervisor's reminders in T4 RCM up to ``until`` s, and the largest W_fmr of the soil's
    own normal forces at any period where the raw F/T estimates put W_fmr over MC#11's 700 N."""
    spec = SYSTEM.trial_spec("rcm", "t4-sinkage", 0, {"protocol.timeout": until, **overrides})
    _, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    soil_at_high = 0.0
    while stop is None:
        cmd = ctl(obs)
        ft, fn = np.asarray(obs.load, float), np.asarray(task.soil_wheels.truth["Fn"], float)
        if max(ft.max() - ft.mean(), ft.mean() - ft.min()) > 700.0:
            soil_at_high = max(soil_at_high, max(fn.max() - fn.mean(), fn.mean() - fn.min()))
        obs, stop = ep.step(cmd)
    return [e for e in ctl.info()["events"] if "reminder" in e[-1]], soil_at_high


def test_a_transient_of_the_estimates_halts_the_raw_monitor_but_not_a_held_load():
    raw, soil_fmr = _reminders({"supervisor.load_tau": 0.0})
    assert [e[-1][:22] for e in raw] == ["reminder 1: MC11 ratio"]  # 21.55 s, as stored
    assert soil_fmr < 700.0  # wherever the estimates cross MC#11, the soil's own loads are inside it
    held, _ = _reminders({"supervisor.load_tau": 0.2})  # the default, a 0.2 s held load
    assert held == []
