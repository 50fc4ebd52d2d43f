"""Speed of the MRS-CWC trial loop against the raw MuJoCo engine on the same model.

Two measurements per terrain, from the same dropped start:

- *raw*: ``mj_step`` alone with constant wheel commands, no Python between steps beyond
  one call per control period (the engine's throughput on this model and terrain);
- *loop*: a real trial (controller, sensing, logging, metrics), timed as a whole, with the
  time spent inside ``mj_step`` accumulated separately.

Reported: physics steps/s, real-time factor (simulated s per wall s) and the loop/raw ratio
(1.0 = Python adds nothing).
"""

from __future__ import annotations

import time
from typing import Sequence

import mujoco
import numpy as np

from terrabench.config import override
from terrabench.systems.mrs_cwc import trial
from terrabench.systems.mrs_cwc.config import MRSConfig
from terrabench.systems.mrs_cwc.methods import get_method
from terrabench.terrain import dataset

DEFAULT_TERRAINS = ("B-05", "B-15", "B-25", "B-35", "B-45")


def measure(method: str, terrains: Sequence[str] | None, seconds: float, cfg: MRSConfig | None = None) -> list[dict]:
    if not seconds > 0:
        raise ValueError(f"seconds must be positive, got {seconds}")
    meth = get_method(method)
    cfg = override(cfg or MRSConfig(), {"protocol.timeout": seconds})
    rows = []
    for tid in terrains or DEFAULT_TERRAINS:
        ter = dataset.get(tid)
        sc = trial.build_scene(ter, meth, cfg)
        m, d = sc.model, sc.data
        nsub = int(round(cfg.protocol.control_period / cfg.physics.timestep))
        d.ctrl[sc.wheel_act] = cfg.drive.wheel_speed
        n_ctrl = int(round(seconds / cfg.protocol.control_period))
        t0 = time.perf_counter()
        for _ in range(n_ctrl):
            mujoco.mj_step(m, d, nsub)
        raw = time.perf_counter() - t0
        status, metrics, _, info = trial.run(meth, ter, cfg)
        steps = info["physics_steps"]
        rows.append({
            "terrain": tid,
            "raw_steps_per_s": n_ctrl * nsub / raw,
            "raw_rtf": n_ctrl * cfg.protocol.control_period / raw,
            "loop_steps_per_s": steps / info["loop_time"],
            "loop_rtf": metrics["sim_time"] / info["loop_time"],
            "engine_share": info["engine_time"] / info["loop_time"],
            "status": status,
        })
    return rows


def perf_table(rows: list[dict]):
    from rich.table import Table

    t = Table(title="MRS-CWC speed: raw mj_step vs the full trial loop (same model, same terrain)")
    for c in ("terrain", "raw steps/s", "raw RTF", "loop steps/s", "loop RTF", "loop/raw", "mj_step share of loop"):
        t.add_column(c, justify="right")
    for r in rows:
        t.add_row(r["terrain"], f"{r['raw_steps_per_s']:.0f}", f"{r['raw_rtf']:.0f}", f"{r['loop_steps_per_s']:.0f}",
                  f"{r['loop_rtf']:.0f}", f"{r['loop_steps_per_s'] / r['raw_steps_per_s']:.2f}", f"{100 * r['engine_share']:.0f} %")
    mean = lambda k: float(np.mean([r[k] for r in rows]))  # noqa: E731
    t.add_row("mean", f"{mean('raw_steps_per_s'):.0f}", f"{mean('raw_rtf'):.0f}", f"{mean('loop_steps_per_s'):.0f}",
              f"{mean('loop_rtf'):.0f}", f"{mean('loop_steps_per_s') / mean('raw_steps_per_s'):.2f}", f"{100 * mean('engine_share'):.0f} %")
    return t
