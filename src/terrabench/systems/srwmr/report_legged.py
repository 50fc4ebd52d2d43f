"""The wheel-legged modes' report sections (stored rows): lift spans, wheel loads and the roll's
s_b / PC beside the paper's Task 6, 7, 12 and 13 figures (the modes themselves: legged.py)."""

from __future__ import annotations

import numpy as np

from terrabench.systems.srwmr.constraints import load_figures
from terrabench.systems.srwmr.legged import position
from terrabench.systems.srwmr.report_tasks import metric
from terrabench.systems.srwmr.robot import WHEEL_SIDE, WHEELS

#: the paper's wheel-load figures while lifted [S Task 6 / Task 7]: W_diff (N) and W_fmr (N) by the
#: position lifted (None: not stated); nominal wheel load ~380 N [S]
PAPER_LOADS = {
    "t6-bricks": {"front": (826, None), "middle": (250, None), "rear": (1050, None)},
    "t7-stairs": {"front": (1300, 640), "middle": (100, 100), "rear": (1189, 612)},
}
PAPER_NOMINAL = {"t6-bricks": "wheel load ~380 N", "t7-stairs": "W_fmr ~100 N, W_diff ~200 N (hard stairs)"}
#: the largest share of the wheel loads the lifted side can have carried in the paper's single-wheel
#: lifts [S Task 6]: the lifted wheel at 0 and the other end "nearly suspended" leave the side's load
#: on its middle wheel, which W_diff bounds (826 / 1050 N of ~2,280 N = 6 x 380 N [S]); the rest is on
#: the other side: "the CoM shifting to the side of the unlifted wheel" [S sec. 3.1]
PAPER_SIDE_SHARE = {("t6-bricks", "front"): "<= ~0.36-0.40", ("t6-bricks", "rear"): "<= ~0.46-0.50"}
#: [S] Tasks 12 and 13: body-slip range during the lifted roll and energy EC (kJ) per trial
PAPER_ROLL = {
    ("t12-lift100", "swlm"): ("0.01-0.24", 39.6), ("t12-lift150", "swlm"): ("0.01-0.24", 43.9),
    ("t12-lift200", "swlm"): ("0.01-0.24, -0.024 seen", 41.5),
    ("t12-lift100", "dwlm"): ("-0.01-0.27", 42.5), ("t12-lift150", "dwlm"): ("-0.01-0.27", 41.9),
    ("t12-lift200", "dwlm"): ("-0.01-0.27", 41.8),
    ("t13-front", "swlm"): ("-0.10-0.14", 41.6), ("t13-middle", "swlm"): ("-0.16-0.10", 23.6),
    ("t13-rear", "swlm"): ("-0.02-0.21", 20.1),
    ("t13-front", "dwlm"): ("-0.01-0.21", 41.8), ("t13-middle", "dwlm"): ("peak 0.32", 22.4),
    ("t13-rear", "dwlm"): ("peak -0.10", 19.4),
}
#: [S] the PC observations of Tasks 12/13 (PC = F_DP / F_N per wheel)
PAPER_PC = {
    ("t12-lift150", "swlm"): "right rear PC 27.5 (F_N 10 N: nearly suspended)",
    ("t12-lift200", "swlm"): "both rear PC 32.5 (F_N 8 N)",
    ("t12-lift100", "swlm"): "left front and left middle PC > 1",
    ("t12-lift100", "dwlm"): "middle PC ~0.1, rear > 1 then ~0.6",
    ("t13-middle", "swlm"): "right rear PC > 1; right front, left rear ~0.6; left front, middle ~0.3",
    ("t13-rear", "swlm"): "left front PC mean 35, peak > 60 (seesaw); left rear 1.6",
    ("t13-middle", "dwlm"): "rear PC 1-1.25; front 0.2 -> 0.7",
    ("t13-rear", "dwlm"): "middle PC > 1 then < 1; left front peak 8",
}


def lift_spans(events: list[dict]) -> list[dict]:
    """Per legged step of a stored trial (``info["legged"]``, entries in order, ``step`` = the plan
    step): the lifted wheels, when the lift began (clutch engaged), when it ended (wheel up), when
    the wheel was down again, and the notes."""
    out: dict[int, dict] = {}
    for e in events:
        sp = out.setdefault(e.get("step", 0), {"lift": e["lift"], "pos": position(tuple(e["lift"].split("+")))})
        key = {"clutch": "t_clutch", "lift": "t_up", "lower": "t_down", "roll": "t_rolled"}.get(e["action"])
        if key:
            sp[key] = e["t"]
        if e["action"] == "lift":
            sp["lift_note"] = e["note"]
    return [out[k] for k in sorted(out)]


def _loads(ts, ft: bool = False):
    """(t, W (n, 6)): the soil's normal forces, or (``ft``) the F/T wheel-load estimates the
    supervisor reads (these include a wheel standing on a rigid step or brick)."""
    pre = "Wft_" if ft and "Wft_c1" in ts else "W_"
    W = np.array([np.asarray(ts[f"{pre}{c}"], float) for c in WHEELS]).T
    return np.asarray(ts["t"], float), W


def fmr_centre(r) -> str:
    """The load a row's W_fmr was measured about (``scales.w_fmr_centre``; rows made before the
    field existed used the mean)."""
    return (r.get("config") or {}).get("scales", {}).get("w_fmr_centre", "mean")


def load_lines(rows, store) -> list[dict]:
    """T6 / T7: W_diff and W_fmr (truth wheel loads) while each wheel set was up, beside the paper's."""
    lines = []
    for r in sorted(rows, key=lambda r: (r["instance"], r["method"], r["seed"])):
        if r["instance"] not in PAPER_LOADS:
            continue
        ts = store.timeseries(r["key"])
        if not ts or "t" not in ts:
            continue
        t, W = _loads(ts, ft=True)
        wd, fm = load_figures(W, fmr_centre(r))
        nom = (t > 1.0) & (t < 5.0)
        for sp in lift_spans(r["info"].get("legged", [])):
            up = (t >= sp.get("t_up", np.inf)) & (t <= sp.get("t_down", -np.inf))
            pdiff, pfmr = PAPER_LOADS[r["instance"]][sp["pos"]]
            lifted = sp["lift"].split("+")
            side = side_share(W, WHEEL_SIDE[WHEELS.index(lifted[0])]) if len(lifted) == 1 and up.any() else None
            lines.append({
                "task": r["instance"], "mode": r["method"], "seed": r["seed"], "lifted": sp["lift"],
                "lift": sp.get("lift_note", "not reached"),
                "nominal W_diff N": float(np.median(wd[nom])) if nom.any() else float("nan"),
                "nominal W_fmr N": float(np.median(fm[nom])) if nom.any() else float("nan"),
                "W_diff max N (up)": float(wd[up].max()) if up.any() else float("nan"),
                "W_fmr max N (up)": float(fm[up].max()) if up.any() else float("nan"),
                "W_max N (up)": float(W[up].max()) if up.any() else float("nan"),
                "paper W_diff N": pdiff, "paper W_fmr N": pfmr if pfmr is not None else "",
                "lifted side's share of the load (up, median)": float(np.median(side[up])) if side is not None else "",
                "paper: lifted side's share": PAPER_SIDE_SHARE.get((r["instance"], sp["pos"]), ""),
            })
    return lines


def side_share(W: np.ndarray, side: str) -> np.ndarray:
    """Per row, the share of the six wheel loads ``W`` (n, 6) that the wheels of ``side`` ("L" or
    "R") carry (nan where no wheel carries any)."""
    on = np.array([s == side for s in WHEEL_SIDE])
    total = W.sum(1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(total > 0.0, W[:, on].sum(1) / total, np.nan)


def roll_lines(rows, store) -> list[dict]:
    """T12 / T13: body slip and per-wheel PC = DP / W over the lifted roll, and the trial's energy
    (electrical input, then mechanical), beside the paper's."""
    lines = []
    for r in sorted(rows, key=lambda r: (r["instance"], r["method"], r["seed"])):
        if (r["instance"], r["method"]) not in PAPER_ROLL:
            continue
        ts = store.timeseries(r["key"])
        if not ts or "t" not in ts or "DP_c1" not in ts:
            continue
        t, W = _loads(ts)
        DP = np.array([np.asarray(ts[f"DP_{c}"], float) for c in WHEELS]).T
        sp = (lift_spans(r["info"].get("legged", [])) or [{}])[0]
        up = (t >= sp.get("t_up", np.inf)) & (t <= sp.get("t_down", -np.inf))
        vc = np.asarray(ts["v_cmd"], float)
        roll = up & (vc > 0.8 * np.nanmax(np.where(up, vc, 0.0))) if up.any() else up
        with np.errstate(divide="ignore", invalid="ignore"):
            sb = 1.0 - np.asarray(ts["v"], float)[roll] / vc[roll]
            pc = np.where(W[roll] > 1.0, DP[roll] / W[roll], np.nan)
        ps, pe = PAPER_ROLL[(r["instance"], r["method"])]
        lifted = [WHEELS.index(c) for c in sp.get("lift", "").split("+") if c in WHEELS]
        others = [i for i in range(6) if i not in lifted]
        lines.append({
            "task": r["instance"], "mode": r["method"], "seed": r["seed"], "status": r["status"],
            "lifted": sp.get("lift", ""), "lift": sp.get("lift_note", "not reached"),
            "s_b p5-p95 (roll)": f"{np.nanpercentile(sb, 5):.2f} to {np.nanpercentile(sb, 95):.2f}" if len(sb) else "",
            "PC median c1..c6 (roll)": " ".join("-" if i in lifted else f"{np.nanmedian(pc[:, i]):.2f}"
                                                for i in range(6)) if len(sb) else "",
            "least W of the grounded N": float(np.min(W[roll][:, others])) if len(sb) else float("nan"),
            # the trial's electrical input beside the paper's EC (measured electrically), the mechanical after it
            "energy kJ": metric(r, "energy_elec_kJ"), "mech kJ": metric(r, "energy_kJ"),
            "paper s_b": ps, "paper EC kJ": pe, "paper PC": PAPER_PC.get((r["instance"], r["method"]), ""),
        })
    return lines


def report_sections(page, store, rows, slug: str, plt) -> None:
    """The SWLM / DWLM sections of the srwmr report: T6/T7 wheel loads (tables and W_diff / W_fmr
    series against MC#10/#11 and the paper's figures), T12/T13 slip, PC and energy."""
    leg = [r for r in rows if r["method"] in ("swlm", "dwlm")]
    if not leg:
        return
    page.h2("Wheel-legged modes (SWLM / DWLM): lifts, wheel loads, slip and PC")
    page.p("Lifted heights are the controller's estimate from the encoders and the IMU (SWLM: the axle over the "
           "opposite wheel's; DWLM: over the line through its side's other two axles). T6/T7/T14 wheel loads are the "
           "F/T estimates the supervisor reads (they include a wheel on a rigid step); the T12/T13 PC = DP / W uses "
           "the soil's own forces. W_diff = "
           "W_max - W_min, W_fmr = max(W_max - c, c - W_min) over all six wheels (a lifted wheel counts "
           "as 0), c the average load the trial's scales.w_fmr_centre names (the six loads' mean, or the midrange "
           "of W_max and W_min: W_fmr = W_diff / 2). MC#10 W_diff <= 1100 N (SWLM) / 1300 N (DWLM), MC#11 "
           "W_fmr <= 700 N [S]. The lifted side's "
           "share (SWLM) is its three wheels' part of the six loads while the wheel is up; the paper's bound follows "
           "from its W_diff with the far wheel 'nearly suspended' (Task 6), the rest on the other side: 'the CoM "
           "shifting to the side of the unlifted wheel' (sec. 3.1).")
    ll = load_lines(leg, store)
    if ll:
        page.table(ll, list(ll[0]), csv_name=f"legged_loads{slug}.csv")
    rl = roll_lines(leg, store)
    if rl:
        page.h3("T12 / T13: the lifted roll (900 mm at 25 mm/s)")
        page.table(rl, list(rl[0]), csv_name=f"legged_roll{slug}.csv")
    for r in sorted(leg, key=lambda r: (r["instance"], r["method"], r["seed"])):
        if r["seed"] != min(x["seed"] for x in leg if x["instance"] == r["instance"] and x["method"] == r["method"]):
            continue
        if r["instance"] not in PAPER_LOADS and r["instance"] != "t14-obstacle":
            continue
        ts = store.timeseries(r["key"])
        if not ts or "t" not in ts:
            continue
        t, W = _loads(ts, ft=True)
        fig, ax = plt.subplots(2, 1, figsize=(9, 5.5), sharex=True)
        for i, c in enumerate(WHEELS):
            ax[0].plot(t, W[:, i], lw=0.8, label=c)
        ax[0].axhline(380, color="k", ls=":", lw=0.8, label="paper nominal ~380 N")
        ax[0].set_ylabel("wheel load N")
        ax[0].legend(fontsize="x-small", ncol=7)
        wd, fm = load_figures(W, fmr_centre(r))
        ax[1].plot(t, wd, label="W_diff")
        ax[1].plot(t, fm, label=f"W_fmr (about the {fmr_centre(r)})")
        lim = 1100 if r["method"] == "swlm" else 1300
        ax[1].axhline(lim, color="r", ls="--", lw=0.8, label=f"MC#10 {lim} N")
        ax[1].axhline(700, color="m", ls="--", lw=0.8, label="MC#11 700 N")
        for pos, (pdiff, _fmr) in PAPER_LOADS.get(r["instance"], {}).items():
            ax[1].axhline(pdiff, color="gray", ls=":", lw=0.6)
            ax[1].text(t[0], pdiff, f"paper W_diff {pos} {pdiff}", fontsize=6, va="bottom")
        for sp in lift_spans(r["info"].get("legged", [])):
            if "t_up" in sp and "t_down" in sp:
                for a in ax:
                    a.axvspan(sp["t_up"], sp["t_down"], color="y", alpha=0.2)
                ax[0].text(sp["t_up"], ax[0].get_ylim()[1] * 0.9, sp["lift"], fontsize=7)
        ax[1].set_ylabel("N")
        ax[1].set_xlabel("t s (shaded: wheel(s) up)")
        ax[1].legend(fontsize="x-small", ncol=4)
        fig.suptitle(f"{r['instance']} / {r['method']} seed {r['seed']}: {r['status']} ({r['info'].get('reason', '')})",
                     fontsize=9)
        fig.tight_layout()
        page.figure(fig, f"legged_loads_{r['instance']}_{r['method']}{slug}.png",
                    f"{r['instance']} / {r['method']}: wheel loads, W_diff and W_fmr beside MC#10/#11 and the paper")
        plt.close(fig)
