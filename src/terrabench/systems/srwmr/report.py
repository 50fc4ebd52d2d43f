"""HIT-MRII results beside the paper's (seed 001 sec. 8): tables, the T14 CSV, series, timelines."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from terrabench.systems.srwmr.ik import limited_share
from terrabench.systems.srwmr.layouts import REGISTRY

#: the paper's figures [S] (compare trends and orderings; its energy units are inconsistent)
PAPER = {
    ("t1-very-loose", "wrm"): "s_b 0.30-0.65",
    ("t1-loose", "wrm"): "s_b 0.0-0.40",
    ("t2-wall", "wcm"): "WRM and WCM s_b both around 0.4",
    ("t3-rclm", "rclm"): "RCLM 250->330->480->250 mm; MC#3 max 0.326",
    ("t4-sinkage", "rcm"): "RCM escapes full sinkage (5 RCLM cycles); MC#3 max 0.15",
    ("t5-slope10", "wrm"): "WRM moved 43.65 of 437.75 mm (10 % efficiency)",
    ("t5-slope10", "rcm"): "WRM then RCM (4 cycles) climbs 10 deg; s_b ~0.93 in RCM",
    ("t8-speeds", "wrm"): "s_b 0.18-0.32 at constant speed; EC 11.3/12.2/14/13/11 kJ per stage",
    ("t9-avoid", "wrm"): "s_b 0.41 (0.27-0.50), 289 s, 69.9 kJ",
    ("t9-avoid", "wcm"): "s_b 0.31 (0.13-0.37), 271 s, 58.7 kJ",
    ("t10-heights", "rclm"): "s_b within 0-0.44; P 54/56/57 W held at 150/450/550 mm",
    ("t15-w002", "rclm"): "yaw rate falls as the wheelbase lengthens; MC#8 max ~0.4",
    ("t15-w003", "rclm"): "yaw rate falls as the wheelbase lengthens; MC#8 max ~0.4",
    ("steer-w001", "rclm"): "in-place yaw rate about one-fifth of the command (sec. 8.6)",
    ("steer-w002", "rclm"): "in-place yaw rate about one-fifth of the command (sec. 8.6)",
    ("t11-slope15", "wrm"): "s_b -> 0.96, health halt at 64 s",
    ("t11-slope15", "rcm"): "RCM holds s_b ~0.44, all wheels on the slope",
    ("t14-obstacle", "wrm"): "4634 mm, 401 s, 97 kJ",
    ("t14-obstacle", "wcm"): "3166 mm, 358 s, 77 kJ",
    ("t14-obstacle", "rclm"): "2800 mm, 249 s, 49 kJ",
    ("t14-obstacle", "swlm"): "2800 mm, 859 s, 36 kJ (slowest, least energy)",
    ("t6-bricks", "swlm"): "right wheels lifted in turn over 150 mm bricks; W_diff 826 (front up) / 1050 N (rear up)",
    ("t7-stairs", "dwlm"): "pairs lifted in sequence up stairs; W_diff 1300 (front up) / 1189 N (rear up)",
    ("t12-lift100", "swlm"): "s_b 0.01-0.24; EC 39.6 kJ",
    ("t12-lift150", "swlm"): "s_b 0.01-0.24; EC 43.9 kJ; right rear PC 27.5",
    ("t12-lift200", "swlm"): "s_b 0.01-0.24; EC 41.5 kJ; both rear PC 32.5",
    ("t12-lift100", "dwlm"): "s_b -0.01-0.27; EC 42.5 kJ",
    ("t12-lift150", "dwlm"): "s_b -0.01-0.27; EC 41.9 kJ",
    ("t12-lift200", "dwlm"): "s_b -0.01-0.27; EC 41.8 kJ",
    ("t13-front", "swlm"): "s_b -0.1-0.14; EC 41.6 kJ",
    ("t13-middle", "swlm"): "s_b -0.16-0.1; EC 23.6 kJ",
    ("t13-rear", "swlm"): "s_b -0.02-0.21; EC 20.1 kJ",
    ("t13-front", "dwlm"): "s_b -0.01-0.21; EC 41.8 kJ",
    ("t13-middle", "dwlm"): "s_b peak 0.32; EC 22.4 kJ",
    ("t13-rear", "dwlm"): "s_b peak -0.1; EC 19.4 kJ",
}
T14_PAPER = {"wrm": (4634, 401, 97), "wcm": (3166, 358, 77), "rclm": (2800, 249, 49), "swlm": (2800, 859, 36)}
OPERATOR = (
    "The 'operator' is scripted per scenario: it answers every reminder after supervisor.reply_s "
    "(default 2 s), which ends the current action; the plan (layouts.py) is the paper's action sequence."
)


def _group(r: dict[str, Any]) -> str:
    """The row's instance group (an instance no longer registered counts as a task)."""
    es = REGISTRY.get(r["instance"])
    return es[0].group if es else "tasks"


def _in_tasks(r: dict[str, Any]) -> bool:
    """A row of the paper's experiments (groups ``tasks`` and ``steer``, sec. 8.6's in-place
    steering): the slope sweep and the ``ik`` cases have their own sections."""
    return _group(r) in ("tasks", "steer")


def _mean(rs, key):
    a = np.array([r["metrics"].get(key, np.nan) for r in rs], float)
    a = a[np.isfinite(a)]
    return float(a.mean()) if len(a) else float("nan")


def _limited(info) -> float | None:
    """``qp_limited_share`` as stored, or (rows made before it was) from the row's counts by the
    same :func:`~terrabench.systems.srwmr.ik.limited_share`."""
    if "qp_limited_share" in info:
        return info["qp_limited_share"]
    n, inside, share = info.get("qp_n"), info.get("qp_inside"), info.get("qp_active_share")
    if n is None or inside is None or share is None:
        return None
    return limited_share(n, inside, round(share * n))


def group(rows):
    out: dict[tuple[str, str], list] = {}
    for r in rows:
        out.setdefault((r["instance"], r["method"]), []).append(r)
    return out


def task_lines(rows) -> list[dict[str, Any]]:
    lines = []
    for (inst, meth), rs in sorted(group(rows).items()):
        st: dict[str, int] = {}
        for r in rs:
            st[r["status"]] = st.get(r["status"], 0) + 1
        lines.append(
            {
                "task": inst,
                "mode": meth,
                "n": len(rs),
                "statuses": ", ".join(f"{k} {v}" for k, v in sorted(st.items())),
                "body slip": _mean(rs, "body_slip"),
                "wheel slip": _mean(rs, "wheel_slip"),
                "progress m": _mean(rs, "progress"),
                "distance m": _mean(rs, "distance"),
                "time s": _mean(rs, "sim_time"),
                "energy kJ": _mean(rs, "energy_elec_kJ"),
                "mech kJ": _mean(rs, "energy_kJ"),
                "W_diff max N": _mean(rs, "W_diff_max"),
                "W_fmr max N": _mean(rs, "W_fmr_max"),
                "MC3 max": _mean(rs, "max_eta_MC3"),
                "paper": PAPER.get((inst, meth), ""),
            }
        )
    return lines


def t14_lines(rows) -> list[dict[str, Any]]:
    g = group([r for r in rows if r["instance"] == "t14-obstacle"])
    lines = []
    for meth in ("wrm", "wcm", "rclm", "swlm"):
        rs = g.get(("t14-obstacle", meth), [])
        pd, pt, pe = T14_PAPER[meth]
        lines.append(
            {
                "mode": meth,
                "n": len(rs),
                "success": sum(r["status"] == "success" for r in rs),
                "distance mm": 1000 * _mean(rs, "distance") if rs else float("nan"),
                "time s": _mean(rs, "sim_time") if rs else float("nan"),
                "energy kJ": _mean(rs, "energy_elec_kJ") if rs else float("nan"),
                "mech kJ": _mean(rs, "energy_kJ") if rs else float("nan"),
                "paper distance mm": pd,
                "paper time s": pt,
                "paper energy kJ": pe,
                "note": "" if rs else "not run",
            }
        )
    return lines


def slope_lines(rows) -> list[dict[str, Any]]:
    lines = []
    for (inst, meth), rs in sorted(group([r for r in rows if r["instance"].startswith("slope-")]).items()):
        _, deg, soil = inst.split("-", 2)
        lines.append(
            {
                "soil": soil,
                "slope deg": int(deg),
                "mode": meth,
                "n": len(rs),
                "success rate": sum(r["status"] == "success" for r in rs) / len(rs),
                "body slip": _mean(rs, "body_slip"),
                "progress m": _mean(rs, "progress"),
                "time s": _mean(rs, "sim_time"),
            }
        )
    return sorted(lines, key=lambda d: (d["soil"], d["mode"], d["slope deg"]))


def summary_table(rows):
    from rich.table import Table

    t = Table(title="HIT-MRII (srwmr): ours beside the paper")
    cols = ("task", "mode", "n", "statuses", "body slip", "progress m", "time s", "energy kJ", "paper")
    for c in cols:
        t.add_column(c)
    for ln in task_lines(rows):
        t.add_row(*[f"{ln[c]:.3f}" if isinstance(ln[c], float) else str(ln[c]) for c in cols])
    return t


def write_report(store, out_dir: Path, system: Any) -> Path:
    """Write the HIT-MRII report (``index.html``, CSVs, figures) from ``store``'s srwmr rows.

    Rows run under other settings than the planned defaults (``--set``) get their own section
    (:func:`terrabench.report.variants.settings_groups`), files suffixed with the group's slug.

    Raises:
        ValueError: no srwmr trials in the store, or ``out_dir`` cannot be written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.report.page import Page, provenance_html
    from terrabench.report.variants import Defaults, settings_groups
    from terrabench.systems.srwmr.soils import (
        FIT_K_LOOSE,
        FIT_K_PHI_VERY_LOOSE,
        T1_RANGES,
        TARGETS,
    )

    rows = store.rows(system=system.id)
    if not rows:
        raise ValueError(f"no srwmr trials in {store.path}; run `terrabench run srwmr --group tasks` first")
    page = Page(out_dir, "HIT-MRII reconfigurable rover (srwmr)")
    page.p(OPERATOR)
    page.h2("Soil calibration (the only fit: T1)")
    page.p(
        f"very loose: k_phi fitted = {FIT_K_PHI_VERY_LOOSE / 1e3:.1f} kN/m^3 so that the zero-pull slip of a "
        f"368 N wheel is {TARGETS['very_loose']} (T1 range {T1_RANGES['very_loose']}); loose: K fitted = "
        f"{FIT_K_LOOSE * 1000:.2f} mm (k_phi 1528 kN/m^3) for {TARGETS['loose']} (T1 range {T1_RANGES['loose']}). "
        "Every other task is a prediction."
    )
    groups = settings_groups(rows, Defaults(system))
    for g in groups:
        if len(groups) > 1:
            page.h2(f"Settings: {g.label} ({len(g.rows)} trials)")
        _section(page, store, list(g.rows), g.slug, plt)
        _snapshots(page, store, system, list(g.rows), g.slug)
    page.h2("Provenance")
    page.raw(provenance_html(store, rows, system_id=system.id, default_config=Defaults(system)))
    return page.finish()


#: at most this much of each mode's first trial is re-run for its snapshots (s, simulated)
SNAPSHOT_SPAN = 30.0
#: simulated seconds of each mode's clip in the report (a frame every 0.4 s, played at 25 fps: 10x real time;
#: software GL renders the soil scene at ~2 frames/s at 640 x 360, so the clips are kept short)
CLIP_SPAN = 60.0
#: the event each mode's clip is cut at (``SRWMRSystem.clip_events``): the mode's own action
CLIP_EVENT = {"wrm": "start", "wcm": "start", "rclm": "start", "rcm": "creep", "swlm": "lift", "dwlm": "lift"}


def _clip_rows(store: Any, system: Any, rows: list[dict[str, Any]]) -> dict[str, tuple[dict[str, Any], float]]:
    """Per mode, its first stored trial (seed, instance order; slope sweeps last; a success before a
    failure) in which the mode's :data:`CLIP_EVENT` happens, and the event's time: a distinct trial
    per mode, showing its action where it works (a DWLM lift that reached its height rather than one
    that stopped at 11 mm, RCM's climb of T5 rather than its shuttle in T4's ruts)."""
    out: dict[str, tuple[dict[str, Any], float]] = {}
    # the paper's numbered tasks first, then its other experiments, the sweeps last
    order = sorted(rows, key=lambda r: (_group(r) != "tasks", not _in_tasks(r), r["status"] != "success",
                                        r["seed"], r["instance"]))
    for r in order:
        meth = r["method"]
        if meth in out or meth not in CLIP_EVENT:
            continue
        ev = system.clip_events(r, store.timeseries(r["key"]))
        if CLIP_EVENT[meth] in ev:
            out[meth] = (r, ev[CLIP_EVENT[meth]])
    return out


def _snapshots(page: Any, store: Any, system: Any, rows: list[dict[str, Any]], slug: str) -> None:
    """Per mode: four frames of its first stored trial (t = 0 and thirds of its first
    ``SNAPSHOT_SPAN`` s), and a clip cut at the mode's own event (:data:`CLIP_EVENT`, a quarter of
    the clip before it) from the first trial where it happens, a success first (:func:`_clip_rows`);
    both re-run from the stored config,
    seen from the robot's right along the axles (a note instead without GL)."""
    from terrabench.benchmark.trial import TrialSpec

    firsts: dict[str, dict[str, Any]] = {}
    for r in sorted(rows, key=lambda r: (r["seed"], r["instance"])):
        if _group(r) == "tasks":
            firsts.setdefault(r["method"], r)
    if not firsts:
        return
    page.h3("Snapshots of each mode")
    for meth, r in sorted(firsts.items()):
        span = min(float(r["metrics"].get("sim_time", 0.0) or 0.0), SNAPSHOT_SPAN)
        times = [round(span * k / 3, 2) for k in range(4)]
        spec = TrialSpec(system.id, r["scenario"], meth, r["instance"], r["seed"], r["config"])
        page.snapshots(f"snap_{meth}{slug}.png",
                       f"{meth.upper()} on {r['instance']} (seed {r['seed']}) at t = "
                       f"{', '.join(f'{t:g}' for t in times)} s, re-run from the stored config "
                       "(<code>terrabench render srwmr</code> makes a clip)",
                       system, spec, times, width=480, height=270)
    page.h3("Each mode at work: clips cut at the mode's own event")
    for meth, (r, t_ev) in sorted(_clip_rows(store, system, rows).items()):
        spec = TrialSpec(system.id, r["scenario"], meth, r["instance"], r["seed"], r["config"])
        start = max(0.0, t_ev - 0.25 * CLIP_SPAN)
        page.clip(f"clip_{meth}{slug}.mp4",
                  f"{meth.upper()} on {r['instance']} (seed {r['seed']}): {CLIP_EVENT[meth]} at {t_ev:.1f} s; "
                  f"{start:.1f}-{start + CLIP_SPAN:.1f} s at 10x real time, trial status {r['status']} "
                  f"(<code>terrabench render srwmr --method "
                  f"{meth} --terrain {r['instance']} --at {CLIP_EVENT[meth]}</code>)",
                  system, spec, CLIP_SPAN, every=40, start=start, width=640, height=360)


def _robot(rows):
    """The robot of the group's first stored trial (its geometry turns closing angles into wheelbases)."""
    from terrabench.systems.srwmr.robot import RobotConfig

    cfg = (rows[0].get("config") or {}).get("robot") if rows else None
    try:
        return RobotConfig(**cfg) if isinstance(cfg, dict) else RobotConfig()
    except (TypeError, ValueError):
        return RobotConfig()


def _task_sections(page: Any, store: Any, task_rows: list[dict[str, Any]], slug: str, plt: Any, robot: Any) -> None:
    """The paper's tasks of one settings group: the summary table, T14 and every task's own sections."""
    lines = task_lines(task_rows)
    page.h2("Tasks: ours beside the paper")
    page.table(lines, list(lines[0]) if lines else ["task"], csv_name=f"tasks{slug}.csv")
    t14 = t14_lines(task_rows)
    if any(ln["n"] for ln in t14):
        page.h2("T14: the obstacle task per mode")
        page.table(t14, list(t14[0]), csv_name=f"t14{slug}.csv")
        ours = [(ln["mode"], ln["energy kJ"]) for ln in t14 if math.isfinite(ln["energy kJ"])]
        page.p(
            "energy ordering, ours (least first): "
            + " < ".join(m for m, _ in sorted(ours, key=lambda x: x[1]))
            + "; paper: swlm < rclm < wcm < wrm"
        )
    from terrabench.systems.srwmr.report_tasks import add_sections

    add_sections(page, store, task_rows, slug, plt, robot)
    from terrabench.systems.srwmr.report_legged import report_sections

    report_sections(page, store, task_rows, slug, plt)  # SWLM / DWLM: T6, T7, T12, T13, T14


def _section(page: Any, store: Any, rows: list[dict[str, Any]], slug: str, plt: Any) -> None:
    """The tables, series and timelines of one settings group (file names end in ``slug``)."""
    from terrabench.report.timeline import draw_timelines

    task_rows = [r for r in rows if _in_tasks(r)]
    if task_rows:  # a settings group may hold only slope or ik trials (e.g. a --timeout run of the sweep)
        _task_sections(page, store, task_rows, slug, plt, _robot(rows))
    page.h2("Constraint-saturated IK: QP solve time (DAQP via qpsolvers, 5 variables, 16 inequalities + bounds)")
    qp = [
        {
            "task": r["instance"],
            "mode": r["method"],
            "seed": r["seed"],
            "solves": r["info"].get("qp_n"),
            "median us": r["info"].get("qp_median_us"),
            "p99 us": r["info"].get("qp_p99_us"),
            "active share": r["info"].get("qp_active_share"),  # of the solves
            # of all control periods: the periods where the projection changed the command
            "limited share": _limited(r["info"]),
        }
        for r in task_rows
    ]
    if qp:
        page.table(qp, list(qp[0]), csv_name=f"qp_timing{slug}.csv")
    from terrabench.systems.srwmr.report_qp import add_section as qp_at_work

    qp_at_work(page, rows, slug, plt)  # group ik: the QP's share per constraint, its effect (figures, CSV)
    sl = slope_lines(rows)
    if sl:
        page.h2("Slopes: success and slip against the slope angle")
        page.table(sl, list(sl[0]), csv_name=f"slopes{slug}.csv")
        fig, ax = plt.subplots(1, 2, figsize=(10, 3.5))
        for soil in sorted({d["soil"] for d in sl}):
            for meth in sorted({d["mode"] for d in sl}):
                pts = [d for d in sl if d["soil"] == soil and d["mode"] == meth]
                ax[0].plot(
                    [d["slope deg"] for d in pts], [d["success rate"] for d in pts], "o-", label=f"{meth} {soil}"
                )
                ax[1].plot([d["slope deg"] for d in pts], [d["body slip"] for d in pts], "o-", label=f"{meth} {soil}")
        ax[0].set_xlabel("slope deg")
        ax[0].set_ylabel("success rate")
        ax[1].set_xlabel("slope deg")
        ax[1].set_ylabel("body slip")
        ax[0].legend(fontsize="small")
        fig.tight_layout()
        page.figure(fig, f"slopes{slug}.png", "success rate and body slip vs slope")
        plt.close(fig)
    # series and the mode timeline, seed 0 of each (task, mode)
    page.h2("Series per trial (seed 0): slip, wheel loads, constraint ratios")
    timelines = []
    for (inst, meth), rs in sorted(group(task_rows).items()):
        r0 = sorted(rs, key=lambda r: r["seed"])[0]
        ts = store.timeseries(r0["key"])
        ev = r0["info"].get("events", [])
        timelines.append((f"{inst}/{meth}", ev, float(r0["metrics"].get("sim_time", 0.0))))
        if not ts or "t" not in ts:
            continue
        t = np.asarray(ts["t"])
        fig, ax = plt.subplots(3, 1, figsize=(9, 7), sharex=True)
        vc = np.asarray(ts["v_cmd"], float)
        with np.errstate(divide="ignore", invalid="ignore"):
            sb = np.where(np.abs(vc) > 1e-4, 1 - np.asarray(ts["v"]) / vc, np.nan)
        ax[0].plot(t, sb, label="body slip s_b")
        ax[0].plot(t, ts["slip"], label="wheel slip (mean)")
        ax[0].set_ylim(-1, 1.2)
        ax[0].legend(fontsize="small")
        for c in ("c1", "c2", "c3", "c4", "c5", "c6"):
            ax[1].plot(t, ts[f"W_{c}"], lw=0.8, label=c)
        ax[1].set_ylabel("wheel load N")
        ax[1].legend(fontsize="x-small", ncol=6)
        from terrabench.systems.srwmr.constraints import NAMES, thresholds

        mode = meth.upper()
        kap = thresholds(mode)
        for i, n in enumerate(NAMES):
            e = np.asarray(ts[f"eta_{n}"], float)
            if np.nanmax(np.abs(e)) > 1e-3 if np.isfinite(e).any() else False:
                ax[2].plot(t, e, lw=0.8, label=f"{n} (kappa {kap[i]:.2f})")
        ax[2].set_ylabel("ratio eta")
        ax[2].set_xlabel("t s")
        ax[2].legend(fontsize="x-small", ncol=3)
        fig.suptitle(f"{inst} / {meth} seed {r0['seed']}: {r0['status']} ({r0['info'].get('reason', '')})")
        fig.tight_layout()
        page.figure(fig, f"ts_{inst}_{meth}{slug}.png",
                    f"{inst} / {meth}: slip, wheel loads (truth), constraint ratios")
        plt.close(fig)
    if timelines:
        fig, ax = plt.subplots(figsize=(10, 0.4 * len(timelines) + 1.2))
        draw_timelines(ax, timelines)
        fig.tight_layout()
        page.figure(fig, f"timeline{slug}.png",
                    "mode timeline per trial (controller events: supervisor halts, RCM switch)")
        plt.close(fig)
