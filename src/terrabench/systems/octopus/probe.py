"""Ground-truth walking probe (evaluation only; controllers never see it).

Runs one CLM trial with per-tick instrumentation and measures what the paper's arm-moving rule
(eqs. 22-27) and its "the crawlers carry the robot" premise are about:

* **tip drift**: how far each arm tip travels over the ground during one support phase (from
  ``settle`` s after it landed to the start of its next transfer), in the world's xy plane;
* **track share**: the tracks' and flippers' part of the robot's normal ground load;
* **walking speed**: the chassis speed along its heading, over the whole walk and while the
  tracks run, beside the commanded track speed.

``python -m terrabench.systems.octopus.probe [seconds]`` prints the figures for flat ground.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field

import numpy as np

from terrabench.sim.episode import Episode
from terrabench.systems.octopus.robot import ARMS, Names


@dataclass
class WalkProbe:
    """Figures of one probed trial (m, m/s, fractions)."""

    drifts: dict[str, list[float]] = field(default_factory=dict)
    track_share: float = float("nan")
    unloaded_frac: float = float("nan")
    speed: float = float("nan")
    speed_driving: float = float("nan")
    track_speed: float = float("nan")
    sim_time: float = 0.0
    status: str = ""

    def all_drifts(self) -> np.ndarray:
        return np.array([d for v in self.drifts.values() for d in v], float)


def probe_walk(seconds: float = 25.0, overrides: dict | None = None, *, instance: str = "step-400",
               start_distance: float = 8.0, settle: float = 0.3, skip: float = 4.0) -> WalkProbe:
    """Probe a CLM walk on flat ground (the ``step-400`` scene with its step ``start_distance``
    m ahead, out of reach for ``seconds``). Figures start ``skip`` s in (arms placed)."""
    from terrabench.systems.octopus.scenarios import SYSTEM

    ov = {"protocol.timeout": seconds, "scene.start_distance": start_distance, **(overrides or {})}
    spec = SYSTEM.plan(methods=["clm"], instances=[instance], seeds=1, overrides=ov)[0]
    cfg, task, ctl = SYSTEM.trial_parts(spec)
    ep = Episode(task)
    obs, stop = ep.begin()
    m, d = ep.model, ep.data
    tips = [m.geom(Names.tip(k)).id for k in ARMS]
    weight = float(m.body_subtreemass[task.chassis]) * 9.81
    support_start: dict[int, np.ndarray | None] = {i: None for i in range(4)}
    landed_t = np.full(4, np.inf)
    out = WalkProbe(drifts={k: [] for k in ARMS}, track_speed=cfg.clm.track_speed)
    shares, unloaded, drive_v = [], [], []
    x0 = t0 = None
    prev_xy = None
    while stop is None:
        cmd = ctl(obs)
        t = obs.t
        supporting = [ctl.phase[k] == 0 and bool(ctl.contact[i]) for i, k in enumerate(ARMS)]
        for i in range(4):
            if supporting[i] and not np.isfinite(landed_t[i]):
                landed_t[i] = t
            if supporting[i] and support_start[i] is None and t - landed_t[i] >= settle:
                support_start[i] = d.geom_xpos[tips[i], :2].copy()
            if not supporting[i]:
                if support_start[i] is not None and t > skip:
                    out.drifts[ARMS[i]].append(float(np.hypot(*(d.geom_xpos[tips[i], :2] - support_start[i]))))
                support_start[i], landed_t[i] = None, np.inf
        if t >= skip:
            tot, tr = task.normal_load()  # the task's track-share computation (tracks + flippers)
            if tot > 0:
                shares.append(tr / tot)
                unloaded.append(tr < 0.05 * weight)
            xy = d.xpos[task.chassis, :2].copy()
            if x0 is None:
                x0, t0 = xy, t
            if prev_xy is not None and float(np.min(cmd.track)) > 0.5 * cfg.clm.track_speed:
                yaw = math.atan2(d.xmat[task.chassis, 3], d.xmat[task.chassis, 0])
                drive_v.append(float((xy - prev_xy) @ (math.cos(yaw), math.sin(yaw))) / task.timing.control_period)
            prev_xy = xy
        obs, stop = ep.step(cmd)
    xy = d.xpos[task.chassis, :2]
    out.sim_time, out.status = float(d.time), stop[0]
    out.track_share = float(np.mean(shares)) if shares else float("nan")
    out.unloaded_frac = float(np.mean(unloaded)) if unloaded else float("nan")
    if x0 is not None and d.time > t0:
        out.speed = float(np.hypot(*(xy - x0))) / (d.time - t0)
    out.speed_driving = float(np.mean(drive_v)) if drive_v else float("nan")
    return out


def main(argv: list[str]) -> None:
    seconds = float(argv[0]) if argv else 25.0
    p = probe_walk(seconds)
    dr = p.all_drifts()
    print(f"flat walk {p.sim_time:.1f} s ({p.status}): tip drift per support phase n={len(dr)} "
          f"median {np.median(dr) * 100:.1f} cm, max {dr.max() * 100:.1f} cm; track share {p.track_share:.0%}, "
          f"tracks unloaded {p.unloaded_frac:.0%} of ticks; speed {p.speed:.3f} m/s overall, "
          f"{p.speed_driving:.3f} m/s while driving (track {p.track_speed} m/s)")
    for k, v in p.drifts.items():
        print(f"  {k}: " + " ".join(f"{x * 100:.1f}" for x in v) + " cm")


if __name__ == "__main__":
    main(sys.argv[1:])
