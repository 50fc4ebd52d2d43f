"""OCTOPUS results: the table beside the paper's numbers and the HTML report (shared page layer).

Every report line is one (task, variant): a run with different ``--set`` values is its own
labelled line (:func:`terrabench.report.variants.find_variants`).
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import Any

import numpy as np

#: the paper's results (Chen, Kamezaki et al. 2018, "Results and discussion"); None = not given
PAPER = {
    ("step-400", "clm"): {"success": "5/5", "max_pitch": 0.6, "max_roll": 0.03, "min_margin": 0.15},
    ("step-400", "ccm"): {"success": "0/5 (turned over)", "max_pitch": None, "max_roll": -0.14, "min_margin": None},
    ("terrace2-front", "clm"): {"success": "yes", "max_pitch": 0.59, "max_roll": None, "min_margin": 0.17},
    ("terrace2-side", "clm"): {"success": "yes", "max_pitch": None, "max_roll": -0.25, "min_margin": 0.07},
    ("block-500", "clm"): {"success": "passes (arm detects, rides over)", "max_pitch": None, "max_roll": None,
                           "min_margin": None},
}
TASK_ORDER = ("step-400", "terrace2-front", "terrace2-side", "block-500")
METHOD_LABEL = {"clm": "CLM", "ccm": "CCM"}
#: mode codes of the stored ``mode`` column, per method (clm.MODE_NAMES, ccm.MODE_NAMES)
CCM_NOTE = (
    "CCM here is an automated stand-in for the paper's two operators (the paper: two skilled "
    "operators drove the robot by joysticks and pedals, watching environment-camera images, and "
    "\"tried twice\" before it turned over; it gives no rule of theirs). It uses the same sensors as "
    "CLM and an automated flipper sequence (the paper: CCM \"can be realized by manual or "
    "well-designed automated control system\"): approach with the front flippers raised and held, "
    "press them on the edge and push with the rear flippers (the paper's eq. 29: flippers rotate "
    "down to lift the body), flatten on the top. Where the operators tried again, it backs off "
    "after 6 s without pitch gain and retries, rearing the nose higher (0.3 rad more) before it "
    "presses each time; it aborts (stops, flattens) at its own estimate of the static tip-back "
    "angle (0.92 rad with the rear flippers pushing). The outcome is decided from the contacts: "
    "tipped_back when the COG passes behind the rearmost loaded contact (a rear end of the robot) "
    "with the nose up and rising for 0.2 s. What it cannot stand in for: the operators' view of "
    "the edge and judgement of when to stop.")
#: a trial whose static margin minimum is below this (m) is in the terraces' low group, the release
#: teeter on the first edge; which group a trial falls in is decided by sub-micrometre differences in
#: its start (benchmarks/start_sensitivity_study.py), so the report counts the trials in it
LOW_MARGIN_M = 0.03
#: the tasks table's column counting them (the README block reads it by this name)
LOW_COLUMN = f"trials with min margin < {LOW_MARGIN_M} m"
MARGIN_NOTE = (
    "Stability margin: the paper's static margin, the distance from the COG's ground projection to "
    "the support polygon, here the hull of the contacts of geoms that carried more than 20 N within "
    "the last 0.5 s (load-filtered), evaluated at quasi-static instants only (chassis speed < 0.15 "
    "m/s, angular speed < 0.3 rad/s, normal ground load within 20 % of the weight), sampled every "
    "0.1 s after the first second. Dynamic events (runs of other instants whose margin over every "
    "contact is negative: impacts, the lift, the release) are counted apart, with their worst "
    "instantaneous margin. On the terraces the per-trial minimum falls in two groups, near 0 (the "
    f"release teeter) and 0.08-0.12 m, decided by sub-micrometre differences in the start; the column "
    f"'trials with min margin < {LOW_MARGIN_M} m' counts the trials in the low group (docs/octopus.md, "
    "'How much a seed's terrace margin says').")
HEADING_NOTE = (
    "Heading: the paper's operator gave the move direction. Here both controllers integrate the "
    "IMU gyro's yaw rate into a heading and hold the start heading with a crawler speed difference "
    "(0.2 m/s per rad, at most 0.03 m/s each way); the robot senses no yaw angle and no position.")


def group(rows: list[dict[str, Any]]) -> dict[tuple[str, str], list[dict[str, Any]]]:
    out: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        out.setdefault((r["instance"], r.get("variant", r["method"])), []).append(r)
    return out


def finite_metric(rs: list[dict[str, Any]], name: str) -> np.ndarray:
    """The finite values of metric ``name`` over the trials ``rs`` (a trial without it: left out)."""
    a = np.array([r["metrics"].get(name, np.nan) for r in rs], float)
    return a[np.isfinite(a)]


def task_summary(rs: list[dict[str, Any]]) -> dict[str, Any]:
    """Successes, statuses and the extreme figures over one (task, variant)'s trials."""
    m = lambda name: np.array([r["metrics"].get(name, np.nan) for r in rs], float)  # noqa: E731
    statuses: dict[str, int] = {}
    for r in rs:
        statuses[r["status"]] = statuses.get(r["status"], 0) + 1

    def ext(a):
        a = a[np.isfinite(a)]
        return float(a[np.argmax(np.abs(a))]) if len(a) else float("nan")

    def lo(a):
        a = a[np.isfinite(a)]
        return float(a.min()) if len(a) else float("nan")

    def mean(a):
        a = a[np.isfinite(a)]
        return float(a.mean()) if len(a) else float("nan")

    ok = np.array([r["status"] == "success" for r in rs])
    t = m("sim_time")
    return {"n": len(rs), "success": int(ok.sum()), "statuses": statuses,
            "max_pitch": ext(m("max_pitch")), "max_roll": ext(m("max_roll")),
            "min_margin": lo(m("min_margin")), "dyn_events": mean(m("dyn_events")),
            "low_margin": int(np.sum(m("min_margin") < LOW_MARGIN_M)),
            "with_margin": int(np.sum(np.isfinite(m("min_margin")))),
            "min_margin_dyn": lo(m("min_margin_dyn")), "track_share": mean(m("track_share")),
            "energy": mean(m("energy")), "track_energy": mean(m("track_energy")),
            "speed": mean(m("progress") / np.maximum(m("sim_time"), 1e-9)),
            "time_success": mean(t[ok]) if ok.any() else float("nan")}


def _f(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, str):
        return v
    return "-" if v != v else f"{v:+.2f}"


def _key_order(order):
    """Tasks in the paper's order, CLM variants before CCM ones."""
    return lambda k: (order.get(k[0], 99), k[0], 0 if k[1].startswith("clm") else 1, k[1])


def _lines(g, order) -> list[dict[str, Any]]:
    lines = []
    for key in sorted(g, key=_key_order(order)):
        rs = g[key]
        s = task_summary(rs)
        meth = rs[0]["method"]
        p = PAPER.get((key[0], meth), {})
        lines.append({
            "task": key[0], "mode": rs[0].get("label", METHOD_LABEL.get(meth, meth)), "n": s["n"],
            "success": f"{s['success']}/{s['n']}", "paper": str(p.get("success", "-")),
            "statuses": ", ".join(f"{k} {v}" for k, v in sorted(s["statuses"].items())),
            "max pitch rad": f"{_f(s['max_pitch'])} ({_f(p.get('max_pitch'))})",
            "max roll rad": f"{_f(s['max_roll'])} ({_f(p.get('max_roll'))})",
            "min margin m": f"{_f(s['min_margin'])} ({_f(p.get('min_margin'))})",
            LOW_COLUMN: f"{s['low_margin']}/{s['with_margin']}",
            "dynamic events / trial": round(s["dyn_events"], 1) if s["dyn_events"] == s["dyn_events"] else None,
            "worst dynamic margin m": s["min_margin_dyn"],
            "track share": s["track_share"], "energy J": s["energy"], "of it crawlers J": s["track_energy"],
            "time to success s": s["time_success"], "mean speed m/s": s["speed"],
        })
    return lines


#: per-trial mechanism figures (task.py) and the issue's targets: (metric, column, target)
MECHANISM = (
    ("max_pitch_rad", "max pitch rad", "~0.6 (Fig. 9)"),
    ("crawler_load_share_min", "crawlers' least load share (climb)", "> 0.5"),
    ("crawler_load_share_phase_min", "crawlers' least mean share over a climb phase", "> 0.5"),
    ("crawler_load_share_lift", "crawlers' least mean share over a nose lift (Fig. 9e)", "> 0.5"),
    ("crawler_load_share_rear_lift", "crawlers' least mean share over a rear lift (eq. 28)", "> 0.5"),
    ("crawler_load_share_drive_on", "crawlers' least mean share over a drive on the top (S to L)", "> 0.5"),
    ("tip_slip_max_m", "tip slip max m (support phase)", "< 0.02"),
    ("tip_slip_walk_max_m", "tip slip max m (support phase, walk)", "< 0.02"),
    ("tip_slip_climb_max_m", "tip slip max m (support phase, climb)", "- (paper: not kept, Fig. 9e)"),
    ("tracks_stopped_share", "tracks stopped (walking ticks)", "< 0.05"),
    ("walk_speed_mean_mps", "crawler speed mean m/s (walking ticks)", "fixed and low [S]"),
    ("crawlers_enclosed_share", "crawlers inside the supporting tips (walking rows)",
     "always (Fig. 7, the issue's reading)"),
    ("walk_three_supports_share", "three or more arms support (walking rows)", "always (Fig. 7's premise)"),
    ("margin_gained_share", "tips widen the crawlers' margin (walking rows)", "always (Fig. 7's conclusion)"),
    ("margin_gain_walk_min_m", "least margin the tips add m (walking rows)", "> 0 (Fig. 7's conclusion)"),
    ("margin_min_m", "static margin min m", "paper's min margin"),
    ("margin_sensed_min_m", "sensed margin min m", "-"),
)


#: figures of the crawlers' load share read from the stored series (:func:`climb_share`): (key, column)
SHARE_SERIES = (
    ("share_min_quasi", "crawlers' least share, quasi-static climb rows"),
    ("crawler_free_s", "longest climb run without crawler load s"),
)


def climb_share(ts: dict[str, np.ndarray], method: str) -> dict[str, float]:
    """The two causes of a zero in ``crawler_load_share_min`` told apart, from a trial's stored
    rows after the first second: the crawlers' least share over the quasi-static climb rows
    (a nose dropping onto its crawlers is a dynamic instant: the crawlers are in the air for
    one row), and the longest run of climb rows with the crawlers carrying < 5 % of the normal
    load (s; the robot held up on its arm tips). NaN without climb rows."""
    from terrabench.systems.octopus import ccm, clm

    nan = float("nan")
    if not ts or "track_share" not in ts:
        return {k: nan for k, _ in SHARE_SERIES}
    modes = {"clm": (clm.CLIMB, clm.RELEASE), "ccm": (ccm.PRESS, ccm.PUSH, ccm.FLATTEN)}.get(method, ())
    t, share = ts["t"], ts["track_share"]
    climb = np.isin(ts["mode"], modes) & np.isfinite(share) & (t > 1.0)
    if not climb.any():
        return {k: nan for k, _ in SHARE_SERIES}
    qs = climb & (ts["quasi"] > 0.5)
    idx = np.flatnonzero(climb)
    dt = float(np.median(np.diff(t[idx]))) if len(idx) > 1 else 0.0  # the stored rows' spacing
    longest, start = 0.0, None
    for j, k in enumerate(idx):  # runs of consecutive stored climb rows below 5 %
        if share[k] >= 0.05:
            start = None
            continue
        if start is None or t[k] - t[idx[j - 1]] > 1.5 * dt:
            start = k
        longest = max(longest, float(t[k] - t[start]) + dt)
    return {"share_min_quasi": float(share[qs].min()) if qs.any() else nan, "crawler_free_s": longest}


#: seconds after a release over which the pitch is watched for a tip-back (:func:`release_points`)
RELEASE_WATCH = 2.5
#: a release is counted against the last edge less than this far ahead of the chassis (m): the
#: chassis stands at most the front's reach (~0.5 m, pulley and level flippers) behind an edge it
#: climbed; the report's grouping only
RELEASE_REACH = 0.25
#: the instances with edges to climb and release past (:func:`release_points`)
RELEASE_TASKS = ("step-400", "terrace2-front", "terrace2-side")


def release_points(events: list, ts: dict[str, np.ndarray]) -> list[tuple[float, float, float]]:
    """Each CLM release (a stored climb -> release transition) as (t s, the chassis' position
    along the approach axis then m (the first edge at 0), the pitch rise within
    :data:`RELEASE_WATCH` s after it rad): a release with the COG still behind the edge it
    climbed tips the robot back over that edge (docs/octopus.md, "The terrace release comes with
    the COG behind the edge"). Evaluation only: the position is the simulator's."""
    if not ts or "s" not in ts:
        return []
    t, s, pitch = ts["t"], ts["s"], ts["pitch"]
    out = []
    for e in events:
        if e[1] == "climb" and e[2] == "release":
            i = min(int(np.searchsorted(t, float(e[0]))), len(t) - 1)
            j = int(np.searchsorted(t, float(e[0]) + RELEASE_WATCH, side="right"))
            out.append((float(t[i]), float(s[i]), float(np.nanmax(pitch[i:max(j, i + 1)]) - pitch[i])))
    return out


def _release_figure(plt, pts: dict[str, list[tuple[float, float, float]]], edges: dict[str, tuple[float, ...]]):
    """Release position against the tip-back that follows, per task (:func:`release_points`)."""
    fig, ax = plt.subplots(figsize=(7, 4))
    for n, (task, p) in enumerate(pts.items()):
        if p:
            ax.plot([x for _, x, _ in p], [d for _, _, d in p], "o^sv"[n % 4], alpha=0.7, label=task)
    for x in sorted({x for e in edges.values() for x in e}):
        ax.axvline(x, color="0.5", lw=0.8, ls="--")
    ax.set_xlabel("chassis position along the approach axis at the release m (edges dashed)")
    ax.set_ylabel(f"pitch rise within {RELEASE_WATCH:g} s rad")
    ax.set_title("CLM releases: where, and whether the robot tipped back over the edge")
    ax.legend()
    fig.tight_layout()
    return fig


def mechanism_lines(g, order, share: dict[str, dict[str, float]] | None = None) -> list[dict[str, Any]]:
    """Per task and mode: the median over the trials of each :data:`MECHANISM` figure, with its
    range (the trials' min-max), from the stored metrics; with ``share`` (trial key ->
    :func:`climb_share`), the :data:`SHARE_SERIES` figures beside them."""
    lines = []
    for key in sorted(g, key=_key_order(order)):
        rs = g[key]
        line: dict[str, Any] = {"task": key[0], "mode": rs[0].get("label", METHOD_LABEL.get(rs[0]["method"],
                                                                                             rs[0]["method"])),
                                "n": len(rs)}
        for metric, col, _ in MECHANISM:
            a = finite_metric(rs, metric)
            line[col] = f"{np.median(a):.3f} ({a.min():.3f}-{a.max():.3f})" if a.size else "-"
        for name, col in SHARE_SERIES if share is not None else ():
            a = np.array([share.get(r["key"], {}).get(name, np.nan) for r in rs], float)
            a = a[np.isfinite(a)]
            line[col] = f"{np.median(a):.3f} ({a.min():.3f}-{a.max():.3f})" if a.size else "-"
        lines.append(line)
    return lines


LINE_COLUMNS = ("task", "mode", "n", "success", "paper", "statuses", "max pitch rad", "max roll rad",
                "min margin m", LOW_COLUMN, "dynamic events / trial", "worst dynamic margin m", "track share",
                "energy J", "of it crawlers J", "time to success s", "mean speed m/s")


def summary_table(rows: list[dict[str, Any]]):
    """Rich table: per task and mode, ours (paper)."""
    from rich.table import Table

    t = Table(title="OCTOPUS: ours (paper). CCM is an automated stand-in for the paper's operators")
    cols = ("task", "mode", "success", "paper", "statuses", "max pitch rad", "max roll rad", "min margin m",
            "track share")
    for c in cols:
        t.add_column(c)
    order = {k: i for i, k in enumerate(TASK_ORDER)}
    for ln in _lines(group(rows), order):
        t.add_row(*[v if isinstance(v, str) else _f(v) for v in (ln[c] for c in cols)])
    return t


def sweep_rates(rows: list[dict[str, Any]]) -> dict[str, list[tuple[int, float, int]]]:
    """variant label -> [(height mm, success rate, n)] of the sweep rows."""
    out: dict[str, dict[int, list[int]]] = {}
    for r in rows:
        if not r["instance"].startswith("sweep-h"):
            continue
        h = int(r["instance"][len("sweep-h"):])
        out.setdefault(r.get("label", r["method"]), {}).setdefault(h, []).append(1 if r["status"] == "success" else 0)
    return {m: [(h, float(np.mean(v)), len(v)) for h, v in sorted(d.items())] for m, d in out.items()}


def snapshot_times(ts: dict[str, np.ndarray]) -> list[float]:
    """Five instants of a CLM climb from its stored series: walking, climb start, mid-lift,
    release, the end (s)."""
    t, mode = np.asarray(ts["t"]), np.nan_to_num(np.asarray(ts["mode"]), nan=-1)
    end = float(t[-1])
    climb = t[mode == 1]
    if not len(climb):
        return [end * f for f in (0.1, 0.3, 0.5, 0.7, 1.0)]
    t0, t1 = float(climb[0]), float(climb[-1])
    return [max(0.0, t0 - 5.0), t0, 0.5 * (t0 + t1), t1 + 0.5, end]


def _series_figure(plt, ts: dict[str, np.ndarray], r: dict[str, Any], title: str):
    """Pitch/roll, margins, progress, arm transfers and the mode timeline of one trial."""
    from terrabench.report.timeline import draw_timelines

    t = np.asarray(ts["t"])
    fig, ax = plt.subplots(5, 1, figsize=(9, 10), sharex=True,
                           gridspec_kw={"height_ratios": [2, 2, 2, 2, 0.8]})
    ax[0].plot(t, ts["pitch"], label="pitch")
    ax[0].plot(t, ts["roll"], label="roll")
    ax[0].set_ylabel("rad")
    ax[0].legend(loc="upper left")
    if "quasi" in ts:
        q = np.nan_to_num(ts["quasi"]) > 0.5
        ax[1].plot(t, np.where(q, ts["margin"], np.nan), ".", ms=2, label="static margin (quasi-static)")
        ax[1].plot(t, np.where(~q, ts["margin_all"], np.nan), ".", ms=2, color="tab:red",
                   label="all contacts, dynamic instants")
    else:
        ax[1].plot(t, ts["margin"], label="margin")
    if "margin_sensed" in ts:
        ax[1].plot(t, ts["margin_sensed"], lw=0.8, color="tab:green", label="sensed margin (FK tips + tracks, IMU)")
    ax[1].axhline(0, color="k", lw=0.5)
    ax[1].set_ylabel("margin m")
    ax[1].legend(loc="lower left", fontsize="small")
    ax[2].plot(t, ts["s"], label="progress s")
    ax[2].plot(t, ts["z"], label="chassis z")
    if "track_share" in ts:
        ax[2].plot(t, ts["track_share"], label="track share of load", lw=0.8)
    if "tip_slip" in ts:
        ax[2].plot(t, ts["tip_slip"], label="tip slip in its support phase m", lw=0.8)
    if "climb_stage" in ts:  # CLM's climb stages shaded behind the load share
        from terrabench.systems.octopus.clm import STAGE_NAMES

        stage = np.nan_to_num(np.asarray(ts["climb_stage"]))
        for (k, name), color in zip(STAGE_NAMES.items(), ("tab:orange", "tab:purple", "tab:cyan", "tab:gray")):
            if (stage == k).any():
                ax[2].fill_between(t, 0, 1, where=stage == k, transform=ax[2].get_xaxis_transform(), step="mid",
                                   color=color, alpha=0.15, lw=0, label=f"climb: {name.replace('_', ' ')}")
    ax[2].set_ylabel("m, -")
    ax[2].legend(loc="upper left", fontsize="small")
    arms = ("LF", "RF", "LR", "RR")
    tc = np.nan_to_num(ts["tip_contact"]).astype(int)
    mv = np.nan_to_num(ts["moving_arm"], nan=-1).astype(int)
    for i in range(len(arms)):
        ax[3].fill_between(t, i - 0.4, i + 0.4, where=(mv == i), color="tab:red", step="mid",
                           label="transfer" if i == 0 else None)
        ax[3].fill_between(t, i - 0.15, i + 0.15, where=((tc >> i) & 1) == 1, color="tab:green", step="mid",
                           label="tip contact" if i == 0 else None)
    ax[3].set_yticks(range(4))
    ax[3].set_yticklabels(arms)
    ax[3].legend(loc="upper right", fontsize="small")
    events = [e for e in r["info"].get("events", []) if "." not in str(e[1])]
    start = "init" if r["method"] == "clm" else "approach"
    draw_timelines(ax[4], [("mode", events, float(t[-1]))], start=start)
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def _joints_figure(plt, ts: dict[str, np.ndarray], title: str):
    """Fig. 14 analogue: the RF and RR joint angles over a trial."""
    t = np.asarray(ts["t"])
    fig, ax = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
    for a, arm in zip(ax, ("RF", "RR")):
        for j in ("swing", "boom", "elbow"):
            a.plot(t, ts[f"{arm}_{j}"], label=j)
        a.set_ylabel(f"{arm} rad")
        a.legend(loc="upper left", fontsize="small")
    ax[1].set_xlabel("t s")
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def _elbow_figure(plt, ts: dict[str, np.ndarray], title: str):
    """Fig. 20 analogue: RF joint angles and elbow torque at the block."""
    t = np.asarray(ts["t"])
    fig, ax = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
    for j in ("swing", "boom", "elbow"):
        ax[0].plot(t, ts[f"RF_{j}"], label=j)
    ax[0].set_ylabel("RF rad")
    ax[0].legend(loc="upper left", fontsize="small")
    ax[1].plot(t, ts["tau_elbow_RF"])
    ax[1].set_ylabel("RF elbow torque N m")
    ax[1].set_xlabel("t s")
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def write_report(store, out_dir: Path, system: Any = None) -> Path:
    """HTML page: the table beside the paper, per-task time series with the mode timeline,
    mode timelines of every trial, joint phases (Fig. 14), elbow torque at the block (Fig. 20),
    the sweep, snapshots and the provenance block.

    Raises:
        ValueError: the store holds no octopus trials.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.report.page import Page, provenance_html
    from terrabench.report.timeline import draw_timelines
    from terrabench.report.variants import Defaults, find_variants, tag_rows

    if system is None:
        raise ValueError("write_report needs the system (OctopusSystem.report passes itself)")
    rows = store.rows(system="octopus")
    if not rows:
        raise ValueError(f"no octopus trials in {store.path}; run `terrabench run octopus` first")
    defaults = Defaults(system)
    variants = find_variants(rows, default_config=defaults, order=("clm", "ccm"),
                             label=lambda m: METHOD_LABEL.get(m, m))
    rows = tag_rows(rows, variants)
    page = Page(out_dir, "OCTOPUS: compound locomotion mode (CLM) vs crawler-only (CCM)")
    page.p(html.escape("Chen, Kamezaki et al., ROBOMECH J. 5:2 (2018). Each cell: ours (paper). "
                       "Max pitch and roll: the extreme over the trials; min margin: the lowest."))
    page.p(html.escape(CCM_NOTE))
    page.p(html.escape(MARGIN_NOTE))
    page.p(html.escape(HEADING_NOTE))
    order = {k: i for i, k in enumerate(TASK_ORDER)}
    tasks = [r for r in rows if not r["instance"].startswith("sweep-")]
    g = group(tasks)
    if g:
        page.h2("Tasks: ours (paper)")
        page.table(_lines(g, order), LINE_COLUMNS, csv_name="tasks.csv")
        page.h2("Mechanism: how each task was crossed (median over the trials, range in brackets)")
        page.p(html.escape("Targets (issue 28): " + "; ".join(f"{c} {t}" for _, c, t in MECHANISM)
                           + ". The climb is the paper's Fig. 9 (docs/octopus.md). A zero in the crawlers' "
                             "least share has two causes, told apart in the last two columns (from the "
                             "stored rows): a nose dropping onto its crawlers (one dynamic row) and, on the "
                             "terraces' short tread, the robot held up on its arm tips between the floor and "
                             "the second top with the crawlers in the air (a run of seconds)."))
        share = {r["key"]: climb_share(store.timeseries(r["key"]), r["method"]) for rs in g.values() for r in rs}
        mech = mechanism_lines(g, order, share)
        page.table(mech, list(mech[0]) if mech else ["task"], csv_name="mechanism.csv")
        _stages(page, plt, g, order, {v.id for v in variants if v.is_default})
        _releases(page, plt, store, g, order, {v.id for v in variants if v.is_default}, system)
    for key in sorted(g, key=_key_order(order)):
        rs = sorted(g[key], key=lambda r: r["seed"])
        r0 = rs[0]
        ts = store.timeseries(r0["key"])
        if not ts:
            continue
        slug = f"{key[0]}_{key[1]}".replace("@", "_")
        label = r0["label"]
        title = f"{key[0]} {label} seed {r0['seed']}: {r0['status']}"
        page.h3(html.escape(f"{key[0]} / {label}"))
        page.figure(_series_figure(plt, ts, r0, title), f"ts_{slug}.png",
                    html.escape(f"seed {r0['seed']}, {r0['status']}: {r0['info'].get('reason', '')}"), dpi=80)
        fig, ax = plt.subplots(figsize=(9, 0.45 * len(rs) + 1.2))
        t_end = {r["key"]: r["metrics"].get("sim_time", 0.0) for r in rs}
        start = "init" if r0["method"] == "clm" else "approach"
        draw_timelines(ax, [(f"seed {r['seed']} ({r['status']})",
                             [e for e in r["info"].get("events", []) if "." not in str(e[1])], t_end[r["key"]])
                            for r in rs], start=start)
        ax.set_title(f"{key[0]} {label}: controller modes per trial")
        page.figure(fig, f"modes_{slug}.png", "controller modes from each trial's stored events", dpi=80)
        if r0["method"] == "clm" and "RF_swing" in ts:
            if key[0] == "block-500":
                page.figure(_elbow_figure(plt, ts, f"{title}: RF arm at the block (Fig. 20)"), f"elbow_{slug}.png",
                            "RF joint angles and elbow torque (paper Fig. 20)", dpi=80)
            else:
                page.figure(_joints_figure(plt, ts, f"{title}: RF and RR joints (Fig. 14)"), f"joints_{slug}.png",
                            "RF and RR joint angles (paper Fig. 14)", dpi=80)
    rates = sweep_rates(rows)
    if rates:
        fig, ax = plt.subplots(figsize=(6, 4))
        for m, v in rates.items():
            ax.plot([h for h, _, _ in v], [s for _, s, _ in v], "o-", label=m)
        ax.set_xlabel("step height mm")
        ax.set_ylabel("success rate")
        ax.set_ylim(-0.05, 1.05)
        ax.legend()
        page.h2("Step-height sweep")
        page.figure(fig, "sweep.png", "success rate against step height", dpi=80)
        page.raw("<pre>" + html.escape("\n".join(f"{m}: " + ", ".join(f"{h} mm {s:.0%} (n={n})" for h, s, n in v)
                                                 for m, v in rates.items())) + "</pre>")
    cand = sorted((r for r in rows if r["instance"] == "step-400" and r["method"] == "clm"
                   and r["status"] == "success"), key=lambda r: r["seed"])
    if cand:
        from terrabench.benchmark.trial import TrialSpec

        r = cand[0]
        times = snapshot_times(store.timeseries(r["key"]))
        spec = TrialSpec("octopus", system.scenario("clm", "step-400"), "clm", "step-400", r["seed"], r["config"])
        page.h2(html.escape(f"Snapshots: CLM on the 400 mm step (seed {r['seed']})"))
        page.snapshots("clm_step400_snapshots.png",
                       html.escape("t = " + ", ".join(f"{t:.1f}" for t in times)
                                   + " s: walking, step detected (climb starts), mid-lift, release, the end"),
                       system, spec, times, width=320, height=240, track="chassis")
    _clips(page, system, rows, {v.id for v in variants if v.is_default}, store)
    page.h2("Provenance")
    page.raw(provenance_html(store, rows, system_id="octopus", default_config=defaults))
    return page.finish()


#: the climb stages the stage figure shows, with their trial metrics (task.py)
STAGE_METRICS = (("nose lift (Fig. 9e)", "crawler_load_share_lift"),
                 ("rear lift (eq. 28)", "crawler_load_share_rear_lift"),
                 ("drive on (S to L)", "crawler_load_share_drive_on"))


def _stages(page: Any, plt, g, order, default_ids: set[str]) -> None:
    """The crawlers' share of the normal load per stage of the default CLM climbs (each trial's least
    mean over a stage's runs; the median over the trials, the range as a bar), the issue's 0.5 drawn."""
    tasks = [key for key in sorted(g, key=_key_order(order))
             if g[key][0]["method"] == "clm" and g[key][0].get("variant") in default_ids
             and finite_metric(g[key], STAGE_METRICS[0][1]).size]
    if not tasks:
        return
    fig, ax = plt.subplots(figsize=(7.5, 3.4))
    width = 0.8 / len(STAGE_METRICS)
    for j, (name, metric) in enumerate(STAGE_METRICS):
        for i, key in enumerate(tasks):
            a = finite_metric(g[key], metric)
            if a.size:
                x, med = i + (j - (len(STAGE_METRICS) - 1) / 2) * width, float(np.median(a))
                ax.bar(x, med, width * 0.9, color=f"C{j}", label=name if i == 0 else None)
                ax.plot([x, x], [a.min(), a.max()], color="k", lw=1)
    ax.axhline(0.5, color="k", ls="--", lw=0.8, label="issue 28's > 0.5")
    ax.set_xticks(range(len(tasks)))
    ax.set_xticklabels([key[0] for key in tasks])
    ax.set_ylim(0, 1)
    ax.set_ylabel("crawlers' mean share of the load")
    ax.legend(fontsize="small", ncol=2, loc="upper right")
    fig.tight_layout()
    page.h2("The crawlers' share of the load per climb stage (CLM default)")
    page.p(html.escape("Each trial's least mean share over a stage of its climbs (the stored climb_stage), "
                       "the median over the trials as a bar, their range as a line. In the rear lift the rear "
                       "booms carry the rear (eq. 28) and the front booms press on the top (clm.climb_press); "
                       "docs/octopus.md, 'The climb's stages'."))
    page.figure(fig, "stages.png", "crawlers' share of the load per climb stage", dpi=80)


def _releases(page: Any, plt, store, g, order, default_ids: set[str], system: Any) -> None:
    """The releases of the default CLM climbs on the step and terrace tasks: a figure and a table
    (releases.csv) of where each came past the edge it climbed (the edges from the task's own
    :func:`.task.layout`) and how far the pitch rose after it."""
    from terrabench.systems.octopus.task import layout

    pts: dict[str, list[tuple[float, float, float]]] = {}
    edges: dict[str, tuple[float, ...]] = {}
    lines = []
    for key in sorted(g, key=_key_order(order)):
        rs = g[key]
        if key[0] not in RELEASE_TASKS or rs[0]["method"] != "clm" or rs[0].get("variant") not in default_ids:
            continue
        p = [x for r in rs for x in release_points(r["info"].get("events", []), store.timeseries(r["key"]))]
        last = layout(key[0], system.load_config(rs[0]["config"]), 0).edge  # the first edge is at 0
        es = edges[key[0]] = (0.0, last) if last > 0.0 else (0.0,)
        pts[key[0]] = p
        # each release against the edge it climbed: the last edge less than RELEASE_REACH ahead
        climbed = [max((e for e in es if e < x[1] + RELEASE_REACH), default=0.0) for x in p]
        for k, edge in enumerate(es):
            sel = [x for x, e in zip(p, climbed) if e == edge]
            if sel:
                xs, ds = np.array([x[1] - edge for x in sel]), np.array([x[2] for x in sel])
                lines.append({"task": key[0], "edge": f"{k + 1} (at {edge:.2f} m)", "releases": len(sel),
                              "chassis past the edge m": f"{np.median(xs):+.3f} ({xs.min():+.3f} to {xs.max():+.3f})",
                              f"pitch rise within {RELEASE_WATCH:g} s rad":
                                  f"{np.median(ds):.3f} ({ds.min():.3f}-{ds.max():.3f})"})
    if not lines:
        return
    page.h2("Releases: where each came, and the tip-back after it (CLM default)")
    page.p(html.escape("The paper releases the arms once S > L (eq. 5, crawler odometry). On the terraces "
                       "the first release comes with the chassis behind the first edge: the level front "
                       "flippers meet the second riser, the crawlers slip, S passes L with the body "
                       "still, and without its rear arms the robot tips back over the edge "
                       "(docs/octopus.md). Positions are the simulator's, along the approach axis."))
    page.figure(_release_figure(plt, pts, edges), "releases.png",
                "each release's position against the pitch rise that follows", dpi=80)
    page.table(lines, list(lines[0]), csv_name="releases.csv")


#: the paper's tasks that get a clip, with the mode shown (CLM everywhere; CCM where it fails the paper's way)
#: the cut clips: (task, method, from event, to event) of :meth:`OctopusSystem.clip_events`
CLIP_CUTS = (("step-400", "clm", "climb", "walk_on"), ("terrace2-front", "clm", "climb", "walk_on"),
             ("terrace2-side", "clm", "climb", "walk_on"), ("step-400", "ccm", "press", "end"))
CLIP_TASKS = (("step-400", "clm"), ("step-400", "ccm"), ("terrace2-front", "clm"), ("terrace2-side", "clm"),
              ("block-500", "clm"))


def _first_default(rows, inst: str, meth: str, default_ids: set[str] | None) -> dict[str, Any] | None:
    """The first stored seed of ``meth`` on ``inst``, of its default-settings run where there is one."""
    rs = sorted((r for r in rows if r["instance"] == inst and r["method"] == meth), key=lambda r: r["seed"])
    rs = [r for r in rs if r.get("variant") in (default_ids or ())] or rs
    return rs[0] if rs else None


def _clips(page: Any, system: Any, rows: list[dict[str, Any]], default_ids: set[str] | None = None,
           store: Any = None) -> None:
    """A clip of the first stored seed of each paper task (:data:`CLIP_TASKS`), re-run from its
    stored config: the whole trial, a frame every 0.2 simulated s at 25 fps (5x real time), from
    the task's own camera (the side camera on step tasks). Of a method run under several
    settings, the default-settings run (``default_ids``: the default variants' ids) is shown.
    Then (with ``store``) the climbs cut at their events (:data:`CLIP_CUTS`, the system's
    ``clip_events``; ``terrabench render octopus --at climb`` cuts the same) at 2.5x real time."""
    from terrabench.benchmark.trial import TrialSpec

    shown = False
    for inst, meth in CLIP_TASKS:
        r = _first_default(rows, inst, meth, default_ids)
        if r is None:
            continue
        if not shown:
            page.h2("Clips of the paper's tasks (5x real time)")
            shown = True
        spec = TrialSpec("octopus", r["scenario"], meth, inst, r["seed"], r["config"])
        span = float(r["metrics"].get("sim_time", 0.0) or 0.0) or 90.0
        page.clip(f"clip_{inst}_{meth}.mp4",
                  html.escape(f"{meth.upper()} on {inst} (seed {r['seed']}, stored status {r['status']}), "
                              f"0-{span:.0f} s"),
                  system, spec, span + 0.5, every=10, width=480, height=360, track="chassis")
    if store is None:
        return
    cut = False
    for inst, meth, a, b in CLIP_CUTS:
        r = _first_default(rows, inst, meth, default_ids)
        if r is None:
            continue
        ev = system.clip_events(r, store.timeseries(r["key"]))
        if a not in ev or b not in ev:
            continue
        if not cut:
            page.h2("The climbs cut at their events (2.5x real time)")
            cut = True
        t0, t1 = max(0.0, ev[a] - 2.0), min(ev["end"], ev[b] + 2.0)
        spec = TrialSpec("octopus", r["scenario"], meth, inst, r["seed"], r["config"])
        page.clip(f"cut_{inst}_{meth}.mp4",
                  html.escape(f"{meth.upper()} on {inst} (seed {r['seed']}, {r['status']}): {t0:.1f}-{t1:.1f} s, "
                              f"from 2 s before '{a}' ({ev[a]:.1f} s) to 2 s after '{b}' ({ev[b]:.1f} s); events "
                              + ", ".join(f"{k} {v:.1f} s" for k, v in sorted(ev.items(), key=lambda kv: kv[1])
                                          if k not in ("start", "end"))),
                  system, spec, t1 - t0, every=5, start=t0, width=640, height=480, track="chassis")
