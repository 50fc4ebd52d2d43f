"""The CMU smooth-wheel trials (robomechanics/3d-terramechanics, MIT) beside the soil model.

189 averaged single-wheel trials of a smooth wheel (r 0.058 m, b 0.05 m) on sand: slip -1..0.9,
slip angle 0-90 deg, load ~16-26 N (package copy: ``terrabench/data/soil/cmu_smooth``).

Two parameter sets ("methods" of the ``cmu-smooth`` group):

- ``cmu-authors``: the authors' hand-tuned soil (``set_soil_params.m`` case K10_mini_smooth as
  stored at commit 229ee2d: k 8e3 kN/m^(n+2) with no cohesive modulus, n0 1.4, n1 0.01, n2 0.55,
  c 1.0 kPa, phi 29 deg, K 0.01 m, 1.33 t/m^3; the shared copy's README quotes the grousered
  wheel's n0 1.46 and K 0.021 m) and their per-slip-angle stress and exit angles (``trench_off_smooth.mat``:
  theta_m = (a0 + a1 s) theta_1, theta_r = (b0 + b1 s) theta_1). terrabench fits nothing here;
  the authors tuned these on the same trials, so it is their calibration, not a prediction.
  terrabench's own choices that their set does not fix: the braked-wheel theta_m continues the
  same line (a1_skid = a1) and the sidewall bulldozing and front ploughing factors are 1 (Hegedus'
  passive pressure, unscaled).
- ``cmu-fit-b0``: terrabench's fit of ten parameters (n, n1, n2, k_phi, K, plough, a1_skid, a0,
  a1, c_exit) to the 27 trials at slip angle 0 (drawbar pull, lateral force and sinkage, all
  slips incl. skid and the locked wheel); c, phi and gamma are the authors', the sidewall
  bulldozing factor stays 1 (the slip-angle-0 trials carry no lateral motion to fit it on). The 162 trials at
  slip angles 15-90 deg are predicted with the same parameters. The fit is stored in
  ``fit_beta0.json`` and redone by ``python -m terrabench.systems.soil.cmu --fit``.

Kinematics of a trial: carriage speed V at slip angle beta (measured), rim speed r omega
(measured): v_x = V cos(beta), v_y = V sin(beta); the model's longitudinal slip and lateral ratio
follow from them (see :mod:`terrabench.soil.terramechanics`). The data's own ``slip`` column is
defined on V (not v_x); it is what the plots use as abscissa.
"""

from __future__ import annotations

import argparse
import functools
import json
from importlib import resources
from pathlib import Path

import numpy as np

from terrabench.soil.terramechanics import SoilParams, WheelParams, solve_sinkage, wheel_forces

CMU_WHEEL = WheelParams(radius=0.058, width=0.05, mass=0.1)
BETAS = (0, 15, 30, 45, 60, 75, 90)
FIT_BETAS = (0,)
METHODS = ("cmu-authors", "cmu-fit-b0")
#: the issue's targets: RMS as a fraction of the load (DP, lateral) and in metres (sinkage)
TARGETS = {"DP_drive": 0.03, "DP_all": 0.08, "lateral": 0.04, "sinkage": 0.004}
FIT_NAMES = ("n", "n1", "n2", "log10_k_phi", "K", "plough", "a1_skid", "a0", "a1", "c_exit")
_AUTHORS = dict(form="bekker", n=1.4, n1=0.01, n2=0.55, k_c=0.0, k_phi=8e6, c=1000.0, phi_deg=29.0,
                gamma=1.33e3 * 9.81, K=0.01)
_DATA = "terrabench.data"


def _file(name: str):
    return resources.files(_DATA).joinpath("soil", "cmu_smooth", name)


@functools.lru_cache(maxsize=1)
def points() -> dict[str, np.ndarray]:
    """The 189 trials as arrays (SI): trial, beta_deg, slip (data's), s (model's longitudinal
    slip), C (lateral ratio), load_N, DP_N, lateral_N, sinkage_m, and the stds."""
    with _file("all_smooth_data.csv").open("r") as f:
        d = np.genfromtxt(f, delimiter=",", names=True)
    be = np.radians(d["avg_angle_deg"])
    V, rw = d["avg_Vx_mm_s"], d["avg_Vry_mm_s"]
    vx = np.maximum(V * np.cos(be), 0.0)
    vy = np.abs(V * np.sin(be))
    u = np.maximum(np.maximum(rw, vx), 1e-9)
    return {"trial": d["trial"].astype(int), "beta_deg": d["beta_deg"].astype(int), "slip": d["slip"],
            "s": np.clip((rw - vx) / u, -1.0, 1.0), "C": np.minimum(vy / u, 1e9), "load_N": -d["avg_Fz_N"],
            "DP_N": -d["avg_Fy_N"], "lateral_N": d["avg_Fx_N"], "sinkage_m": -d["avg_Z_mm"] / 1e3,
            "std_DP_N": d["std_Fy_N"], "std_lateral_N": d["std_Fx_N"], "std_sinkage_m": d["std_Z_mm"] / 1e3}


@functools.lru_cache(maxsize=1)
def tuned_angles() -> dict[int, tuple[float, float, float, float]]:
    """The authors' (a0, a1, b0, b1) per slip angle (deg)."""
    with _file("tuned_stress_angles.csv").open("r") as f:
        t = np.genfromtxt(f, delimiter=",", skip_header=1)
    return {int(r[0]): tuple(float(x) for x in r[1:]) for r in t}


@functools.lru_cache(maxsize=1)
def fitted() -> dict:
    """The stored fit (``fit_beta0.json``): parameter names, values, fitted points, residuals."""
    with _file("fit_beta0.json").open("r") as f:
        return json.load(f)


def soil_for(method: str, beta: int, x=None) -> SoilParams:
    """The soil of a parameter set at a slip angle (deg); ``x`` overrides the stored fit."""
    if method == "cmu-authors":
        a0, a1, b0, b1 = tuned_angles()[int(beta)]
        return SoilParams(name="cmu_authors", a0=a0, a1=a1, a1_skid=a1, c_exit=-b0, c_exit1=-b1, bulldoze=1.0,
                          plough=1.0,
                          source="robomechanics/3d-terramechanics set_soil_params.m K10_mini_smooth + "
                                 "trench_off_smooth.mat (authors' hand tuning)", **_AUTHORS)
    if method == "cmu-fit-b0":
        p = dict(zip(FIT_NAMES, fitted()["x"] if x is None else x))
        base = {k: v for k, v in _AUTHORS.items() if k not in ("n", "n1", "n2", "k_phi", "K")}
        return SoilParams(name="cmu_fit_b0", n=p["n"], n1=p["n1"], n2=p["n2"], k_phi=10 ** p["log10_k_phi"], K=p["K"],
                          plough=p["plough"], bulldoze=1.0, a1_skid=p["a1_skid"], a0=p["a0"], a1=p["a1"],
                          c_exit=p["c_exit"],
                          source="terrabench fit to the CMU trials at slip angle 0 (fit_beta0.json)", **base)
    raise ValueError(f"method={method!r} is unknown; valid: {', '.join(METHODS)}")


def model_point(method: str, i: int, x=None) -> dict[str, float]:
    """Model sinkage, drawbar pull, lateral force and torque of trial i (steady state at its load)."""
    p = points()
    sp = soil_for(method, int(p["beta_deg"][i]), x)
    s, C, load = float(p["s"][i]), float(p["C"][i]), float(p["load_N"][i])
    capped = 0.0
    try:
        z = float(solve_sinkage(load, s, sp, CMU_WHEEL, C))
    except ValueError:  # the load would sink the wheel past its axle: held at z = r
        z, capped = CMU_WHEEL.radius, 1.0
    f = wheel_forces(z, s, sp, CMU_WHEEL, C)
    return {"sinkage_m": z, "DP_N": float(f["DP"]), "lateral_N": float(f["Fy"]), "torque_Nm": float(f["T"]),
            "W_N": float(f["W"]), "sinkage_capped": capped}


def evaluate(method: str, idx=None, x=None) -> dict[str, np.ndarray]:
    """Model values of the trials ``idx`` (default all) as arrays."""
    p = points()
    idx = np.arange(len(p["trial"])) if idx is None else np.asarray(idx)
    rows = [model_point(method, int(i), x) for i in idx]
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def rms_table(meas: dict[str, np.ndarray], model: dict[str, np.ndarray], sel: np.ndarray) -> dict[str, float]:
    """RMS errors on the selected points: DP driving / all (fraction of load), lateral (fraction
    of load), sinkage (m); n = number of points (driving and all)."""
    load = meas["load_N"]
    drive = sel & (meas["slip"] >= 0)

    def frac(key, m):
        return float(np.sqrt(np.mean(((model[key][m] - meas[key][m]) / load[m]) ** 2))) if m.any() else float("nan")

    return {"DP_drive": frac("DP_N", drive), "DP_all": frac("DP_N", sel), "lateral": frac("lateral_N", sel),
            "sinkage": float(np.sqrt(np.mean((model["sinkage_m"][sel] - meas["sinkage_m"][sel]) ** 2))) if sel.any()
            else float("nan"), "n_drive": int(drive.sum()), "n_all": int(sel.sum())}


def _residuals(x, idx):
    p = points()
    m = evaluate("cmu-fit-b0", idx, x)
    load = p["load_N"][idx]
    # sinkage weighted so that the 4 mm target counts like 3 % of the load
    return np.r_[(m["DP_N"] - p["DP_N"][idx]) / load, (m["lateral_N"] - p["lateral_N"][idx]) / load,
                 (m["sinkage_m"] - p["sinkage_m"][idx]) / 0.004 * 0.03]


def fit(out: Path | None = None) -> dict:
    """Least-squares fit of FIT_NAMES on the slip-angle-0 trials, from the authors' values."""
    from scipy.optimize import least_squares

    p = points()
    idx = np.flatnonzero(np.isin(p["beta_deg"], FIT_BETAS))
    x0 = [1.4, 0.01, 0.55, np.log10(8e6), 0.01, 1.0, 0.45, 0.41, 0.45, 0.22]
    lb = [0.3, -0.5, -0.5, 4.0, 0.002, 0.0, -1.0, 0.0, -0.5, 0.0]
    ub = [2.95, 1.5, 1.5, 11.0, 0.1, 10.0, 1.0, 0.9, 0.5, 1.0]
    r = least_squares(_residuals, x0, args=(idx,), bounds=(lb, ub))
    at = [n for n, v, lo, hi in zip(FIT_NAMES, r.x, lb, ub) if min(v - lo, hi - v) < 1e-3 * (hi - lo)]
    res = {"names": list(FIT_NAMES), "x": [float(v) for v in r.x], "x0": x0, "lower": lb, "upper": ub,
           "at_bounds": at, "fitted_trials": [int(i) for i in p["trial"][idx]], "fitted_betas": list(FIT_BETAS),
           "cost": float(r.cost), "method": "scipy.optimize.least_squares (trf), residuals: DP/load, lateral/load, "
           "sinkage/4 mm x 0.03"}
    if out is not None:
        Path(out).write_text(json.dumps(res, indent=1) + "\n", encoding="utf-8")
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fit", action="store_true", help="refit on slip angle 0 and print the JSON")
    ap.add_argument("--out", type=Path, default=None, help="write the fit JSON here")
    args = ap.parse_args()
    if args.fit:
        print(json.dumps(fit(args.out), indent=1))
        return
    p = points()
    for method in METHODS:
        m = evaluate(method)
        fitted_mask = np.isin(p["beta_deg"], FIT_BETAS) if method == "cmu-fit-b0" else np.zeros(len(m["DP_N"]), bool)
        for label, sel in (("fitted", fitted_mask), ("predicted", ~fitted_mask), ("all", np.ones_like(fitted_mask))):
            print(method, label, {k: round(v, 4) for k, v in rms_table(p, m, sel).items()})


if __name__ == "__main__":
    main()
