"""Tasks 2, 9, 10 and 15 of the HIT-MRII beside the paper's figures (pure functions of stored rows
and series; :func:`terrabench.systems.srwmr.report._section` places them on the page).

* T2: the body slip of each period (WRM A, C, E; WCM B, D) [S "around 0.4" for both modes].
* T9: WRM (Ackermann) against WCM from A to B: mean body slip, its spread, time, energy, power.
* T10: every period of the height sequence (held heights and the changes between them): slip,
  time, energy, mean power.
* T15: the yaw rate against the front-middle wheelbase while the chassis is lowered under
  differential steering: the fitted slope d(yaw rate)/d(wheelbase) (the paper: it falls) and
  MC#8's largest ratio (the paper: ~0.4, below its threshold).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from terrabench.systems.srwmr.layouts import STEER_RATES, T10_HEIGHTS, T15_RATES

#: [S] Task 9 (WRM Ackermann, WCM): mean s_b, s_b range, running time (s), energy (kJ), mean power (kW)
T9_PAPER = {
    "wrm": (0.41, "0.27-0.50", 289, 69.9, 0.067),
    "wcm": (0.31, "0.13-0.37", 271, 58.7, 0.059),
}
#: [S] Task 10 energies per period (kJ) where stated: held 150 / 450 / 550 mm 5.8 / 6.1 / 6.0 kJ,
#: raised 200 mm 13.5 kJ, raised 400 mm 27.5 kJ, lowered 300 mm 15.9 and 20.6 kJ; power held
#: 0.054 / 0.056 / 0.057 kW at 150 / 450 / 550 mm; s_b within 0-0.44 throughout
T10_PAPER_KJ = {
    "250->450": 13.5,
    "450": 6.1,
    "450->150": 15.9,
    "150": 5.8,
    "150->550": 27.5,
    "550": 6.0,
    "550->250": 20.6,
}
T10_PAPER_KW = {"150": 0.054, "450": 0.056, "550": 0.057}
T2_PERIODS = ("A WRM", "B WCM right", "C WRM", "D WCM left", "E WRM")


#: seconds at the start of a steering step left out of its yaw rate: the command ramps up under MC#8
YAW_RAMP_S = 5.0


def _first(rows, inst, meth):
    rs = sorted((r for r in rows if r["instance"] == inst and r["method"] == meth), key=lambda r: r["seed"])
    return rs


def metric(r, key) -> float:
    """A stored row's metric as a float (NaN where the trial did not record it)."""
    v = r["metrics"].get(key, float("nan"))
    return float(v) if v is not None else float("nan")


def t10_periods() -> list[str]:
    """Labels of T10's plan steps: a held height, then the change to the next one."""
    hs = [round(h * 1000) for h in T10_HEIGHTS]
    out = [f"{hs[0]}"]
    for a in hs[1:-1]:
        out.append(f"{out[-1].split('->')[-1]}->{a}")
        out.append(f"{a}")
    out.append(f"{hs[-2]}->{hs[-1]}")
    return out


def t2_lines(rows) -> list[dict[str, Any]]:
    lines = []
    for r in _first(rows, "t2-wall", "wcm"):
        for k, name in enumerate(T2_PERIODS):
            lines.append({
                "seed": r["seed"],
                "period": name,
                "body slip": metric(r, f"step{k}_slip"),
                "time s": metric(r, f"step{k}_time"),
                "energy kJ": metric(r, f"step{k}_energy_elec_kJ"),
                "mech kJ": metric(r, f"step{k}_energy_kJ"),
                "paper": "s_b around 0.4 (WRM and WCM)",
            })
    return lines


def t9_lines(rows) -> list[dict[str, Any]]:
    lines = []
    for meth in ("wrm", "wcm"):
        for r in _first(rows, "t9-avoid", meth):
            sb, rng, pt, pe, pp = T9_PAPER[meth]
            t, e = metric(r, "sim_time"), metric(r, "energy_elec_kJ")
            lines.append({
                "mode": meth,
                "seed": r["seed"],
                "status": r["status"],
                "body slip": metric(r, "body_slip"),
                "slip p10-p90": f"{metric(r, 'slip_p10'):.2f}-{metric(r, 'slip_p90'):.2f}",
                "time s": t,
                "energy kJ": e,
                "mech kJ": metric(r, "energy_kJ"),
                "power W": 1000 * e / t if t > 0 else float("nan"),
                "PE": metric(r, "PE"),
                "paper s_b": sb,
                "paper range": rng,
                "paper time s": pt,
                "paper energy kJ": pe,
                "paper power W": 1000 * pp,
            })
    return lines


def t10_lines(rows) -> list[dict[str, Any]]:
    lines = []
    for r in _first(rows, "t10-heights", "rclm"):
        for k, name in enumerate(t10_periods()):
            t, e = metric(r, f"step{k}_time"), metric(r, f"step{k}_energy_elec_kJ")
            lines.append({
                "seed": r["seed"],
                "period mm": name,
                "body slip": metric(r, f"step{k}_slip"),
                "time s": t,
                "energy kJ": e,
                "mech kJ": metric(r, f"step{k}_energy_kJ"),
                "power W": 1000 * e / t if t > 0 else float("nan"),
                "paper energy kJ": T10_PAPER_KJ.get(name, float("nan")),
                "paper power W": 1000 * T10_PAPER_KW[name] if name in T10_PAPER_KW else float("nan"),
            })
    return lines


def yaw_vs_wheelbase(ts: dict[str, np.ndarray], robot) -> tuple[np.ndarray, np.ndarray]:
    """(wheelbase m, yaw rate rad/s) over the differential-steering step (plan step 1) of a T15
    series: the yaw rate from the stored yaw (central differences of the unwrapped heading), the
    front-middle wheelbase from the stored closing angles (mean of the sides)."""
    from terrabench.systems.srwmr.kinematics import geometry

    t = np.asarray(ts["t"], float)
    sel = np.asarray(ts["step"], float) == 1
    if sel.sum() < 5:
        return np.array([]), np.array([])
    yaw = np.unwrap(np.asarray(ts["yaw"], float))
    rate = np.gradient(yaw, t)
    dl, dr = np.asarray(ts["delta_L"], float), np.asarray(ts["delta_R"], float)
    wb = np.empty(len(t))
    for i in range(len(t)):
        P, _ = geometry(robot, (dl[i], dr[i]))
        wb[i] = 0.5 * ((P[0, 0] - P[2, 0]) + (P[1, 0] - P[3, 0]))
    t0 = t[sel][0]
    keep = sel & (t >= t0 + YAW_RAMP_S)
    return wb[keep], rate[keep]


def t15_lines(store, rows, robot) -> tuple[list[dict[str, Any]], list[tuple[str, np.ndarray, np.ndarray]]]:
    lines, curves = [], []
    for inst, w in T15_RATES.items():
        for r in _first(rows, inst, "rclm"):
            ts = store.timeseries(r["key"])
            if not ts or "t" not in ts:
                continue
            wb, rate = yaw_vs_wheelbase(ts, robot)
            if len(wb) < 3:
                continue
            slope = float(np.polyfit(wb, rate, 1)[0])
            curves.append((f"{inst} seed {r['seed']}", wb, rate))
            lines.append({
                "task": inst,
                "seed": r["seed"],
                "yaw cmd rad/s": w,
                "wheelbase m": f"{wb[0]:.3f} -> {wb[-1]:.3f}",
                "yaw rate rad/s": f"{rate[:3].mean():.4f} -> {rate[-3:].mean():.4f}",
                "achieved share": float(np.mean(rate) / w),
                "d(yaw rate)/d(wheelbase) 1/(m s)": slope,
                "MC8 max": metric(r, "max_eta_MC8"),
                "paper": "yaw rate falls as the wheelbase lengthens; MC#8 max ~0.4 (below threshold)",
                "verdict": "falls" if slope < 0 else "does not fall",
            })
    return lines, curves


def steer_lines(store, rows) -> list[dict[str, Any]]:
    """Sec. 8.6's in-place steering: the mean yaw rate over the steering step (its first
    :data:`YAW_RAMP_S` left out) against the command; the paper measured about one-fifth of it."""
    lines = []
    for inst, w in STEER_RATES.items():
        for r in _first(rows, inst, "rclm"):
            ts = store.timeseries(r["key"])
            if not ts or "t" not in ts:
                continue
            t = np.asarray(ts["t"], float)
            yaw = np.unwrap(np.asarray(ts["yaw"], float))
            keep = t >= t[0] + YAW_RAMP_S
            if keep.sum() < 5:
                continue
            rate = float((yaw[keep][-1] - yaw[keep][0]) / (t[keep][-1] - t[keep][0]))
            lines.append({
                "task": inst,
                "seed": r["seed"],
                "status": r["status"],
                "yaw cmd rad/s": w,
                "steering s": float(t[keep][-1] - t[0]),
                "mean yaw rate rad/s": rate,
                "achieved share": rate / w,
                "paper": "about one-fifth (0.2) of the command on loose soil [S sec. 8.6]",
            })
    return lines


def add_sections(page: Any, store: Any, rows: list[dict[str, Any]], slug: str, plt: Any, robot) -> None:
    """The T2 / T9 / T10 / sec. 8.6 steering / T15 tables (and T15's figure) of one settings group."""
    t2 = t2_lines(rows)
    if t2:
        page.h2("T2: WCM past a wall (slip per period)")
        page.table(t2, list(t2[0]), csv_name=f"t2{slug}.csv")
    t9 = t9_lines(rows)
    if t9:
        page.h2("T9: WRM (Ackermann) vs WCM from A to B around an obstacle")
        page.table(t9, list(t9[0]), csv_name=f"t9{slug}.csv")
        page.p("paper: WCM below WRM in slip (0.31 < 0.41), time (271 < 289 s) and energy (58.7 < 69.9 kJ)")
    t10 = t10_lines(rows)
    if t10:
        page.h2("T10: RCLM at four chassis heights while driving at 15 mm/s")
        page.table(t10, list(t10[0]), csv_name=f"t10{slug}.csv")
    steer = steer_lines(store, rows)
    if steer:
        page.h2("Sec. 8.6: differential steering in place at a held clearance")
        page.table(steer, list(steer[0]), csv_name=f"steer{slug}.csv")
    t15, curves = t15_lines(store, rows, robot)
    if t15:
        page.h2("T15: yaw rate while the wheelbase lengthens (differential steering, chassis lowered)")
        page.table(t15, list(t15[0]), csv_name=f"t15{slug}.csv")
        fig, ax = plt.subplots(figsize=(6, 3.5))
        for label, wb, rate in curves:
            ax.plot(wb * 1000, rate, "o-", ms=2, lw=0.8, label=label)
        ax.set_xlabel("front-middle wheelbase mm")
        ax.set_ylabel("yaw rate rad/s")
        ax.legend(fontsize="small")
        fig.tight_layout()
        page.figure(fig, f"t15{slug}.png", "T15: measured yaw rate against the wheelbase while the chassis is lowered")
        plt.close(fig)
