"""Stored soil trials -> the CLI table and the HTML report (one page, :mod:`terrabench.report.page`).

Sections: the CMU validation (every measured point beside the model, RMS errors per quantity
against the targets, fitted vs predicted points) and the single-wheel sweeps (drawbar pull,
torque and sinkage against slip per soil). Config variants (``--set`` runs) are separated with
:mod:`terrabench.report.variants`: each is its own labelled line and curve.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from terrabench.systems.soil.instances import CMU_METHODS, RIG_METHODS, parse_instance

SOURCE = {"rig": "mujoco", "analytic": "analytic"}
ORDER = list(RIG_METHODS + CMU_METHODS)
QUANT = (("DP_drive", "drawbar pull, driving (s >= 0)", "% of load"),
         ("DP_all", "drawbar pull, all slips", "% of load"),
         ("lateral", "lateral force", "% of load"), ("sinkage", "sinkage", "mm"))
WHY = {
    "DP_all": "skid and the locked wheel: the braked-wheel resistance (front ploughing of the rut) sets it; at slip "
              "angles >= 60 deg the wheel is buried past its axle in the data",
    "lateral": "the lateral force at large slip angles is mostly sidewall bulldozing, which grows with the square of "
               "the sinkage and whose mobilisation the slip-angle-0 trials cannot fix: unscaled Hegedus pressure "
               "over-predicts it at 30-60 deg, and at 75-90 deg the measured sinkage passes the wheel radius",
    "sinkage": "at slip angles >= 60 deg the measured sinkage (42-77 mm) reaches or exceeds the wheel radius (58 mm): "
               "the wheel digs a trench sideways, a mechanism (lateral excavation) the model does not have",
    "DP_drive": "driving at 75-90 deg slip angle: the force along the heading comes from the rim dragging the soil "
                "of the trench it digs sideways, past the wheel's axle, which the model cannot hold",
}


def sweep_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Single-wheel trial rows as sweep points (soil, load_N, slip, DP_N, ..., source)."""
    out = []
    for r in rows:
        if r["status"] != "done" or r["method"] not in SOURCE:
            continue
        _, load, slip = parse_instance(r["instance"])
        m = r["metrics"]
        out.append({"soil": r["config"]["soil"]["name"], "load_N": load, "slip": slip, "DP_N": m["DP_N"],
                    "torque_Nm": m["torque_Nm"], "sinkage_m": m["sinkage_m"], "DP_coeff": m["DP_coeff"],
                    "efficiency": m["efficiency"], "source": SOURCE[r["method"]], "label": r.get("label", r["method"])})
    return out


def cmu_arrays(rows: list[dict[str, Any]]) -> dict[str, np.ndarray]:
    """The metrics of CMU rows as arrays (one entry per row, in the rows' order)."""
    keys = ("beta_deg", "slip", "load_N", "DP_meas_N", "lateral_meas_N", "sinkage_meas_m", "DP_N", "lateral_N",
            "sinkage_m", "torque_Nm", "fitted", "sinkage_capped")
    return {k: np.array([float(r["metrics"][k]) for r in rows]) for k in keys}


def rms(a: dict[str, np.ndarray], sel: np.ndarray) -> dict[str, float]:
    """:func:`terrabench.systems.soil.cmu.rms_table` on stored rows' arrays (:func:`cmu_arrays`):
    DP driving and all slips, lateral (fractions of the load), sinkage (m), point counts."""
    from terrabench.systems.soil.cmu import rms_table

    meas = {"load_N": a["load_N"], "slip": a["slip"], "DP_N": a["DP_meas_N"], "lateral_N": a["lateral_meas_N"],
            "sinkage_m": a["sinkage_meas_m"]}
    return rms_table(meas, a, sel)


def rms_lines(label: str, a: dict[str, np.ndarray]) -> list[dict[str, Any]]:
    """One line per point subset (fitted / predicted / all) with each RMS against its target."""
    from terrabench.systems.soil.cmu import TARGETS

    fitted = a["fitted"] > 0
    lines = []
    subsets = (("fitted", fitted), ("predicted", ~fitted), ("all", np.ones_like(fitted)))
    if label.startswith("cmu-authors"):  # tuned by the authors on these trials: nothing predicted
        subsets = (("all (authors' tuning on these trials)", np.ones_like(fitted)),)
    for subset, sel in subsets:
        if not sel.any():
            continue
        e = rms(a, sel)
        line = {"parameters": label, "points": subset, "n (driving/all)": f"{e['n_drive']}/{e['n_all']}"}
        for key, _, unit in QUANT:
            v, t = e[key], TARGETS[key]
            scale = 1e3 if unit == "mm" else 100.0
            verdict = "meets" if v <= t else f"misses by {scale * (v - t):.1f}"
            line[f"{key} ({unit})"] = f"{scale * v:.1f} (target {scale * t:g}: {verdict})"
        lines.append(line)
    return lines


def summary_table(rows: list[dict[str, Any]]):
    """CMU RMS per parameter set, and DP/W at slip 0.2 / 0.4 / 0.6 per soil, load and method."""
    from rich.table import Table

    t = Table(title="soil: CMU RMS (fitted/predicted/all); single-wheel DP/W at slip 0.2 / 0.4 / 0.6, sinkage at 0.2")
    for c in ("what", "set / soil", "points / load", "DP drive", "DP all / s=0.4", "lateral / s=0.6", "sinkage mm"):
        t.add_column(c)
    for method in CMU_METHODS:
        rs = [r for r in rows if r["method"] == method and r["status"] == "done"]
        if not rs:
            continue
        for line in rms_lines(method, cmu_arrays(rs)):
            t.add_row("cmu", method, line["points"], *(line[f"{k} ({u})"].split(" (")[0] for k, _, u in QUANT))
    pts = {}
    for p in sweep_rows(rows):
        pts[(p["soil"], p["load_N"], p["source"], round(p["slip"], 2))] = p
    for soil, load, src in sorted({k[:3] for k in pts}):
        cells = [f"{pts[(soil, load, src, s)]['DP_coeff']:.3f}" if (soil, load, src, s) in pts else "-"
                 for s in (0.2, 0.4, 0.6)]
        z = pts.get((soil, load, src, 0.2))
        t.add_row("single wheel", soil, f"{load:g} N {src}", *cells, f"{1e3 * z['sinkage_m']:.1f}" if z else "-")
    return t


def _cmu_figure(variants_rows: list[tuple[str, list[dict[str, Any]]]]):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.systems.soil.cmu import BETAS, points

    p = points()
    fig, axs = plt.subplots(3, len(BETAS), figsize=(3.0 * len(BETAS), 8.4), sharey="row")
    colors = plt.cm.tab10(np.arange(10))
    for j, beta in enumerate(BETAS):
        m = p["beta_deg"] == beta
        for i, (key, std, scale) in enumerate((("DP_N", "std_DP_N", 1.0), ("lateral_N", "std_lateral_N", 1.0),
                                               ("sinkage_m", "std_sinkage_m", 1e3))):
            ax = axs[i, j]
            ax.errorbar(p["slip"][m], p[key][m] * scale, yerr=p[std][m] * scale, fmt="o", ms=3, color="k",
                        label="measured (CMU)", zorder=3)
            for c, (label, rs) in zip(colors, variants_rows):
                a = cmu_arrays([r for r in rs if int(r["metrics"]["beta_deg"]) == beta])
                if not len(a["slip"]):
                    continue
                o = np.argsort(a["slip"], kind="stable")
                ax.plot(a["slip"][o], a[key][o] * scale, "-", color=c, lw=1.2, label=label)
            ax.grid(alpha=0.3)
            if i == 0:
                ax.set_title(f"slip angle {beta} deg")
            if i == 2:
                ax.set_xlabel("slip (data's definition)")
        axs[0, 0].set_ylabel("drawbar pull (N)")
        axs[1, 0].set_ylabel("lateral force (N)")
        axs[2, 0].set_ylabel("sinkage (mm)")
    axs[0, 0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def _sweep_figure(srows: list[dict[str, Any]], name: str):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axs = plt.subplots(2, 2, figsize=(10, 7.5))
    keys = sorted({(r["label"], r["load_N"]) for r in srows})
    colors = plt.cm.viridis(np.linspace(0, 0.85, max(len(keys), 1)))
    for c, (label, load) in zip(colors, keys):
        sel = sorted((r for r in srows if r["label"] == label and r["load_N"] == load), key=lambda r: r["slip"])
        style = dict(ls="none", marker="o", ms=4) if sel[0]["source"] == "mujoco" else dict(ls="-")
        for ax, key, scale in ((axs[0, 0], "DP_N", 1.0), (axs[0, 1], "torque_Nm", 1.0), (axs[1, 0], "sinkage_m", 1e3)):
            ax.plot([r["slip"] for r in sel], [r[key] * scale for r in sel], color=c, label=f"{label} {load:g} N",
                    **style)
    axs[0, 0].set(xlabel="slip", ylabel="drawbar pull (N)", title=f"{name}: drawbar pull")
    axs[0, 0].axhline(0, color="k", lw=0.5)
    axs[0, 1].set(xlabel="slip", ylabel="driving torque (N m)", title="torque")
    axs[1, 0].set(xlabel="slip", ylabel="sinkage (mm)", title="sinkage vs slip")
    slips = np.array(sorted({r["slip"] for r in srows}))
    s_ref = float(slips[np.argmin(np.abs(slips - 0.2))])
    for label in sorted({r["label"] for r in srows}):
        sel = sorted((r for r in srows if r["label"] == label and r["slip"] == s_ref), key=lambda r: r["load_N"])
        if sel:
            axs[1, 1].plot([r["load_N"] for r in sel], [r["sinkage_m"] * 1e3 for r in sel], "o-", label=label)
    axs[1, 1].set(xlabel="load (N)", ylabel="sinkage (mm)", title=f"sinkage vs load (slip {s_ref:g})")
    for ax in axs.flat:
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=6)
    fig.tight_layout()
    return fig


def write_report(store, out_dir: Path, system: Any) -> Path:
    from terrabench.report.page import Page, cell, provenance_html
    from terrabench.report.variants import Defaults, find_variants, tag_rows
    from terrabench.systems.soil.cmu import FIT_BETAS, fitted

    rows = [r for r in store.rows(system="soil") if r["status"] == "done"]
    if not rows:
        raise ValueError("the store has no finished soil trials; run `terrabench run soil --group cmu-smooth` "
                         "or `--group single-wheel` first")
    defaults = Defaults(system)
    variants = find_variants(rows, default_config=defaults, order=ORDER)
    rows = tag_rows(rows, variants)
    page = Page(out_dir, "Soil: wheel-soil terramechanics", outputs=("mars_soft.png", "dry_sand.png",
                                                                      "lunar_regolith.png"))
    cmu_vs = [v for v in variants if v.method in CMU_METHODS]
    if cmu_vs:
        page.h2("CMU smooth wheel on sand: every measured trial beside the model")
        fit = fitted()
        page.p("Data: robomechanics/3d-terramechanics (C. Pavlov, CMU; MIT licence), 189 averaged single-wheel "
               "trials, wheel r = 0.058 m, b = 0.05 m, load 16-26 N, slip -1 (locked) to 0.9, slip angle 0-90 deg. "
               "No torque was measured, so none is compared (the model's torque is stored with each trial).")
        page.p("<b>cmu-authors</b>: the authors' hand-tuned soil and per-slip-angle stress and exit angles; "
               "terrabench fits nothing (the authors tuned them on these trials: calibration, not prediction). "
               f"<b>cmu-fit-b0</b>: terrabench fits {', '.join(fit['names'])} on the {len(fit['fitted_trials'])} "
               f"trials at slip angle {', '.join(str(b) for b in FIT_BETAS)} deg (all slips incl. skid and the "
               "locked wheel); every trial at other slip angles is predicted with the same parameters. "
               f"Parameters at a bound of the fit: {', '.join(fit['at_bounds']) or 'none'}.")
        lines = []
        for v in cmu_vs:
            lines += rms_lines(v.label, cmu_arrays(v.rows_of(rows)))
        cols = ["parameters", "points", "n (driving/all)"] + [f"{k} ({u})" for k, _, u in QUANT]
        page.table(lines, cols, csv_name="cmu_rms.csv")
        missed = {k for line in lines for k, _, u in QUANT if "misses" in line[f"{k} ({u})"]}
        for k in sorted(missed):
            page.note(f"{dict((q, d) for q, d, _ in QUANT)[k]} misses its target: {WHY[k]}.")
        per_beta = []
        for v in cmu_vs:
            a = cmu_arrays(v.rows_of(rows))
            for beta in sorted(set(a["beta_deg"].astype(int))):
                e = rms(a, a["beta_deg"] == beta)
                per_beta.append({"parameters": v.label, "slip angle (deg)": beta,
                                 "fitted": "yes" if a["fitted"][a["beta_deg"] == beta].any() else "no",
                                 "DP drive %": 100 * e["DP_drive"], "DP all %": 100 * e["DP_all"],
                                 "lateral %": 100 * e["lateral"], "sinkage mm": 1e3 * e["sinkage"],
                                 "sinkage capped at r": int(a["sinkage_capped"][a["beta_deg"] == beta].sum())})
        page.h3("RMS per slip angle")
        page.table(per_beta, list(per_beta[0]), csv_name="cmu_rms_by_slip_angle.csv",
                   fmt=lambda c, v: f"{v:.1f}" if isinstance(v, float) else cell(v))
        page.figure(_cmu_figure([(v.label, v.rows_of(rows)) for v in cmu_vs]), "cmu_smooth.png",
                    "Measured (dots, +-1 std of the trial) and modelled (lines) drawbar pull, lateral force and "
                    "sinkage against slip, one column per slip angle.")
        pts = []
        for r in rows:
            if r["method"] in CMU_METHODS:
                pts.append({"label": r["label"], "instance": r["instance"], **r["metrics"]})
        page.csv("cmu_points.csv", pts, list(pts[0]))
        page.p("Every point: <a href='cmu_points.csv'>cmu_points.csv</a>.")
    srows = sweep_rows(rows)
    if srows:
        page.h2("Single wheel: drawbar pull, torque and sinkage against slip")
        page.p("Lines: steady-state equations; dots: the MuJoCo rig (soil forces in the episode loop's per-step hook).")
        for name in sorted({r["soil"] for r in srows}):
            sr = [r for r in srows if r["soil"] == name]
            page.h3(name)
            page.figure(_sweep_figure(sr, name), f"single_{name}.png", f"{name}: sweeps per variant and load")
            lines = []
            for label in sorted({r["label"] for r in sr}):
                for load in sorted({r["load_N"] for r in sr if r["label"] == label}):
                    sel = {round(r["slip"], 6): r for r in sr if r["label"] == label and r["load_N"] == load}
                    line = {"variant": label, "load N": load}
                    for s in (0.2, 0.4, 0.6):
                        line[f"DP/W s={s:g}"] = sel[s]["DP_coeff"] if s in sel else None
                    line["sinkage mm s=0"] = 1e3 * sel[0.0]["sinkage_m"] if 0.0 in sel else None
                    line["sinkage mm s=0.6"] = 1e3 * sel[0.6]["sinkage_m"] if 0.6 in sel else None
                    lines.append(line)
            page.table(lines, list(lines[0]), csv_name=f"single_{name}.csv")
    page.raw(provenance_html(store, rows, system_id="soil", default_config=defaults))
    return page.finish()

