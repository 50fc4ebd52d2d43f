"""Figures (and the CSVs written beside them) of the beams report, drawn only from stored trial rows."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .model import critical_stiffness
from .report_tables import PAPER, _by, _groupby, _ms, estimation_table, reading


def reading_figures(page: Any, store: Any, rows: list[dict[str, Any]], rd: str, slug: str, plt: Any,
                    save: Any, _write_csv: Any) -> None:
    """One gap reading of a settings group: estimation, traversal, open-loop, delay, experiment and
    MuJoCo-check figures and CSVs."""
    out_dir = page.out_dir
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
