"""OCTOPUS results: the table beside the paper's numbers and the HTML report."""

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
    ("block-500", "clm"): {"success": "passes (arm detects, rides over)", "max_pitch": None, "max_roll": None, "min_margin": None},
}
TASK_ORDER = ("step-400", "terrace2-front", "terrace2-side", "block-500")


def group(rows: list[dict[str, Any]]) -> dict[tuple[str, str], list[dict[str, Any]]]:
    out: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        out.setdefault((r["instance"], r["method"]), []).append(r)
    return out


def task_summary(rs: list[dict[str, Any]]) -> dict[str, Any]:
    """Successes, statuses and the extreme figures over a (task, method)'s trials."""
    m = lambda name: np.array([r["metrics"].get(name, np.nan) for r in rs], float)  # noqa: E731
    pitch, roll, margin = m("max_pitch"), m("max_roll"), m("min_margin")
    statuses: dict[str, int] = {}
    for r in rs:
        statuses[r["status"]] = statuses.get(r["status"], 0) + 1

    def ext(a):
        a = a[np.isfinite(a)]
        return float(a[np.argmax(np.abs(a))]) if len(a) else float("nan")

    return {"n": len(rs), "success": statuses.get("success", 0), "statuses": statuses,
            "max_pitch": ext(pitch), "max_roll": ext(roll),
            "min_margin": float(np.nanmin(margin)) if np.isfinite(margin).any() else float("nan")}


def _f(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, str):
        return v
    return "-" if v != v else f"{v:+.2f}"


def summary_table(rows: list[dict[str, Any]]):
    """Rich table: per task and mode, ours (paper's)."""
    from rich.table import Table

    t = Table(title="OCTOPUS: ours (paper). CCM is an automated stand-in for the paper's operators")
    for c in ("task", "mode", "n", "success", "statuses", "max pitch rad", "max roll rad", "min margin m"):
        t.add_column(c)
    g = group(rows)
    order = {k: i for i, k in enumerate(TASK_ORDER)}
    for (inst, meth) in sorted(g, key=lambda k: (order.get(k[0], 99), k[0], k[1])):
        s = task_summary(g[(inst, meth)])
        p = PAPER.get((inst, meth), {})
        st = ", ".join(f"{k} {v}" for k, v in sorted(s["statuses"].items()))
        t.add_row(inst, meth, str(s["n"]), f"{s['success']}/{s['n']} ({p.get('success', '-')})", st,
                  f"{_f(s['max_pitch'])} ({_f(p.get('max_pitch'))})", f"{_f(s['max_roll'])} ({_f(p.get('max_roll'))})",
                  f"{_f(s['min_margin'])} ({_f(p.get('min_margin'))})")
    return t


def sweep_rates(rows: list[dict[str, Any]]) -> dict[str, list[tuple[int, float, int]]]:
    """method -> [(height mm, success rate, n)] of the sweep rows."""
    out: dict[str, dict[int, list[int]]] = {}
    for r in rows:
        if not r["instance"].startswith("sweep-h"):
            continue
        h = int(r["instance"][len("sweep-h"):])
        out.setdefault(r["method"], {}).setdefault(h, []).append(1 if r["status"] == "success" else 0)
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


def _snapshots_html(store, rows: list[dict[str, Any]], out_dir: Path) -> str:
    """One row of rendered frames of the first successful CLM step-400 trial (seed order)."""
    try:
        from terrabench.report.render import frame_strip, snapshots
    except ImportError:
        return "<h2>Snapshots</h2><p>skipped: terrabench.report.render is not available.</p>"
    from terrabench.benchmark.trial import TrialSpec
    from terrabench.systems.octopus.scenarios import SYSTEM

    cand = sorted((r for r in rows if r["instance"] == "step-400" and r["method"] == "clm" and r["status"] == "success"),
                  key=lambda r: r["seed"])
    if not cand:
        return "<h2>Snapshots</h2><p>no successful CLM step-400 trial stored.</p>"
    r = cand[0]
    times = snapshot_times(store.timeseries(r["key"]))
    spec = TrialSpec("octopus", SYSTEM.scenario("clm", "step-400"), "clm", "step-400", r["seed"], r["config"])
    try:
        frames = snapshots(SYSTEM, spec, times, width=320, height=240, track="chassis")
    except Exception as e:  # no headless GL on this machine: the report still builds
        return f"<h2>Snapshots</h2><p>skipped: {html.escape(str(e))}</p>"
    frame_strip(frames, out_dir / "clm_step400_snapshots.png")
    return ("<h2>Snapshots: CLM on the 400 mm step (seed %d)</h2><p>t = %s s: walking, step detected (climb "
            "starts), mid-lift (front flippers on the top), release, the end.</p>"
            "<img src='clm_step400_snapshots.png'>" % (r["seed"], ", ".join(f"{t:.1f}" for t in times)))


def write_report(store, out_dir: Path) -> Path:
    """HTML page: the table, pitch/roll/margin over time per task, gait timeline, sweep, snapshots."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir.mkdir(parents=True, exist_ok=True)
    rows = store.rows(system="octopus")
    parts = ["<html><head><meta charset='utf-8'><title>OCTOPUS report</title></head><body>",
             "<h1>OCTOPUS: compound locomotion mode (CLM) vs crawler-only (CCM)</h1>",
             "<p>CCM here is an automated flipper step-climbing controller (Nagatani/Okada style), "
             "not the paper's two human operators. Stability margin: static, COG projection to the "
             "hull of all ground contacts (evaluation only).</p>"]
    g = group([r for r in rows if not r["instance"].startswith("sweep-")])
    parts.append("<h2>Tasks: ours (paper)</h2><table border=1 cellpadding=4><tr><th>task</th><th>mode</th>"
                 "<th>success</th><th>statuses</th><th>max pitch</th><th>max roll</th><th>min margin</th></tr>")
    order = {k: i for i, k in enumerate(TASK_ORDER)}
    for key in sorted(g, key=lambda k: (order.get(k[0], 99), k[1])):
        s, p = task_summary(g[key]), PAPER.get(key, {})
        st = ", ".join(f"{k} {v}" for k, v in sorted(s["statuses"].items()))
        parts.append(f"<tr><td>{key[0]}</td><td>{key[1]}</td><td>{s['success']}/{s['n']} ({html.escape(str(p.get('success', '-')))})</td>"
                     f"<td>{st}</td><td>{_f(s['max_pitch'])} ({_f(p.get('max_pitch'))})</td>"
                     f"<td>{_f(s['max_roll'])} ({_f(p.get('max_roll'))})</td><td>{_f(s['min_margin'])} ({_f(p.get('min_margin'))})</td></tr>")
    parts.append("</table>")
    # time series of seed 0 per task and method (Figs. 12, 13, 16, 18 analogues) + gait timeline
    for key in sorted(g, key=lambda k: (order.get(k[0], 99), k[1])):
        r0 = sorted(g[key], key=lambda r: r["seed"])[0]
        ts = store.timeseries(r0["key"])
        if not ts:
            continue
        fig, ax = plt.subplots(4, 1, figsize=(8, 8), sharex=True)
        ax[0].plot(ts["t"], ts["pitch"], label="pitch"); ax[0].plot(ts["t"], ts["roll"], label="roll")
        ax[0].set_ylabel("rad"); ax[0].legend()
        ax[1].plot(ts["t"], ts["margin"]); ax[1].set_ylabel("margin m"); ax[1].axhline(0, color="k", lw=0.5)
        ax[2].plot(ts["t"], ts["s"], label="progress s"); ax[2].plot(ts["t"], ts["z"], label="z")
        ax[2].set_ylabel("m"); ax[2].legend()
        arms = ("LF", "RF", "LR", "RR")
        tc = np.nan_to_num(ts["tip_contact"]).astype(int)
        mv = np.nan_to_num(ts["moving_arm"], nan=-1).astype(int)
        for i, a in enumerate(arms):
            ax[3].fill_between(ts["t"], i - 0.4, i + 0.4, where=(mv == i), color="tab:red", step="mid", label="transfer" if i == 0 else None)
            ax[3].fill_between(ts["t"], i - 0.15, i + 0.15, where=((tc >> i) & 1) == 1, color="tab:green", step="mid", label="tip contact" if i == 0 else None)
        ax[3].set_yticks(range(4)); ax[3].set_yticklabels(arms); ax[3].set_xlabel("t s"); ax[3].legend(loc="upper right")
        fig.suptitle(f"{key[0]} {key[1]} seed {r0['seed']}: {r0['status']}")
        name = f"ts_{key[0]}_{key[1]}.png"
        fig.tight_layout(); fig.savefig(out_dir / name, dpi=80); plt.close(fig)
        parts.append(f"<h3>{key[0]} / {key[1]} (seed {r0['seed']}, {r0['status']}: {html.escape(str(r0['info'].get('reason', '')))})</h3><img src='{name}'>")
    rates = sweep_rates(rows)
    if rates:
        fig, ax = plt.subplots(figsize=(6, 4))
        for m, v in rates.items():
            ax.plot([h for h, _, _ in v], [s for _, s, _ in v], "o-", label=m)
        ax.set_xlabel("step height mm"); ax.set_ylabel("success rate"); ax.set_ylim(-0.05, 1.05); ax.legend()
        fig.tight_layout(); fig.savefig(out_dir / "sweep.png", dpi=80); plt.close(fig)
        parts.append("<h2>Step-height sweep</h2><img src='sweep.png'><pre>"
                     + "\n".join(f"{m}: " + ", ".join(f"{h} mm {s:.0%} (n={n})" for h, s, n in v) for m, v in rates.items())
                     + "</pre>")
    parts.append(_snapshots_html(store, rows, out_dir))
    parts.append("</body></html>")
    path = out_dir / "index.html"
    path.write_text("\n".join(parts))
    return path
