"""Navigation metrics of the MRS-CWC benchmark as pure functions (spec section 5).

Per trial: minimum leader-target distance d_min (0 below the success threshold), effective
distance D_ef = L0 - d_min, NCR = D_ef / L0, journey J (3-D path length of the leader),
NEF = D_ef / J, energy E and NEC = E / D_ef. Per group: NSR and the means.
"""

from __future__ import annotations

import math
from typing import Iterable, Mapping

import numpy as np


def journey(xyz: np.ndarray) -> float:
    """Sum of 3-D displacements between consecutive samples, shape (T, 3) -> m.

    Starts at the first sample; the released code also counted the first sample's |z| by
    starting from the origin, which is a bug we do not copy.
    """
    xyz = np.asarray(xyz, float)
    if len(xyz) < 2:
        return 0.0
    return float(np.linalg.norm(np.diff(xyz, axis=0), axis=1).sum())


def navigation_metrics(
    xyz: np.ndarray,
    target_xy: tuple[float, float],
    start_xy: tuple[float, float],
    energy: float,
    success_threshold: float,
) -> dict[str, float]:
    """Per-trial figures from the leader's path.

    Args:
        xyz: leader positions at each control step, shape (T, 3) (m).
        target_xy, start_xy: (m).
        energy: total electrical-mechanical energy E (J).
        success_threshold: XY distance counted as arrival (m).

    Returns:
        ``success`` (0/1), ``d_min`` (m), ``d_final`` (m), ``L0`` (m), ``D_ef`` (m), ``NCR``,
        ``journey`` (m), ``NEF``, ``energy`` (J), ``NEC`` (J/m; NaN when D_ef <= 0).
    """
    xyz = np.asarray(xyz, float)
    L0 = math.hypot(target_xy[0] - start_xy[0], target_xy[1] - start_xy[1])
    d = np.hypot(xyz[:, 0] - target_xy[0], xyz[:, 1] - target_xy[1])
    d_min = float(d.min())
    success = d_min < success_threshold
    if success:
        d_min = 0.0
    D_ef = L0 - d_min
    J = journey(xyz)
    return {
        "success": float(success),
        "d_min": d_min,
        "d_final": float(d[-1]),
        "L0": L0,
        "D_ef": D_ef,
        "NCR": D_ef / L0,
        "journey": J,
        "NEF": D_ef / J if J > 0 else float("nan"),
        "energy": float(energy),
        "NEC": energy / D_ef if D_ef > 0 else float("nan"),
    }


def group_summary(trials: Iterable[Mapping[str, float]]) -> dict[str, float]:
    """NSR (%), mean NCR (%), mean NEF, mean NEC (J/m), pooled NEC and counts over a group's trials.

    A trial that ended ``diverged`` or ``error`` still counts as a trial and as a failure;
    its metrics enter the means if it has them. NaNs are left out of the means, so each mean
    also comes with ``n_NCR``, ``n_NEF``, ``n_NEC``: the number of trials behind it.
    """
    rows = list(trials)
    n = len(rows)
    if n == 0:
        return {"n": 0, "NSR": float("nan"), "NCR": float("nan"), "NEF": float("nan"), "NEC": float("nan")}

    def finite(key: str) -> np.ndarray:
        vals = np.array([r.get(key, float("nan")) for r in rows], float)
        return vals[np.isfinite(vals)]

    def mean(vals: np.ndarray) -> float:
        return float(vals.mean()) if len(vals) else float("nan")

    # NEC = E / D_ef explodes for trials that barely moved toward the target, so its mean is
    # heavy-tailed; the pooled ratio sum(E) / sum(D_ef) is the robust companion figure
    energy = np.array([r.get("energy", float("nan")) for r in rows], float)
    d_ef = np.array([r.get("D_ef", float("nan")) for r in rows], float)
    ok = np.isfinite(energy) & np.isfinite(d_ef)
    nec_pooled = float(energy[ok].sum() / d_ef[ok].sum()) if ok.any() and d_ef[ok].sum() > 0 else float("nan")
    successes = sum(1 for r in rows if r.get("success", 0.0) == 1.0)
    lo, hi = wilson_interval(successes, n)
    ncr, nef, nec = finite("NCR"), finite("NEF"), finite("NEC")
    return {
        "n": n,
        "successes": successes,
        "NSR": 100.0 * successes / n,
        "NSR_lo": 100.0 * lo,
        "NSR_hi": 100.0 * hi,
        "NCR": 100.0 * mean(ncr),
        "NEF": mean(nef),
        "NEC": mean(nec),
        "NEC_pooled": nec_pooled,
        "n_NCR": len(ncr),
        "n_NEF": len(nef),
        "n_NEC": len(nec),
    }


def wilson_interval(k: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """95 % Wilson score interval of a binomial proportion k/n."""
    if n == 0:
        return float("nan"), float("nan")
    p = k / n
    den = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return max(0.0, centre - half), min(1.0, centre + half)
