"""The two soils of the paper, "very loose" (freshly turned) and "loose" (compacted) sandy loam.

The paper's soil table is lost. Both start from the project's soft Mars simulant
(:data:`terrabench.soil.presets.MARS_SOFT`: n 1.0, k_c 1.4 kN/m^2, c 0.5 kPa, phi 30 deg) and
differ only in compaction. **Calibration (the only fit): T1's WRM slip ranges** (seed 001 sec.
8.4: "the changes in sb for the WRM range from 0.3 to 0.65 and from 0.0 to 0.4 on ... very loose
and loose soil"). One parameter per soil is fitted so that the steady-state slip at which a wheel
carrying the nominal load (225 kg g / 6 = 368 N) makes zero drawbar pull (the slip a rover on
flat soil settles at) equals the middle of the range:

* very loose: target s* = 0.30, the lower end of the range (not its middle): with this model the
  drawbar pull of the very loose soil rises to a flat top near zero from s ~ 0.45 on, so a zero
  crossing at the middle (0.475) is tangent (no traction left at any slip, the robot could not
  have driven T1 at all, which it did for 153 s). Fitted k_phi (freshly turned soil has the
  lowest modulus of deformation), K = 0.02 m (upper end of the spec's range: least compacted).
* loose: target s* = 0.20; k_phi = 1528 kN/m^3 (the spec's dense-simulant value, not fitted),
  fitted K (compaction stiffens the shear response).

:func:`fit` re-runs the fit (bisection on the analytic steady state of
:mod:`terrabench.soil.terramechanics`); the constants below are its result and a test checks
they still reproduce the targets. Every other task is a prediction of the model.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from terrabench.soil.presets import HIT_MRII_WHEEL, MARS_SOFT, SOILS
from terrabench.soil.terramechanics import SoilParams, steady_state

NOMINAL_LOAD = 225.0 * 9.81 / 6
TARGETS = {"very_loose": 0.30, "loose": 0.20}
T1_RANGES = {"very_loose": (0.30, 0.65), "loose": (0.0, 0.40)}

#: fitted values (:func:`fit`, see the module docstring)
FIT_K_PHI_VERY_LOOSE = 937.2e3
FIT_K_LOOSE = 0.01783

VERY_LOOSE = dataclasses.replace(
    MARS_SOFT,
    name="very_loose",
    k_phi=FIT_K_PHI_VERY_LOOSE,
    K=0.02,
    source="MARS_SOFT with k_phi fitted to T1 very-loose WRM slip (srwmr.soils)",
)
LOOSE = dataclasses.replace(
    MARS_SOFT,
    name="loose",
    k_phi=1528e3,
    K=FIT_K_LOOSE,
    source="MARS_SOFT with the dense k_phi and K fitted to T1 loose WRM slip (srwmr.soils)",
)
SRWMR_SOILS = {"very_loose": VERY_LOOSE, "loose": LOOSE}


def zero_pull_slip(soil: SoilParams, load: float = NOMINAL_LOAD) -> float:
    """Slip (-) at which the drawbar pull of a wheel under ``load`` crosses zero (1.0: never)."""
    s = np.linspace(0.0, 0.95, 381)
    dp = steady_state(np.full_like(s, load), s, soil, HIT_MRII_WHEEL)["DP_N"]
    if dp.max() <= 0:
        return 1.0
    i = int(np.argmax(dp > 0))
    if i == 0:
        return 0.0
    return float(np.interp(0.0, dp[i - 1 : i + 1], s[i - 1 : i + 1]))


def fit() -> dict[str, float]:
    """Re-run the calibration; returns the fitted k_phi (very loose) and K (loose)."""

    def bisect(f, lo, hi, target, increasing):
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            if (f(mid) > target) == increasing:
                hi = mid
            else:
                lo = mid
        return 0.5 * (lo + hi)

    kphi = bisect(
        lambda k: zero_pull_slip(dataclasses.replace(MARS_SOFT, k_phi=k, K=0.02)),
        700e3,
        1500e3,
        TARGETS["very_loose"],
        increasing=False,
    )
    K = bisect(
        lambda k: zero_pull_slip(dataclasses.replace(MARS_SOFT, k_phi=1528e3, K=k)),
        0.008,
        0.03,
        TARGETS["loose"],
        increasing=True,
    )
    return {"k_phi_very_loose": kphi, "K_loose": K}


def srwmr_soil(name: str) -> SoilParams:
    """A soil by name: the two calibrated ones, or any preset of :mod:`terrabench.soil.presets`."""
    if name in SRWMR_SOILS:
        return SRWMR_SOILS[name]
    if name in SOILS:
        return SOILS[name]
    raise ValueError(f"soil={name!r} is unknown; valid: {', '.join(list(SRWMR_SOILS) + sorted(SOILS))}")


SOIL_NAMES = tuple(SRWMR_SOILS) + tuple(sorted(SOILS))
