"""HTML + PNG report of single-wheel sweep rows (from :mod:`terrabench.soil.testbed`).

Each row: soil, load_N, slip, DP_N, torque_Nm, sinkage_m, DP_coeff, efficiency, source
("analytic" | "mujoco"). Per soil: DP and torque vs slip, sinkage vs slip (one curve per
load and source), sinkage vs load (at the slip nearest 0.2), and a table of DP/W at slip
0.2 / 0.4 / 0.6 beside the reference (the Coulomb bound tan(phi) of the preset; no published
per-slip numbers are quoted, see docs/soil.md).
"""

from __future__ import annotations

import html
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REQUIRED = ("soil", "load_N", "slip", "DP_N", "torque_Nm", "sinkage_m", "DP_coeff", "efficiency", "source")
STYLE = {"analytic": dict(ls="-", marker=""), "mujoco": dict(ls="none", marker="o", ms=4)}


def _check(rows: list[dict]) -> None:
    if not rows:
        raise ValueError("rows is empty; need at least one sweep row")
    for r in rows:
        missing = [k for k in REQUIRED if k not in r]
        if missing:
            raise ValueError(f"row {r!r} lacks {missing}; required keys: {', '.join(REQUIRED)}")


def _curves(ax, rows, ykey, scale=1.0):
    loads = sorted({r["load_N"] for r in rows})
    colors = plt.cm.viridis(np.linspace(0, 0.85, max(len(loads), 1)))
    for src in ("analytic", "mujoco"):
        for c, load in zip(colors, loads):
            sel = sorted((r for r in rows if r["source"] == src and r["load_N"] == load), key=lambda r: r["slip"])
            if sel:
                ax.plot([r["slip"] for r in sel], [r[ykey] * scale for r in sel], color=c,
                        label=f"{src} {load:g} N", **STYLE.get(src, {}))


def write_report(rows: list[dict], out_dir: Path) -> Path:
    """Write ``out_dir/index.html`` and one PNG per soil; return the index path."""
    from terrabench.soil.presets import SOILS

    _check(rows)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    parts = ["<html><head><meta charset='utf-8'><title>terrabench soil: single wheel</title></head><body>",
             "<h1>Single-wheel terramechanics sweep</h1>",
             "<p>Lines: analytic steady state (Wong-Reece / Bekker / Janosi). Dots: MuJoCo rig "
             "(SoilWheels forces, servoed carriage). Reference: the Coulomb limit of DP/W, "
             "tan(phi) + cA/W, approached at high slip; see docs/soil.md.</p>"]
    for name in sorted({r["soil"] for r in rows}):
        srows = [r for r in rows if r["soil"] == name]
        fig, axs = plt.subplots(2, 2, figsize=(10, 7.5))
        _curves(axs[0, 0], srows, "DP_N")
        axs[0, 0].set(xlabel="slip", ylabel="drawbar pull (N)", title=f"{name}: drawbar pull")
        axs[0, 0].axhline(0, color="k", lw=0.5)
        _curves(axs[0, 1], srows, "torque_Nm")
        axs[0, 1].set(xlabel="slip", ylabel="driving torque (N m)", title="torque")
        _curves(axs[1, 0], srows, "sinkage_m", 1e3)
        axs[1, 0].set(xlabel="slip", ylabel="sinkage (mm)", title="sinkage vs slip")
        slips = np.array(sorted({r["slip"] for r in srows}))
        s_ref = float(slips[np.argmin(np.abs(slips - 0.2))])
        for src in ("analytic", "mujoco"):
            sel = sorted((r for r in srows if r["source"] == src and r["slip"] == s_ref), key=lambda r: r["load_N"])
            if sel:
                axs[1, 1].plot([r["load_N"] for r in sel], [r["sinkage_m"] * 1e3 for r in sel], label=src, **STYLE[src])
        axs[1, 1].set(xlabel="load (N)", ylabel="sinkage (mm)", title=f"sinkage vs load (slip {s_ref:g})")
        for ax in axs.flat:
            ax.grid(alpha=0.3)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=7)
        fig.tight_layout()
        png = out_dir / f"{name}.png"
        fig.savefig(png, dpi=90)
        plt.close(fig)
        ref = ""
        if name in SOILS:
            sp = SOILS[name]
            ref = f"tan(phi) = {sp.tan_phi:.3f} (phi {sp.phi_deg:g} deg, c {sp.c:g} Pa); source: {html.escape(sp.source)}"
        parts.append(f"<h2>{html.escape(name)}</h2><p>{ref}</p><img src='{png.name}'>")
        parts.append("<table border=1 cellpadding=3><tr><th>source</th><th>load (N)</th>"
                     + "".join(f"<th>DP/W @ s={s:g}</th>" for s in (0.2, 0.4, 0.6)) + "<th>efficiency @ s=0.2</th></tr>")
        for src in ("analytic", "mujoco"):
            for load in sorted({r["load_N"] for r in srows}):
                sel = {round(r["slip"], 6): r for r in srows if r["source"] == src and r["load_N"] == load}
                if not sel:
                    continue
                cells = "".join(f"<td>{sel[s]['DP_coeff']:.3f}</td>" if s in sel else "<td>-</td>" for s in (0.2, 0.4, 0.6))
                eff = f"{sel[0.2]['efficiency']:.3f}" if 0.2 in sel else "-"
                parts.append(f"<tr><td>{src}</td><td>{load:g}</td>{cells}<td>{eff}</td></tr>")
        parts.append("</table>")
    parts.append("</body></html>")
    index = out_dir / "index.html"
    index.write_text("\n".join(parts), encoding="utf-8")
    return index
