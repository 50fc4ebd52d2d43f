"""Soil and wheel presets, each with its source (docs/assumptions-soil.md lists every value).

Shared choices for all soils (Wong-Reece stress distribution):
    a0 = 0.4, a1 = 0.15: Wong & Reece (1967) report theta_m = (c1 + c2 s) theta_1 with
    c1 ~ 0.4 and c2 ~ 0.15-0.35 (as quoted in Wong, *Theory of Ground Vehicles*, ch. 2;
    approximate: the lower end of c2 is taken). c_exit = 0: no rebound behind the wheel
    (the classical Wong-Reece assumption). The shear moduli K are not in Bekker's tables: they
    are taken from the project spec's range K ~ 0.01-0.02 m (approximate).
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

SOILS: dict[str, SoilParams] = {s.name: s for s in (MARS_SOFT, DRY_SAND, LUNAR)}

#: HIT-MRII-like wheel: r = 150 mm from the paper's parameter settings (seed 001, sec. 8.2);
#: width 0.12 m is a terrabench assumption (the paper gives none).
HIT_MRII_WHEEL = WheelParams(radius=0.15, width=0.12, mass=2.0)


def soil(name: str) -> SoilParams:
    """Preset by name; unknown names raise ValueError listing the valid ones."""
    try:
        return SOILS[name]
    except KeyError:
        raise ValueError(f"soil={name!r} is unknown; valid: {', '.join(sorted(SOILS))}") from None
