"""Tables and figures of the beams system, read only from stored trial rows.

Paper reference values are shipped in :data:`PAPER` (Xuan, Wang & Li, Tables 1-4, Sec. III-A,
III-D, IV) and shown beside ours.
"""

from __future__ import annotations

import html
import math
import os
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

from .model import critical_stiffness

#: The paper's numbers. Estimation tables: {variant: {instance: {param: (estimate, rel. error)}}}.
PAPER: dict[str, Any] = {
    "source": "Xuan, Wang & Li, 'Environmental force sensing enables robots to traverse cluttered obstacles "
              "with interaction', Tables 1-4 and Secs. III-A, III-D, IV",
    "k0": 0.028,
    "estimation": {
        "estimate-4": {  # Table 1
            "sigma5-ts300": {"k1": (0.264, .05), "k2": (0.283, .05), "hb1": (1.57, .31), "hb2": (1.39, .28)},
            "sigma10-ts300": {"k1": (0.273, .09), "k2": (0.355, .30), "hb1": (3.33, .67), "hb2": (9.77, 1.95)},
            "sigma20-ts300": {"k1": (0.253, .01), "k2": (0.306, .13), "hb1": (1.40, .28), "hb2": (5.14, 1.02)},
            "sigma50-ts300": {"k1": (0.274, .10), "k2": (0.344, .27), "hb1": (1.82, .36), "hb2": (6.84, 1.37)},
        },
        "estimate-3": {  # Table 2 and Table 4
            "sigma5-ts300": {"k1": (0.257, .03), "k2": (0.278, .03), "hb": (0.92, .18)},
            "sigma10-ts300": {"k1": (0.243, .03), "k2": (0.263, .03), "hb": (1.37, .27)},
            "sigma20-ts300": {"k1": (0.239, .05), "k2": (0.259, .04), "hb": (0.58, .12)},
            "sigma50-ts300": {"k1": (0.336, .34), "k2": (0.258, .33), "hb": (7.34, 1.47)},
            "sigma20-ts50": {"k1": (0.090, .24), "k2": (0.100, .63), "hb": (22.0, 4.40)},
            "sigma20-ts100": {"k1": (0.229, .08), "k2": (0.248, .08), "hb": (1.92, .38)},
            "sigma20-ts600": {"k1": (0.270, .08), "k2": (0.290, .07), "hb": (0.79, .16)},
        },
        "estimate-2": {  # Table 3
            "sigma5-ts300": {"k1": (0.250, .00), "k2": (0.270, .00)},
            "sigma10-ts300": {"k1": (0.252, .01), "k2": (0.273, .01)},
            "sigma20-ts300": {"k1": (0.244, .02), "k2": (0.265, .02)},
            "sigma50-ts300": {"k1": (0.262, .05), "k2": (0.284, .05)},
        },
    },
    "open_loop": {"stiff-f0.1": "stuck", "flimsy-f0.1": "stuck", "stiff-f1": "fell (flipped over)",
                  "flimsy-f1": "success (traversed)"},
    "energy_mJ": {("stiff", "interact"): 60, ("stiff", "avoid"): 52, ("flimsy", "interact"): 21,
                  ("flimsy", "avoid"): 52},
    "mode": {"stiff": "roll", "flimsy": "pitch"},
    "experiment": {"k": 0.67, "tau0": 0.21, "k_true": 0.78, "tau0_true": 0.19},
}


def _by(rows, scenario):
    return [r for r in rows if r["scenario"] == scenario]


def reading(r) -> str:
    """The gap reading a stored row ran under ("edge" for rows stored before the reading existed)."""
    lay = (r.get("config") or {}).get("layout")
    return lay.get("gap_reading", "edge") if isinstance(lay, dict) else "edge"


def readings_present(rows) -> list[str]:
    from .model import GAP_READINGS
    have = {reading(r) for r in rows}
    return [g for g in GAP_READINGS if g in have]


def _only(rows, rd):
    return [r for r in rows if reading(r) == rd]


#: The sentence of the paper each reading rests on.
READING_BASIS = {
    "edge": "Sec. II-A: 'The gap width between two beams is d = 0.12 m, which is narrower than the width of the "
            "robot' (a gap's width is the free space between the beams)",
    "centre": "Sec. II-G: 'For the roll mode, the potential energy reaches the maximum when the robot rolls until "
              "no contact ... PE_roll ~ M g h_c' (needs a free gap well below 2b; d between centre lines gives "
              "d - w = 0.07 m)",
}


def paper_vs_readings(rows) -> list[dict[str, Any]]:
    """One line per result of the paper: the paper's value and ours under each stored reading."""
    rds = readings_present(rows)
    lines: list[dict[str, Any]] = []

    def add(result, paper, fn):
        ln = {"result": result, "paper": paper}
        for rd in rds:
            try:
                ln[rd] = fn(_only(rows, rd))
            except Exception:  # noqa: BLE001 - a missing group shows as "-"
                ln[rd] = "-"
        lines.append(ln)

    def bar(rs, gap_inst, key, nd=1):
        r = next((r for r in _by(rs, "beams/barriers-v1") if r["instance"] == gap_inst), None)
        return "-" if r is None else _fmt(r["metrics"].get(key), nd)

    add("k_0 formula M g h_c / arccos(H/L)^2 (N m/rad)", "0.028", lambda rs: f"{critical_stiffness():.4f}")
    add("landscape crossover k (pitch = roll barrier) at d = 0.12 (N m/rad)", "0.028 (k_0)",
        lambda rs: bar(rs, "gap0.12", "k_cross", 4))
    add("roll barrier at d = 0.12 (mJ)", "~ M g h_c = 39", lambda rs: bar(rs, "gap0.12", "roll_mJ"))
    add("pitch barrier k = 0.01 / 0.25 at d = 0.12 (mJ)", "k arccos(H/L)^2 = 14 / 352",
        lambda rs: bar(rs, "gap0.12", "pitch_low_mJ") + " / " + bar(rs, "gap0.12", "pitch_high_mJ"))
    for inst in ("stiff-f0.1", "flimsy-f0.1", "stiff-f1", "flimsy-f1"):
        def ol(rs, inst=inst):
            r = next((r for r in _by(rs, "beams/open-loop-v1") if r["instance"] == inst), None)
            if r is None:
                return "-"
            m = r["metrics"]
            return (f"{r['status']} (pitch {_fmt(m.get('max_pitch_deg'), 0)}/{_fmt(m.get('min_pitch_deg'), 0)} deg)")
        add(f"open loop {inst.replace('-f', ' F_x=')} N", PAPER["open_loop"][inst], ol)
    for case in ("stiff", "flimsy"):
        def mode(rs, case=case):
            tr = [r for r in _by(rs, "beams/traversal-v1") if r["instance"] == case and r["method"] == "interact"]
            if not tr:
                return "-"
            roll = sum(r["metrics"].get("mode_roll", 0) == 1 for r in tr)
            succ = sum(r["status"] == "success" for r in tr)
            return f"roll {roll}/{len(tr)}, pitch {len(tr) - roll}/{len(tr)} (success {succ}/{len(tr)})"
        add(f"mode choice {case} (interact, noise seeds)", PAPER["mode"][case], mode)
    for case, m in (("stiff", "avoid"), ("stiff", "interact"), ("flimsy", "interact"), ("flimsy", "avoid")):
        def en(rs, case=case, m=m):
            tr = [r for r in _by(rs, "beams/traversal-v1") if r["instance"] == case and r["method"] == m]
            mu, sd, n = _ms([r["metrics"].get("energy_mJ") for r in tr])
            return "-" if n == 0 else (f"{mu:.1f}" if n == 1 else f"{mu:.1f}+-{sd:.1f} (n={n})")
        add(f"energy {case} {m} (mJ)", str(PAPER["energy_mJ"][(case, m)]), en)
    for case in ("stiff", "flimsy"):
        def dl(rs, case=case):
            out = []
            for d in (100, 300, 600):
                tr = [r for r in _by(rs, "beams/delay-v1") if r["instance"] == f"{case}-d{d}"]
                mu, _, n = _ms([r["metrics"].get("energy_mJ") for r in tr])
                out.append("-" if n == 0 else f"{mu:.1f}")
            return " / ".join(out)
        add(f"delay 100/300/600 ms energy, {case} (mJ)", "cost rises with delay", dl)

    def cc(rs):
        c = _by(rs, "beams/contact-check-v1")
        if not c:
            return "-"
        th = max(r["metrics"].get("theta_err_max_deg", math.nan) for r in c)
        fm = max(r["metrics"].get("force_rel_err_median", math.nan) for r in c)
        fx = max(r["metrics"].get("force_rel_err_max", math.nan) for r in c)
        sth = max(r["metrics"].get("soft_theta_err_max_deg", math.nan) for r in c)
        return (f"theta max {th:.2f} deg, |F| median {100 * fm:.1f} % (max {100 * fx:.1f} %); "
                f"soft contact theta max {sth:.0f} deg")
    add("MuJoCo cross-check, 5 poses (worst pose)", "(not in paper)", cc)
    return lines


def _ms(vals):
    v = np.asarray([x for x in vals if x is not None and np.isfinite(x)], float)
    if v.size == 0:
        return math.nan, math.nan, 0
    return float(v.mean()), float(v.std(ddof=1)) if v.size > 1 else 0.0, int(v.size)


def estimation_table(rows) -> list[dict[str, Any]]:
    """One line per (method, instance): mean/std/median of estimates and errors, seed 0, paper."""
    out = []
    groups = defaultdict(list)
    for r in _by(rows, "beams/estimation-v1"):
        if r["status"] == "done":
            groups[(r["method"], r["instance"])].append(r)
    for (m, inst), rs in sorted(groups.items()):
        rs = sorted(rs, key=lambda r: r["seed"])
        line: dict[str, Any] = {"method": m, "instance": inst, "n_seeds": len(rs)}
        for p, key, err in (("k1", "k1_hat", "e_k1"), ("k2", "k2_hat", "e_k2"), ("hb1", "hb1_hat_mm", "e_hb1"),
                            ("hb2", "hb2_hat_mm", "e_hb2")):
            if m == "estimate-2" and p.startswith("hb"):
                continue
            if m == "estimate-3" and p == "hb2":
                continue
            vals = [r["metrics"][key] for r in rs]
            errs = [r["metrics"][err] for r in rs]
            mu, sd, _ = _ms(vals)
            emu, esd, _ = _ms(errs)
            line[f"{p}_seed0"] = vals[0]
            line[f"{p}_mean"], line[f"{p}_std"] = mu, sd
            line[f"e_{p}_seed0"] = errs[0]
            line[f"e_{p}_mean"], line[f"e_{p}_std"] = emu, esd
            line[f"e_{p}_median"] = float(np.median(errs))
            ref = PAPER["estimation"].get(m, {}).get(inst, {})
            pk = "hb" if (m == "estimate-3" and p == "hb1") else p
            if pk in ref:
                line[f"{p}_paper"], line[f"e_{p}_paper"] = ref[pk]
        out.append(line)
    return out


def _fmt(v, nd=3):
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return "-"
    return f"{v:.{nd}f}" if isinstance(v, float) else str(v)


def summarize(rows: list[dict[str, Any]]):
    """Rich tables: the paper's results under each gap reading, then per reading: estimation beside
    the paper, traversal energies, open loop, delay, experiment, MuJoCo check."""
    from rich.console import Group
    from rich.table import Table

    rds = readings_present(rows)
    parts = []
    if rows:
        t = Table(title="The paper's results under each reading of the gap d (layout.gap_reading)")
        for c in ["result", "paper"] + rds:
            t.add_column(c)
        for ln in paper_vs_readings(rows):
            t.add_row(ln["result"], ln["paper"], *[ln[rd] for rd in rds])
        parts.append(t)
    for rd in rds:
        parts.extend(_tables(_only(rows, rd), f"[{rd}] "))
    if not parts:
        return Table(title="beams: no stored rows")
    return Group(*parts)


def _tables(rows, tag: str) -> list:
    from rich.table import Table

    parts = []
    est = estimation_table(rows)
    if est:
        t = Table(title=tag + "Beam estimation: relative errors, mean +- std over seeds (paper's single draw)")
        for c in ("method", "instance", "n", "e_k1", "e_k2", "e_hb1", "e_hb2"):
            t.add_column(c)
        for ln in est:
            cells = []
            for p in ("k1", "k2", "hb1", "hb2"):
                if f"e_{p}_mean" in ln:
                    cells.append(f"{100 * ln[f'e_{p}_mean']:.0f}+-{100 * ln[f'e_{p}_std']:.0f}% "
                                 f"({_fmt(100 * ln[f'e_{p}_paper'], 0) if f'e_{p}_paper' in ln else '-'}%)")
                else:
                    cells.append("")
            t.add_row(ln["method"], ln["instance"], str(ln["n_seeds"]), *cells)
        parts.append(t)
    trav = _by(rows, "beams/traversal-v1")
    if trav:
        t = Table(title=tag + "Traversal: status, mode, energy eq. 11 (paper mJ)")
        for c in ("case", "method", "n", "success", "mode roll %", "energy mJ", "paper mJ"):
            t.add_column(c)
        for (inst, m), rs in sorted(_groupby(trav, ("instance", "method")).items()):
            mu, sd, n = _ms([r["metrics"].get("energy_mJ") for r in rs])
            succ = sum(r["status"] == "success" for r in rs)
            roll = np.mean([r["metrics"].get("mode_roll", np.nan) for r in rs]) * 100
            t.add_row(inst, m, str(len(rs)), f"{succ}/{len(rs)}", f"{roll:.0f}", f"{mu:.1f}+-{sd:.1f}",
                      str(PAPER["energy_mJ"].get((inst, m), "-")))
        parts.append(t)
    ol = _by(rows, "beams/open-loop-v1")
    if ol:
        t = Table(title=tag + "Open loop (Sec. III-A)")
        for c in ("case", "status", "max pitch deg", "paper"):
            t.add_column(c)
        for r in sorted(ol, key=lambda r: r["instance"]):
            t.add_row(r["instance"], r["status"], _fmt(r["metrics"].get("max_pitch_deg"), 1),
                      PAPER["open_loop"].get(r["instance"], "-"))
        parts.append(t)
    dl = _by(rows, "beams/delay-v1")
    if dl:
        t = Table(title=tag + "Sensory delay (Sec. III-E): energy mJ mean+-std, start pitch deg")
        for c in ("case", "n", "success", "energy mJ", "start pitch deg", "mode roll %"):
            t.add_column(c)
        for inst, rs in sorted(_groupby(dl, ("instance",)).items(), key=lambda kv: _delay_key(kv[0][0])):
            mu, sd, n = _ms([r["metrics"].get("energy_mJ") for r in rs])
            pm, _, _ = _ms([r["metrics"].get("start_pitch_deg") for r in rs])
            roll = np.mean([r["metrics"].get("mode_roll", np.nan) for r in rs]) * 100
            t.add_row(inst[0], str(len(rs)), f"{sum(r['status'] == 'success' for r in rs)}/{len(rs)}",
                      f"{mu:.1f}+-{sd:.1f}", f"{pm:.1f}", f"{roll:.0f}")
        parts.append(t)
    ex = _by(rows, "beams/experiment-v1")
    if ex:
        t = Table(title=tag + "Experiment variant (eq. 12), truth k=0.78, tau0=0.19; paper robot: 0.67, 0.21")
        for c in ("instance", "n", "k mean+-std", "tau0 mean+-std", "e_k", "e_tau0"):
            t.add_column(c)
        for inst, rs in sorted(_groupby(ex, ("instance",)).items()):
            rs = [r for r in rs if r["status"] == "done"]
            k = _ms([r["metrics"]["k_hat"] for r in rs])
            tau = _ms([r["metrics"]["tau0_hat"] for r in rs])
            ek = _ms([r["metrics"]["e_k"] for r in rs])
            et = _ms([r["metrics"]["e_tau0"] for r in rs])
            t.add_row(inst[0], str(len(rs)), f"{k[0]:.3f}+-{k[1]:.3f}", f"{tau[0]:.3f}+-{tau[1]:.3f}",
                      f"{100 * ek[0]:.0f}%", f"{100 * et[0]:.0f}%")
        parts.append(t)
    cc = _by(rows, "beams/contact-check-v1")
    if cc:
        t = Table(title=tag + "MuJoCo cross-check (stiff contact; soft contact in brackets)")
        for c in ("pose", "theta err mean/max deg", "force rel err median/max", "force dir err max deg"):
            t.add_column(c)
        for r in sorted(cc, key=lambda r: r["instance"]):
            m = r["metrics"]
            t.add_row(r["instance"],
                      f"{_fmt(m.get('theta_err_mean_deg'), 2)}/{_fmt(m.get('theta_err_max_deg'), 2)} "
                      f"[{_fmt(m.get('soft_theta_err_mean_deg'), 1)}/{_fmt(m.get('soft_theta_err_max_deg'), 1)}]",
                      f"{_fmt(m.get('force_rel_err_median'), 3)}/{_fmt(m.get('force_rel_err_max'), 3)} "
                      f"[{_fmt(m.get('soft_force_rel_err_median'), 2)}/{_fmt(m.get('soft_force_rel_err_max'), 2)}]",
                      f"{_fmt(m.get('force_dir_err_max_deg'), 2)} [{_fmt(m.get('soft_force_dir_err_max_deg'), 1)}]")
        parts.append(t)
    bars = _by(rows, "beams/barriers-v1")
    if bars:
        t = Table(title=tag + "Landscape barriers vs the gap d (Sec. II-G; h_b = 0, k1 = k2)")
        for c in ("d m", "free gap m", "roll to clear deg", "roll mJ", "pitch k=0.01 mJ", "pitch k=0.25 mJ",
                  "crossover k", "mode k=0.01 / 0.25"):
            t.add_column(c)
        for r in sorted(bars, key=lambda r: r["metrics"].get("gap", 0)):
            m = r["metrics"]
            def mode(pk, m=m):
                if not np.isfinite(m.get("roll_mJ", np.nan)):
                    return "-"
                return "pitch" if m[pk] < m["roll_mJ"] else "roll"
            t.add_row(_fmt(m.get("gap"), 2), _fmt(m.get("inner_gap"), 3), _fmt(m.get("roll_clear_deg"), 1),
                      _fmt(m.get("roll_mJ"), 1), _fmt(m.get("pitch_low_mJ"), 1), _fmt(m.get("pitch_high_mJ"), 1),
                      _fmt(m.get("k_cross"), 4), f"{mode('pitch_low_mJ')} / {mode('pitch_high_mJ')}")
        parts.append(t)
    return parts


def _groupby(rows, keys):
    g = defaultdict(list)
    for r in rows:
        g[tuple(r[k] for k in keys)].append(r)
    return g


def _delay_key(inst: str):
    case, d = inst.split("-d")
    return case, int(d)


# --------------------------------------------------------------------------- HTML report

def write_report(store, out_dir: Path, system: Any) -> Path:
    """Write ``out_dir/index.html`` plus PNG figures and CSV tables from the store's beams rows.

    Rows are split by their settings (:func:`terrabench.report.variants.settings_groups`, the gap
    reading aside, which is compared side by side): each group with settings other than the
    defaults gets its own section, files suffixed with the group's slug.

    Raises:
        ValueError: the store holds no beams trials, or ``out_dir`` cannot be written.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.report.page import Page, provenance_html
    from terrabench.report.variants import Defaults, settings_groups

    rows = store.rows(system="beams")
    if not rows:
        raise ValueError(f"no beams trials in {store.path}; run `terrabench run beams` first")
    page = Page(out_dir, "Beam traversal with environmental force sensing")
    out_dir = page.out_dir
    page.p(html.escape(PAPER["source"]))
    defaults = Defaults(system)
    groups = settings_groups(rows, defaults, ignore=("layout.gap_reading",))
    k0 = critical_stiffness()
    page.p(f"Critical stiffness k<sub>0</sub> = M g h<sub>c</sub> / arccos(H/L)<sup>2</sup> = "
           f"{k0:.4f} N m/rad (paper: 0.028). Rows in store: {len(rows)} in {len(groups)} settings group(s).")
    for rd in readings_present(rows):
        page.p(f"<b>{rd} reading</b> rests on {html.escape(READING_BASIS[rd])}.")
    for g in groups:
        _group_section(page, store, list(g.rows), g.label, g.slug, plt)
    page.h2("Provenance")
    page.raw(provenance_html(store, rows, system_id="beams", default_config=defaults))
    return page.finish()


def _group_section(page: Any, store: Any, rows: list[dict[str, Any]], label: str, slug: str, plt: Any) -> None:
    """One settings group: the paper-vs-ours table, the summary tables, every figure and CSV."""
    out_dir = page.out_dir
    page.h2(f"Settings: {html.escape(label)}")

    def _write_csv(path: Path, lines: list[dict[str, Any]]) -> None:
        if lines:
            page.csv(path.name, lines, list(dict.fromkeys(k for ln in lines for k in ln)))

    def save(fig, name, caption, rd=None):
        if rd is not None and rd != "edge":
            name = name.replace(".", f"_{rd}.", 1)
        name = name.replace(".", f"{slug}.", 1)
        if rd is not None:
            caption = f"[{rd} reading] {caption}"
        fig.tight_layout()
        page.figure(fig, name, html.escape(caption))

    all_rows = rows
    for rd in readings_present(all_rows) or ["edge"]:
        rows = _only(all_rows, rd)
        tag = rd

        def save_rd(fig, name, caption, tag=tag):
            save(fig, name, caption, tag)

        def nm(name, rd=rd):
            name = name if rd == "edge" else name.replace(".", f"_{rd}.", 1)
            return name.replace(".", f"{slug}.", 1)

        # ---- estimation
        est = estimation_table(rows)
        _write_csv(out_dir / nm("estimation.csv"), est)
        if est:
            fig, axes = plt.subplots(1, 2, figsize=(11, 4))
            for m, mk in (("estimate-4", "o"), ("estimate-3", "s"), ("estimate-2", "^")):
                ln = [x for x in est if x["method"] == m and x["instance"].endswith("ts300")]
                ln.sort(key=lambda x: int(x["instance"].split("-")[0][5:]))
                sig = [int(x["instance"].split("-")[0][5:]) for x in ln]
                if not ln:
                    continue
                ek = [(x["e_k1_mean"] + x["e_k2_mean"]) / 2 for x in ln]
                eks = [(x["e_k1_std"] + x["e_k2_std"]) / 2 for x in ln]
                axes[0].errorbar(sig, np.multiply(ek, 100), np.multiply(eks, 100), marker=mk, capsize=3,
                                 label=f"{m} (ours)")
                paper = [PAPER["estimation"][m].get(x["instance"], {}) for x in ln]
                axes[0].plot(sig, [100 * (p["k1"][1] + p["k2"][1]) / 2 if p else np.nan for p in paper], mk + ":",
                             color="gray", alpha=.7, label=f"{m} (paper, 1 draw)")
                if m != "estimate-2":
                    eh = [x["e_hb1_mean"] for x in ln]
                    ehs = [x["e_hb1_std"] for x in ln]
                    axes[1].errorbar(sig, np.multiply(eh, 100), np.multiply(ehs, 100), marker=mk, capsize=3,
                                     label=f"{m} (ours)")
                    axes[1].plot(sig,
                                 [100 * (p.get("hb1", p.get("hb", (0, np.nan)))[1]) if p else np.nan for p in paper],
                                 mk + ":", color="gray", alpha=.7, label=f"{m} (paper)")
            axes[0].set(xlabel="noise sigma (%)", ylabel="stiffness rel. error (%) mean of k1,k2", xscale="log")
            axes[1].set(xlabel="noise sigma (%)", ylabel="deflection-height error / 5 mm (%)", xscale="log")
            for a in axes:
                a.legend(fontsize=7)
                a.grid(alpha=.3)
            save_rd(fig, "estimation_vs_noise.png", "Estimation error vs noise (T_s = 300 ms); bars = std over seeds, "
                                                 "grey = the paper's single draw (Tables 1-3).")
            fig, ax = plt.subplots(figsize=(6, 4))
            for m, mk in (("estimate-4", "o"), ("estimate-3", "s"), ("estimate-2", "^")):
                ln = [x for x in est if x["method"] == m and x["instance"].startswith("sigma20")]
                ln.sort(key=lambda x: int(x["instance"].split("ts")[1]))
                if ln:
                    ts = [int(x["instance"].split("ts")[1]) for x in ln]
                    ax.errorbar(ts, [100 * (x["e_k1_mean"] + x["e_k2_mean"]) / 2 for x in ln],
                                [100 * (x["e_k1_std"] + x["e_k2_std"]) / 2 for x in ln], marker=mk, capsize=3, label=m)
            p4 = PAPER["estimation"]["estimate-3"]
            p4_k = [100 * (p4[f"sigma20-ts{t}"]["k1"][1] + p4[f"sigma20-ts{t}"]["k2"][1]) / 2
                    for t in (50, 100, 300, 600)]
            ax.plot([50, 100, 300, 600], p4_k, "s:", color="gray", label="estimate-3 paper (Table 4)")
            ax.set(xlabel="sensing time T_s (ms)", ylabel="stiffness rel. error (%)", xscale="log")
            ax.legend(fontsize=7)
            ax.grid(alpha=.3)
            save_rd(fig, "estimation_vs_sensing_time.png",
                    "Stiffness error vs sensing time at sigma = 20 % (Table 4).")
            ex_row = next((r for r in rows if r["scenario"] == "beams/estimation-v1"
                           and r["instance"] == "sigma20-ts300" and r["seed"] == 0 and r["method"] == "estimate-3"),
                          None)
            if ex_row:
                ts = store.timeseries(ex_row["key"])
                fig, ax = plt.subplots(figsize=(6, 3.5))
                ax.plot(ts["t"] * 1e3, ts["fx"], ".", label="sensed F_x (sigma 20 %)")
                ax.plot(ts["t"] * 1e3, ts["fx_clean"], "-", label="model F_x")
                ax.set(xlabel="time since contact (ms)", ylabel="force on robot (N)")
                ax.legend()
                save_rd(fig, "sensed_force.png", "Sensed total beam force (cf. paper Fig. 3), trial " + ex_row["key"])
        # ---- traversal traces, landscape slices
        trav = _by(rows, "beams/traversal-v1")
        lines = []
        for (inst, m), rs in sorted(_groupby(trav, ("instance", "method")).items()):
            mu, sd, n = _ms([r["metrics"].get("energy_mJ") for r in rs])
            pipeline_s = [(r["info"].get("wall_s") or {}).get("total_s", r["metrics"].get("total_s")) for r in rs]
            lines.append({"case": inst, "method": m, "n": len(rs), "success": sum(r["status"] == "success" for r in rs),
                          "mode_roll_frac": float(np.mean([r["metrics"].get("mode_roll", np.nan) for r in rs])),
                          "energy_mJ_mean": mu, "energy_mJ_std": sd, "paper_mJ": PAPER["energy_mJ"].get((inst, m)),
                          "paper_mode": PAPER["mode"].get(inst) if m == "interact" else "roll",
                          "pipeline_s_mean": _ms(pipeline_s)[0]})
        _write_csv(out_dir / nm("traversal.csv"), lines)
        if trav:
            fig, axes = plt.subplots(3, 1, figsize=(9, 8), sharex=True)
            for r in sorted(trav, key=lambda r: (r["instance"], r["method"])):
                if r["seed"] != 0:
                    continue
                ts = store.timeseries(r["key"])
                lab = f"{r['instance']} {r['method']} ({r['status']})"
                axes[0].plot(ts["t"], ts["x"], label=lab)
                axes[1].plot(ts["t"], np.degrees(ts["alpha"]), label=lab)
                axes[2].plot(ts["t"], np.degrees(ts["beta"]), label=lab)
            axes[0].set_ylabel("x (m)")
            axes[1].set_ylabel("roll (deg)")
            axes[2].set_ylabel("pitch (deg)")
            axes[2].set_xlabel("time (s)")
            axes[0].legend(fontsize=7)
            save_rd(fig, "traversal_states.png",
                    "State traces of the controlled traversals, seed 0 (cf. paper Fig. 6).")
            _landscape_fig(store, trav, save_rd, plt)
        # ---- open loop
        ol = _by(rows, "beams/open-loop-v1")
        if ol:
            fig, ax = plt.subplots(figsize=(8, 4))
            for r in sorted(ol, key=lambda r: r["instance"]):
                ts = store.timeseries(r["key"])
                ax.plot(ts["t"], np.degrees(ts["beta"]), label=f"{r['instance']}: {r['status']}")
            ax.set(xlabel="time (s)", ylabel="pitch (deg)")
            ax.axhline(90, color="k", ls=":")
            ax.legend(fontsize=8)
            save_rd(fig, "open_loop_pitch.png", "Open-loop pitch traces (cf. paper Fig. 5); 90 deg = flipped.")
            _write_csv(out_dir / nm("open_loop.csv"), [{"case": r["instance"], "status": r["status"], **r["metrics"],
                                                    "paper": PAPER["open_loop"].get(r["instance"])} for r in ol])
        # ---- delay
        dl = _by(rows, "beams/delay-v1")
        if dl:
            fig, axes = plt.subplots(1, 2, figsize=(10, 4))
            dlines = []
            for case in ("stiff", "flimsy"):
                ds, es, ess, ps = [], [], [], []
                for d in (100, 300, 600):
                    rs = [r for r in dl if r["instance"] == f"{case}-d{d}"]
                    if not rs:
                        continue
                    mu, sd, n = _ms([r["metrics"].get("energy_mJ") for r in rs])
                    pm = _ms([r["metrics"].get("start_pitch_deg") for r in rs])[0]
                    ds.append(d), es.append(mu), ess.append(sd), ps.append(pm)
                    dlines.append({"case": case, "delay_ms": d, "n": len(rs), "energy_mJ_mean": mu, "energy_mJ_std": sd,
                                   "start_pitch_deg": pm, "success": sum(r["status"] == "success" for r in rs)})
                axes[0].errorbar(ds, es, ess, marker="o", capsize=3, label=case)
                axes[1].plot(ds, ps, "o-", label=case)
            axes[0].set(xlabel="sensory delay (ms)", ylabel="energy cost eq. 11 (mJ)")
            axes[1].set(xlabel="sensory delay (ms)", ylabel="pitch when control starts (deg)")
            for a in axes:
                a.legend()
                a.grid(alpha=.3)
            save_rd(fig, "delay.png", "Sensory-delay study (cf. paper Fig. 7).")
            _write_csv(out_dir / nm("delay.csv"), dlines)
        # ---- experiment and contact check
        ex = _by(rows, "beams/experiment-v1")
        _write_csv(out_dir / nm("experiment.csv"), [{"instance": r["instance"], "seed": r["seed"],
                                                     "status": r["status"], **r["metrics"]} for r in ex])
        cc = _by(rows, "beams/contact-check-v1")
        _write_csv(out_dir / nm("contact_check.csv"), [{"pose": r["instance"], **r["metrics"]} for r in cc])
        if cc:
            fig, axes = plt.subplots(1, 2, figsize=(10, 4))
            for r in sorted(cc, key=lambda r: r["instance"]):
                ts = store.timeseries(r["key"])
                axes[0].plot(np.degrees(ts["theta1_an"]), np.degrees(ts["theta1_mj"]), "o", label=r["instance"])
                fa = np.hypot(ts["fx_an"], np.hypot(ts["fy_an"], ts["fz_an"]))
                fm = np.hypot(ts["fx_mj"], np.hypot(ts["fy_mj"], ts["fz_mj"]))
                axes[1].plot(fa, fm, "o", label=r["instance"])
            for a, lab in zip(axes, ("beam-1 deflection (deg)", "|total force| (N)")):
                lim = [0, max(a.get_xlim()[1], a.get_ylim()[1])]
                a.plot(lim, lim, "k:")
                a.set(xlabel=f"analytic {lab}", ylabel=f"MuJoCo {lab}")
                a.legend(fontsize=7)
            save_rd(fig, "contact_check.png", "Analytic contact model vs MuJoCo quasi-static pushes (stiff contact).")
    rows = all_rows
    _sensitivity_fig(rows, save, plt, out_dir, _write_csv, slug)
    from rich.console import Console
    con = Console(record=True, width=150, file=open(os.devnull, "w"))
    con.print(summarize(rows))
    pv = paper_vs_readings(rows)
    _write_csv(out_dir / f"paper_vs_readings{slug}.csv", pv)
    page.h3("Tables")
    page.raw("<pre>" + html.escape(con.export_text()) + "</pre>")


def _landscape_fig(store, trav, save, plt) -> None:
    """Energy-landscape slices with the planned path of seed-0 traversals (cf. paper Fig. 4)."""
    from terrabench.config import from_dict

    from .landscape import LandscapeConfig, build_landscape
    from .model import Beam, BeamLayout, RobotParams

    picks = [r for r in trav if r["seed"] == 0 and r["method"] == "interact"]
    if not picks:
        return
    grid = LandscapeConfig()
    fig, axes = plt.subplots(len(picks), 2, figsize=(11, 4 * len(picks)), squeeze=False)
    for row, r in zip(axes, sorted(picks, key=lambda r: r["instance"])):
        believed = r["info"].get("believed")
        path = np.asarray(r["info"].get("plan_path", []))
        if not believed or path.size == 0:
            continue
        cfg = r.get("config") or {}
        robot = from_dict(RobotParams, cfg["robot"]) if isinstance(cfg.get("robot"), dict) else RobotParams()
        layout = from_dict(BeamLayout, cfg["layout"]) if isinstance(cfg.get("layout"), dict) else BeamLayout()
        ls = build_landscape((Beam(*believed[0]), Beam(*believed[1])), robot, layout, grid=grid)
        e0 = ls.energy.min()
        ang = np.degrees(grid.angles)
        ix0 = int(np.argmin(np.abs(grid.xs - 0.0)))
        im = row[0].imshow((ls.energy[ix0].T - e0) * 1e3, origin="lower", extent=[ang[0], ang[-1], ang[0], ang[-1]],
                           aspect="auto", vmax=60, cmap="viridis")
        row[0].plot(np.degrees(path[:, 1]), np.degrees(path[:, 2]), "w.-", ms=2, lw=1)
        row[0].set(xlabel="roll (deg)", ylabel="pitch (deg)",
                   title=f"{r['instance']}: E(x=0, roll, pitch) - min (mJ); path = all x ({r['info'].get('mode')})")
        fig.colorbar(im, ax=row[0])
        mid = grid.angles.size // 2
        im = row[1].imshow((ls.energy[:, :, mid].T - e0) * 1e3, origin="lower",
                           extent=[grid.xs[0], grid.xs[-1], ang[0], ang[-1]], aspect="auto", vmax=60, cmap="viridis")
        row[1].plot(path[:, 0], np.degrees(path[:, 1]), "w.-", ms=2, lw=1)
        row[1].set(xlabel="x (m)", ylabel="roll (deg)", title="E(x, roll, pitch = 0) (mJ) with path (x, roll)")
        fig.colorbar(im, ax=row[1])
    save(fig, "landscape_paths.png", "Potential-energy landscape slices from the estimated beams with the Dijkstra "
                                     "path (cf. paper Fig. 4); stored trial rows give the beams and the path.")


def _sensitivity_fig(rows, save, plt, out_dir: Path, write_csv, slug: str = "") -> None:
    """Roll and pitch barriers (k = 0.01, 0.25) and the crossover stiffness against the gap d,
    one line style per reading; where pitch < roll the pitch mode is chosen."""
    bars = _by(rows, "beams/barriers-v1")
    if not bars:
        return
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    lines = []
    for rd, ls in (("edge", "-"), ("centre", "--")):
        rs = sorted((r for r in bars if reading(r) == rd), key=lambda r: r["metrics"]["gap"])
        if not rs:
            continue
        d = [r["metrics"]["gap"] for r in rs]
        m = {k: np.array([r["metrics"].get(k, np.nan) for r in rs]) for k in
             ("roll_mJ", "pitch_low_mJ", "pitch_high_mJ", "k_cross", "inner_gap", "roll_clear_deg")}
        axes[0].plot(d, m["roll_mJ"], "k" + ls, marker="o", label=f"roll barrier ({rd})")
        axes[0].plot(d, m["pitch_low_mJ"], "C0" + ls, marker="s", label=f"pitch barrier k=0.01 ({rd})")
        axes[0].plot(d, m["pitch_high_mJ"], "C3" + ls, marker="^", label=f"pitch barrier k=0.25 ({rd})")
        axes[1].plot(d, m["k_cross"], "k" + ls, marker="o", label=f"landscape crossover k ({rd})")
        for r in rs:
            lines.append({"reading": rd, **{k: r["metrics"].get(k) for k in
                                            ("gap", "inner_gap", "roll_clear_deg", "roll_mJ", "pitch_low_mJ",
                                             "pitch_high_mJ", "k_cross", "k0_formula")}})
    for a in axes:
        a.axvline(0.12, color="gray", ls=":", lw=1)
        a.grid(alpha=.3)
    axes[0].axhline(1e3 * 0.2 * 9.81 * 0.02, color="gray", ls="-.", lw=1, label="M g h_c = 39 mJ")
    axes[0].set(xlabel="gap d (m) as read (edge: free gap; centre: centre lines)", ylabel="barrier (mJ)",
                title="pitch below roll: pitch mode chosen")
    axes[0].set_ylim(0, 60)
    axes[0].legend(fontsize=7)
    axes[1].axhline(0.01, color="C0", lw=1, label="k_low = 0.01")
    axes[1].axhline(0.25, color="C3", lw=1, label="k_high = 0.25")
    axes[1].axhline(critical_stiffness(), color="gray", ls="-.", lw=1, label="k_0 formula = 0.028")
    axes[1].set(xlabel="gap d (m)", ylabel="crossover stiffness (N m/rad)", yscale="log",
                title="beams stiffer than the curve are rolled, flimsier pitched")
    axes[1].legend(fontsize=7)
    save(fig, "barrier_sensitivity.png", "Sensitivity of the mode choice to the gap (Sec. II-G on our landscape): "
         "roll barrier and pitch barriers at k = 0.01 and 0.25 against d under each reading (left), and the "
         "stiffness where they are equal (right); the dotted line is the paper's d = 0.12 m.")
    write_csv(out_dir / f"barrier_sensitivity{slug}.csv", lines)
