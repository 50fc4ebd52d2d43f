"""Soil and wheel presets, each with its source (docs/assumptions-soil.md lists every value).

Stress-angle defaults of the classic presets (mars_soft, dry_sand, lunar_regolith):
    a0 = 0.4, a1 = 0.15 in theta_m = (a0 + a1 s) theta_1: the values Ishigami et al. (2007,
    J. Field Robotics 24(3), "Terramechanics-based model for steering maneuver of planetary
    exploration rovers on loose soil") use; Wong & Reece (1967) give the linear form. c_exit = 0:
    no rebound behind the wheel. No slip-dependent exponent (n1 = n2 = 0). The shear moduli K are
    not in Bekker's tables: they are taken from the project spec's range K ~ 0.01-0.02 m.

The two Mars-simulant presets for the HIT-MRII rover (``mars_very_loose``, ``mars_loose``) keep
those published pressure-sinkage and strength values and take the stress-angle, exit-angle and
slip-sinkage coefficients of the only measured smooth-wheel set we hold, the hand-tuned model of
robomechanics/3d-terramechanics (CMU, MIT licence, ``set_soil_params.m`` K10_mini_smooth and
``trench_off_smooth.mat`` at slip angle 0): a0 0.412, a1 0.455, exit ratio 0.224 + 0.007 s,
n1 0.01, n2 0.55, specific weight 1.33 t/m^3 x g. The rover issue calibrates them on T1.
"""

from __future__ import annotations

from terrabench.soil.terramechanics import SoilParams, WheelParams

#: Loose Mars simulant ("soft" set of the project spec, docs/../shared/specs/srwmr.md "Soil").
MARS_SOFT = SoilParams(
    name="mars_soft",
    n=1.0, k_c=1.4e3, k_phi=700e3, c=500.0, phi_deg=30.0, K=0.02,
    source=("terrabench spec srwmr.md 'Soil' (soft simulant: k_c 1.4 kN/m^(n+1), k_phi 700 "
            "kN/m^(n+2), n ~1.0, c ~0.5-1 kPa, phi ~30-35 deg, K ~0.01-0.02 m); lower ends taken"),
)

#: Dry sand, Bekker values as tabulated by Wong (Theory of Ground Vehicles, Table 2.3,
#: "Dry sand (Land Locomotion Lab.)": n 1.1, k_c 0.99 kN/m^(n+1), k_phi 1528.43 kN/m^(n+2),
#: c 1.04 kPa, phi 28 deg); also the spec's "dense simulant" moduli. K from the spec's range.
DRY_SAND = SoilParams(
    name="dry_sand",
    n=1.1, k_c=0.99e3, k_phi=1528.43e3, c=1040.0, phi_deg=28.0, K=0.01,
    source="Wong, Theory of Ground Vehicles, Table 2.3 (dry sand, LLL); K from spec range",
)

#: Lunar regolith, the Bekker set commonly quoted for lunar surface soil (n 1, k_c 1.4
#: kN/m^(n+1), k_phi 820 kN/m^(n+2), c 0.17 kPa, phi 35 deg, K 0.018 m; e.g. Lunar
#: Sourcebook, Heiken/Vaniman/French 1991, ch. 9, and Wong's book). Approximate: quoted
#: from memory of those tables, verify before relying on absolute values.
LUNAR = SoilParams(
    name="lunar_regolith",
    n=1.0, k_c=1.4e3, k_phi=820e3, c=170.0, phi_deg=35.0, K=0.018,
    source="commonly quoted lunar soil set (Lunar Sourcebook ch. 9; Wong) - approximate",
)

#: stress-angle / slip-sinkage coefficients of the CMU smooth-wheel model at slip angle 0
CMU_STRESS = dict(a0=0.412, a1=0.455, c_exit=0.224, c_exit1=0.007, n1=0.01, n2=0.55, gamma=1.33e3 * 9.81)

#: "Very loose" Mars simulant (HIT-MRII T1, freshly turned sandy loam): the spec's soft simulant
#: (mars_soft values) with the CMU stress coefficients. On the 0.15 m x 0.12 m wheel at 368 N:
#: DP > 0 for slips ~0.1-0.5 (max DP/W ~0.04), sinkage 56 mm at s = 0 rising to 82 mm at 0.65.
MARS_VERY_LOOSE = SoilParams(
    name="mars_very_loose",
    n=1.0, k_c=1.4e3, k_phi=700e3, c=500.0, phi_deg=30.0, K=0.02, **CMU_STRESS,
    source=("pressure-sinkage/strength: spec srwmr.md 'Soil' soft simulant (as mars_soft); stress angles, "
            "exit angle, slip-sinkage: robomechanics/3d-terramechanics K10_mini_smooth (CMU)"),
)

#: "Loose" Mars simulant (HIT-MRII T1, compacted): Wong's dry sand (LLL) = the spec's dense simulant,
#: with the CMU stress coefficients. At 368 N: DP > 0 for slips 0-0.75 (max DP/W ~0.13 at 0.2-0.3),
#: sinkage 43 mm at s = 0 rising to 63 mm at 0.65.
MARS_LOOSE = SoilParams(
    name="mars_loose",
    n=1.1, k_c=0.99e3, k_phi=1528.43e3, c=1040.0, phi_deg=28.0, K=0.01, **CMU_STRESS,
    source=("pressure-sinkage/strength: Wong, Theory of Ground Vehicles, Table 2.3 dry sand (LLL) = spec dense "
            "simulant; stress angles, exit angle, slip-sinkage: robomechanics/3d-terramechanics K10_mini_smooth (CMU)"),
)

SOILS: dict[str, SoilParams] = {s.name: s for s in (MARS_SOFT, DRY_SAND, LUNAR, MARS_VERY_LOOSE, MARS_LOOSE)}

#: HIT-MRII-like wheel: r = 150 mm from the paper's parameter settings (seed 001, sec. 8.2);
#: width 0.12 m is a terrabench assumption (the paper gives none).
HIT_MRII_WHEEL = WheelParams(radius=0.15, width=0.12, mass=2.0)


def soil(name: str) -> SoilParams:
    """Preset by name; unknown names raise ValueError listing the valid ones."""
    try:
        return SOILS[name]
    except KeyError:
        raise ValueError(f"soil={name!r} is unknown; valid: {', '.join(sorted(SOILS))}") from None
