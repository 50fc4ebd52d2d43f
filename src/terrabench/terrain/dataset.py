"""The 100 released MRS-CWC benchmark terrains as named entries, and new ones like them.

Group A = rows 1-50 of ``terrain_values_slope_lessthan30.csv``, group B = the 50 rows of
``terrain_values_slope_morethan30.csv`` (spec section 1). Ids are ``A-01 ... A-50`` and
``B-01 ... B-50``. The CSVs ship in ``terrabench/data/mrs_cwc`` with their provenance.
"""

from __future__ import annotations

import csv
import functools
import io
import re
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Sequence

import numpy as np

from terrabench.terrain import sine_sum
from terrabench.terrain.sine_sum import SineSumParams
from terrabench.terrain.stats import slope_stats

GROUP_FILES = {"A": "terrain_values_slope_lessthan30.csv", "B": "terrain_values_slope_morethan30.csv"}
WAYPOINT_FILES = {"A": "astar_waypoints_lessthan30.csv", "B": "astar_waypoints_morethan30.csv"}
GROUP_SIZE = 50
GROUPS = ("A", "B")
REQUIRED_COLUMNS = (
    "Size", "XY Proportion", "Height",
    "Ch1 Freq", "Ch1 Ampl", "Ch1 Phase",
    "Ch2 Freq", "Ch2 Ampl", "Ch2 Phase",
    "Ch3 Freq", "Ch3 Ampl", "Ch3 Phase",
)
_ID = re.compile(r"^([AB])-?(\d{1,2})$")


@dataclass(frozen=True)
class Terrain:
    """A named benchmark terrain.

    Attributes:
        id: ``"A-01"`` ... ``"B-50"``.
        group: ``"A"`` (mean slope < 30 deg) or ``"B"`` (> 30 deg).
        row: 1-based row in its CSV.
        params: the sine-sum parameters.
    """

    id: str
    group: str
    row: int
    params: SineSumParams

    def heights(self) -> np.ndarray:
        return sine_sum.heights(self.params)

    def stats(self) -> dict[str, float]:
        return slope_stats(self.heights(), *sine_sum.spacing(self.params))


def _data_text(name: str) -> str:
    return resources.files("terrabench.data").joinpath("mrs_cwc", name).read_text()


def parse_rows(text: str, source: str = "<csv>") -> list[SineSumParams]:
    """Parse a terrain CSV's text into parameter rows; one clear error for bad columns or values."""
    reader = csv.DictReader(io.StringIO(text))
    header = reader.fieldnames or []
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise ValueError(f"{source}: missing column(s) {', '.join(missing)}; required: {', '.join(REQUIRED_COLUMNS)}")
    out = []
    for n, row in enumerate(reader, start=1):
        try:
            vals = {c: float(row[c]) for c in REQUIRED_COLUMNS}
        except (TypeError, ValueError):
            bad = {c: row.get(c) for c in REQUIRED_COLUMNS if not _is_float(row.get(c))}
            raise ValueError(f"{source}: row {n} has non-numeric value(s) {bad}") from None
        try:
            out.append(
                SineSumParams(
                    size=vals["Size"],
                    xy_proportion=vals["XY Proportion"],
                    height=vals["Height"],
                    freq=tuple(vals[f"Ch{k} Freq"] for k in (1, 2, 3)),
                    ampl=tuple(vals[f"Ch{k} Ampl"] for k in (1, 2, 3)),
                    phase=tuple(vals[f"Ch{k} Phase"] for k in (1, 2, 3)),
                )
            )
        except ValueError as exc:
            raise ValueError(f"{source}: row {n}: {exc}") from None
    return out


def _is_float(s: object) -> bool:
    try:
        float(s)  # type: ignore[arg-type]
        return True
    except (TypeError, ValueError):
        return False


@functools.cache
def benchmark_terrains() -> dict[str, Terrain]:
    """All 100 benchmark terrains keyed by id, A-01..A-50 then B-01..B-50."""
    out: dict[str, Terrain] = {}
    for group, fname in GROUP_FILES.items():
        rows = parse_rows(_data_text(fname), fname)[:GROUP_SIZE]
        for k, params in enumerate(rows, start=1):
            tid = f"{group}-{k:02d}"
            out[tid] = Terrain(tid, group, k, params)
    return out


def normalise_id(tid: str) -> str:
    m = _ID.match(tid.strip().upper())
    if not m:
        return tid
    return f"{m.group(1)}-{int(m.group(2)):02d}"


def get(tid: str) -> Terrain:
    """A terrain by id (``"B-07"``, ``"b7"`` also accepted)."""
    terrains = benchmark_terrains()
    key = normalise_id(tid)
    if key not in terrains:
        raise ValueError(f"unknown terrain id {tid!r}; valid: A-01 ... A-50, B-01 ... B-50")
    return terrains[key]


def select(ids: Sequence[str] | None = None, group: str | None = None) -> list[Terrain]:
    """Terrains by explicit ids, or by group ``"A"``, ``"B"`` or ``"all"`` (default all)."""
    if ids:
        return [get(t) for t in ids]
    g = (group or "all").strip()
    if g.lower() == "all":
        return list(benchmark_terrains().values())
    if g.upper() not in GROUPS:
        raise ValueError(f"unknown terrain group {group!r}; valid: A, B, all")
    return [t for t in benchmark_terrains().values() if t.group == g.upper()]


@functools.cache
def released_waypoints(tid: str) -> np.ndarray:
    """The waypoints the released A* variants follow, shape (n, 2), world frame (m)."""
    t = get(tid)
    reader = csv.DictReader(io.StringIO(_data_text(WAYPOINT_FILES[t.group])))
    for row in reader:
        if int(row["Terrain_Num"]) == t.row:
            pts = [tuple(map(float, p.split(","))) for p in row["Path"].split(";") if p.strip()]
            return np.asarray(pts, float)
    raise ValueError(f"no released waypoints for terrain {tid!r}")


def generate(
    n: int,
    rng: np.random.Generator,
    *,
    slope_band_deg: tuple[float, float] = (0.0, 30.0),
    max_slope_deg: float = 70.0,
    max_draws: int = 100_000,
) -> list[SineSumParams]:
    """Draw ``n`` new terrains whose mean per-axis slope lies in ``slope_band_deg``.

    This is how the paper made its groups (A: mean slope < 30 deg, B: > 30 deg, maximum slope
    <= 70 deg); the averaging rule is :func:`terrabench.terrain.stats.slope_stats`'s
    ``mean_axis_slope_deg``, which separates the released groups.
    """
    lo, hi = slope_band_deg
    if not (0 <= lo < hi):
        raise ValueError(f"slope band must satisfy 0 <= low < high, got {slope_band_deg!r}")
    out: list[SineSumParams] = []
    for _ in range(max_draws):
        p = sine_sum.random_params(rng)
        s = slope_stats(sine_sum.heights(p), *sine_sum.spacing(p))
        if lo <= s["mean_axis_slope_deg"] < hi and s["max_slope_deg"] <= max_slope_deg:
            out.append(p)
            if len(out) == n:
                return out
    raise ValueError(f"only {len(out)} of {n} terrains fell in slope band {slope_band_deg} after {max_draws} draws")


def load_csv(path: str | Path) -> list[SineSumParams]:
    """Terrains from a user's CSV in the released format."""
    p = Path(path)
    if p.is_dir():
        raise ValueError(f"terrain CSV {str(p)!r} is a folder; give one CSV file in the released format")
    if not p.is_file():
        raise ValueError(f"terrain CSV not found: {str(p)!r}")
    return parse_rows(p.read_text(), str(p))


def write_csv(params: Sequence[SineSumParams], path: str | Path) -> Path:
    """Write terrains in the released CSV format (``Seed`` is written as 0: it is never used)."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    with p.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(("Seed",) + REQUIRED_COLUMNS)
        for q in params:
            chans = [v for k in range(3) for v in (q.freq[k], q.ampl[k], q.phase[k])]
            w.writerow([0, q.size, q.xy_proportion, q.height, *chans])
    return p
