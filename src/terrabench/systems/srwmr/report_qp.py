"""The constraint-saturated IK at work (issue 27, piece 5): group ``ik`` in the srwmr report.

Per instance of :mod:`~terrabench.systems.srwmr.ik_cases` (and its ``-noqp`` twin, the same plan
with the projection bypassed) from the trial's stored QP trace (``info["qp_trace"]``,
:mod:`~terrabench.systems.srwmr.qp_trace`):

* a table (``qp_ik.csv``): the share of the periods in which the QP changes the nominal command,
  per constraint the share in which its rows are active at the executed command and violated by
  the nominal, the largest measured ratio over kappa, the reminders (supervisor halts);
* a figure: the constrained ratios eta_k against time with kappa (the executed command's, the
  nominal's one step ahead, and the twin's measured), the nominal against the executed command,
  the periods in which the QP changed the command shaded.

Pure functions of stored rows (:func:`qp_lines`, :func:`trace_arrays`) and one
:func:`add_section` that :func:`terrabench.systems.srwmr.report._section` calls.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from terrabench.systems.srwmr.ik_cases import CASES, HALT_TOL, case_of, variant_of
from terrabench.systems.srwmr.qp_trace import QP_NAMES

#: the command component(s) each case's constraint acts on: (index in u, label)
COMMAND_OF = {
    "MC3": ((3, "ddelta_L rad/s"), (4, "ddelta_R rad/s")),
    "MC4": ((3, "ddelta_L rad/s"), (4, "ddelta_R rad/s")),
    "MC5": ((3, "ddelta_L rad/s"), (4, "ddelta_R rad/s")),
    "MC6": ((3, "ddelta_L rad/s"), (4, "ddelta_R rad/s")),
    "MC7": ((0, "vx m/s"), (2, "wz rad/s")),
}


def ik_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The rows of group ``ik`` that carry a QP trace, seed 0 first."""
    order = ("qp", "target", "noqp")
    return sorted((r for r in rows if case_of(r["instance"]) in CASES and "qp_trace" in r.get("info", {})),
                  key=lambda r: (list(CASES).index(case_of(r["instance"])), order.index(variant_of(r["instance"])),
                                 r["seed"]))


def trace_arrays(trace: dict[str, Any]) -> dict[str, np.ndarray]:
    """The thinned trace as one float array per column (None -> nan)."""
    cols = trace["columns"]
    if not trace["rows"]:
        return {c: np.zeros(0) for c in cols}
    a = np.array([[np.nan if v is None else v for v in row] for row in trace["rows"]], float)
    return {c: a[:, i] for i, c in enumerate(cols)}


def _ratio_over_kappa(tr: dict[str, Any], name: str) -> float:
    k = next(iter(tr["kappa"].values()), None) if tr["kappa"] else None
    m = tr["max_measured"].get(name)
    if k is None or m is None:
        return float("nan")
    kap = k[QP_NAMES.index(name)]
    return float(m) / kap if kap else float("nan")


def qp_lines(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One line per ``ik`` trial: the QP's share and its rows, and the measured effect."""
    out = []
    for r in ik_rows(rows):
        tr, info = r["info"]["qp_trace"], r["info"]
        n = max(int(tr["periods"]), 1)
        main = CASES[case_of(r["instance"])]
        line = {
            "instance": r["instance"],
            "seed": r["seed"],
            "QP": {"qp": "executed", "noqp": "bypassed (traced)",
                   "target": "executed, rows about the servo targets"}[variant_of(r["instance"])],
            "saturates": main,
            "status": r["status"],
            "sim s": float(r["metrics"].get("sim_time", float("nan"))),
            "IK periods": int(tr["periods"]),
            "QP changed %": 100.0 * tr["changed"] / n,
        }
        for name in QP_NAMES:
            line[f"active {name} %"] = 100.0 * tr["active_rows"].get(name, 0) / n
        for name in QP_NAMES:
            line[f"nominal violates {name} %"] = 100.0 * tr["violated_rows"].get(name, 0) / n
        line["max eta / kappa (saturated MC)"] = _ratio_over_kappa(tr, main)
        line["max nominal eta / kappa (1 step ahead)"] = (
            float(tr["max_predicted_nominal"].get(main) or float("nan"))
            / next(iter(tr["kappa"].values()))[QP_NAMES.index(main)] if tr["kappa"] else float("nan"))
        line["periods measured > kappa"] = int(sum(tr["measured_above_kappa"].values()))
        line["reminders"] = int(sum((info.get("reminders") or {}).values()))
        line["reason"] = info.get("reason", "")
        out.append(line)
    return out


def _shade(ax, runs, color="tab:orange", alpha=0.18) -> None:
    for t0, t1, *_ in runs:
        ax.axvspan(t0, max(t1, t0 + 0.01), color=color, alpha=alpha, lw=0)


#: per variant: line style, label, shading colour of its QP-changed periods (None: not shaded)
STYLE = {"qp": ("-", "QP", "tab:orange"), "target": ("-.", "QP about targets", "tab:green"),
         "noqp": (":", "no QP", None)}


def case_figure(plt: Any, case: str, variants: dict[str, dict[str, Any]]):
    """The figure of one case (``variants``: variant -> row): ratios with kappa, the commands, the
    QP-changed periods shaded."""
    main = CASES[case]
    # the constraints the nominal violates in at least 2 % of the periods of some variant, the case's own first
    names = [main] + [n for n in QP_NAMES[:-1] if n != main and any(
        r["info"]["qp_trace"]["violated_rows"].get(n, 0) > 0.02 * max(r["info"]["qp_trace"]["periods"], 1)
        for r in variants.values())]
    color = {n: f"C{j}" for j, n in enumerate(QP_NAMES)}
    top = 0.0
    fig, ax = plt.subplots(3, 1, figsize=(9, 7.5), sharex=True)
    for var in ("qp", "target", "noqp"):
        r = variants.get(var)
        if r is None:
            continue
        style, who, shade = STYLE[var]
        tr = r["info"]["qp_trace"]
        a = trace_arrays(tr)
        t = a["t"]
        kap = next(iter(tr["kappa"].values())) if tr["kappa"] else None
        for n in names:
            c = color[n]
            if kap is not None and kap[QP_NAMES.index(n)] is not None:
                top = max(top, 3.0 * kap[QP_NAMES.index(n)])
            ax[0].plot(t, a[f"eta_{n}"], style, color=c, lw=1.0, label=f"{n} measured ({who})")
            if var == "qp":
                ax[0].plot(t, a[f"pred_nom_{n}"], "--", color=c, lw=0.7, alpha=0.6, label=f"{n} nominal, 1 step ahead")
                if kap is not None and kap[QP_NAMES.index(n)] is not None:
                    ax[0].axhline(kap[QP_NAMES.index(n)], color=c, lw=0.8, ls=(0, (6, 2)), alpha=0.9,
                                  label=f"kappa {n}")
        for j, (i, lab) in enumerate(COMMAND_OF.get(main, ())):
            if var == "qp":
                ax[1].plot(t, a[f"u_nom{i}"], "--", color=f"C{j}", lw=0.8, alpha=0.6, label=f"{lab} nominal")
            ax[1].plot(t, a[f"u{i}"], style, color=f"C{j}", lw=1.0, label=f"{lab} executed ({who})")
        if shade is not None:
            _shade(ax[0], tr["runs"], color=shade)
            _shade(ax[1], tr["runs"], color=shade)
            off = 0.0 if var == "qp" else 1.5
            ax[2].step(t, off + a["changed"], where="post", color=shade, lw=0.8, label=f"QP changed ({who})")
            act = a["active"].astype(int)
            for j, n in enumerate(QP_NAMES):
                on = (act >> j) & 1
                if on.any():
                    ax[2].step(t, off + on * (0.2 + 0.1 * j), where="post", lw=0.7, color=color[n],
                               ls=style, label=f"{n} active ({who})")
    ax[0].set_ylabel("constraint ratio eta")
    if top > 0:
        ax[0].set_ylim(bottom=min(0.0, ax[0].get_ylim()[0]), top=min(ax[0].get_ylim()[1], top))
    for a_, nc in ((ax[0], 3), (ax[1], 2), (ax[2], 3)):
        a_.legend(fontsize="xx-small", ncol=nc, loc="best")
    ax[1].set_ylabel("command")
    ax[2].set_ylabel("QP changed / rows active\n(QP; QP about targets +1.5)")
    ax[2].set_xlabel("t s")
    fig.suptitle(f"{case}: {main} at its QP boundary (shaded: the QP changed the nominal command)")
    fig.tight_layout()
    return fig


def add_section(page: Any, rows: list[dict[str, Any]], slug: str, plt: Any) -> None:
    """The ``ik`` group's table and one figure per case (nothing if the store has none)."""
    lines = qp_lines(rows)
    if not lines:
        return
    page.h2("The constraint-saturated IK at work (group ik: MC#3-#9 at their QP boundary, each with a -noqp twin)")
    page.p("Run: terrabench run srwmr --group ik --store ... (each case as the IK runs in every trial, "
           "its -noqp twin with the projection bypassed, the posture cases also as -target with the rows "
           "linearised about the rockers' servo targets; the supervisor of the group halts above kappa (1 + "
           f"{HALT_TOL:g}), ik_cases.HALT_TOL).")
    page.p("QP changed %: of the control periods through the IK, those in which the projection changed the "
           "nominal command (in a -noqp twin: would have changed; the nominal is executed). active X %: the "
           "periods in which X's rows are active at the executed command while it differs from the nominal; "
           "nominal violates X %: the periods in which the nominal command violates X's rows. max eta / kappa: "
           "the largest measured ratio over the mode's threshold; the nominal's one step ahead from the QP's rows.")
    page.table(lines, list(lines[0]), csv_name=f"qp_ik{slug}.csv")
    by: dict[str, dict[str, dict[str, Any]]] = {}
    for r in ik_rows(rows):
        by.setdefault(case_of(r["instance"]), {}).setdefault(variant_of(r["instance"]), r)
    for case, rs in by.items():
        fig = case_figure(plt, case, rs)
        page.figure(fig, f"qp_{case}{slug}.png",
                    f"{case}: eta of the constraints the nominal violates, with kappa (solid: the QP as every "
                    "trial runs it; dash-dot: rows about the servo targets (-target); dotted: the -noqp twin; "
                    "dashed: the nominal one step ahead); nominal vs executed command; shaded / steps: the "
                    "periods where the QP changed the command and the rows active")
        import matplotlib.pyplot as _plt

        _plt.close(fig)
