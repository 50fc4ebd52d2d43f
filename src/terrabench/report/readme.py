"""README.md's result blocks, rendered from the landed CSVs under ``docs/results/`` and from the
systems' own records, so the README's numbers cannot drift from the reports behind them.

A block in README.md is the text between ``<!-- generated: NAME -->`` and ``<!-- /generated -->``;
each :data:`BLOCKS` entry renders one (its last line names the CSVs it read)::

    python -m terrabench.report.readme --write   # rewrite every block of README.md in place
    python -m terrabench.report.readme --check   # exit 1 naming each block that differs from a fresh render

The render reads only the CSVs (``csv`` module) and the registry (:func:`terrabench.catalog.populate`):
no store, no simulation, deterministic. A required CSV that is absent is a :class:`MissingSource`
(exit 2, naming the file and the command that writes it); an optional column that is absent
renders as ``-``.
"""

from __future__ import annotations

import argparse
import csv
import difflib
import math
import re
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from decimal import ROUND_HALF_UP, Decimal
from pathlib import Path
from typing import Literal, TypedDict, overload

#: the command that rewrites the blocks (named in every --check failure)
WRITE_COMMAND = "python -m terrabench.report.readme --write"
BLOCK_RE = re.compile(r"<!-- generated: ([a-z0-9-]+) -->\n(.*?)<!-- /generated -->", re.S)

#: one CSV row as ``csv.DictReader`` reads it: column -> cell text
Row = dict[str, str]


class MissingSource(FileNotFoundError):
    """A CSV a block needs is not in ``docs/results`` (regenerate it with the named command)."""


@dataclass(frozen=True)
class Block:
    """One rendered block: its markdown body and the repository paths it was read from."""

    body: str
    sources: tuple[str, ...]

    def text(self, name: str) -> str:
        src = ", ".join(f"`{s}`" for s in self.sources)
        tail = f"Source: {src}." if self.sources else ""
        inner = "\n\n".join(p for p in (self.body.strip("\n"), tail) if p)
        return f"<!-- generated: {name} -->\n\n{inner}\n\n<!-- /generated -->"


def default_root() -> Path:
    """The source checkout (this file's repository when installed editable, else the working directory)."""
    here = Path(__file__).resolve().parents[3]
    return here if (here / "docs" / "results").is_dir() else Path.cwd()


# ---------------------------------------------------------------------------------------- reading
class Sources:
    """Reads CSVs under ``root`` and remembers which (for the block's source line)."""

    def __init__(self, root: Path) -> None:
        self.root = Path(root)
        self.used: list[str] = []

    def rel(self, path: Path) -> str:
        return path.relative_to(self.root).as_posix()

    @overload
    def read(self, rel: str, how: str = "", required: Literal[True] = True) -> list[Row]: ...

    @overload
    def read(self, rel: str, how: str = "", *, required: bool) -> list[Row] | None: ...

    def read(self, rel: str, how: str = "", required: bool = True) -> list[Row] | None:
        path = self.root / rel
        if not path.is_file():
            if required:
                raise MissingSource(f"{rel} is missing (README blocks are rendered from it)"
                                    + (f"; it is written by `{how}`" if how else ""))
            return None
        with path.open(newline="") as f:
            rows = list(csv.DictReader(f))
        if rel not in self.used:
            self.used.append(rel)
        return rows

    def glob(self, pattern: str) -> list[str]:
        return sorted(self.rel(p) for p in self.root.glob(pattern) if p.is_file())

    def block(self, body: str) -> Block:
        return Block(body, tuple(self.used))


# ---------------------------------------------------------------------------------------- formatting
def fnum(value: object) -> float | None:
    """A CSV cell as a finite float, else None (empty, '-', nan, text)."""
    try:
        v = float(str(value).strip())
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def num(value: object, digits: int) -> str:
    """``value`` with ``digits`` decimals, rounded half up from its decimal text as the CSV writes
    it (0.7925 -> 0.793); '-' when not a number; never '-0'."""
    v = fnum(value)
    if v is None:
        return "-"
    text = str(value).strip() if isinstance(value, str) else repr(v)
    s = f"{Decimal(text).quantize(Decimal(1).scaleb(-digits), rounding=ROUND_HALF_UP):f}"
    return s[1:] if s.startswith("-") and Decimal(s) == 0 else s


def cell(value: object) -> str:
    """A text cell for a markdown table: stripped, '-' when empty, pipes escaped."""
    s = str(value if value is not None else "").strip()
    return s.replace("|", "\\|") if s else "-"


def table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def split_parts(text: str) -> list[str]:
    """``"a, b=[1, 2], c"`` -> ``["a", "b=[1, 2]", "c"]`` (commas inside brackets kept)."""
    parts, depth, cur = [], 0, ""
    for ch in text:
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        parts.append(cur.strip())
    return parts


def label_parts(label: str) -> tuple[str, list[str]]:
    """A report label ``"MRS-CWC + A* (released waypoints, stiffness.mode=eq12)"`` -> base and parts."""
    if label.endswith(")") and " (" in label:
        base, _, rest = label.partition(" (")
        return base.strip(), split_parts(rest[:-1])
    return label.strip(), []


def natural(text: str) -> tuple:
    """Sort key with numbers compared as numbers (t2 < t10)."""
    return tuple(int(t) if t.isdigit() else t for t in re.split(r"(\d+)", text))


def span(values: Sequence[float], digits: int, unit: str = "") -> str:
    """``min-max`` (or one value) of ``values``."""
    lo, hi = num(min(values), digits), num(max(values), digits)
    return (lo if lo == hi else f"{lo} to {hi}") + unit


# ---------------------------------------------------------------------------------------- systems
def block_systems(src: Sources) -> Block:
    """The system table: each system's registry summary (what `terrabench list` prints), its
    ``status`` line and its groups with their sizes."""
    from terrabench.catalog import populate, system
    from terrabench.describe import instances_of

    reg = populate()
    rows = []
    for sid in sorted(reg.ids("system")):
        sysobj = system(sid)
        record = reg.get("system", sid)
        groups = ", ".join(f"{g} ({len(instances_of(sysobj, g))})" for g in sysobj.groups)
        status = (getattr(sysobj, "status", "") or "-").rstrip(".")
        rows.append([f"`{sid}`", cell(record.summary), cell(f"{status}; `--group` {groups}" if groups else status)])
    body = table(["system", "paper", "status"], rows)
    return Block(body, ())  # from the systems' own records, not a CSV


def block_envs(src: Sources) -> Block:
    from terrabench.catalog import populate, system

    reg = populate()
    have: list[tuple[str, tuple[str, ...]]] = []
    none: list[tuple[str, tuple[str, ...]]] = []
    for sid in sorted(reg.ids("system")):
        ids = system(sid).env_ids
        (have if ids else none).append((sid, ids))
    text = "Environments (`gymnasium.make`; `terrabench list` prints them): " + ", ".join(
        f"`{e}` ({sid})" for sid, ids in have for e in ids)
    if none:
        text += "; " + ", ".join(sid for sid, _ in none) + " " + ("has" if len(none) == 1 else "have") + " none"
    return Block(text + ".", ())


# ---------------------------------------------------------------------------------------- MRS-CWC
#: report-label parts of the released protocol's rows (a row with only these is a default row)
MRS_DEFAULT_PARTS = {"stiffness.mode=released", "released waypoints"}
#: report-label parts -> how the README names the variant
MRS_VARIANT_NAMES = {"stiffness.mode=eq12": "eq. 12 law", "our planner": "our planner",
                     "chain.wheel_drive=constraint": "rigid chain", "chain.wheel_drive=servo": "default chain",
                     "chain.wheel_shape=sphere": "sphere wheels"}
MRS_REPORT = "terrabench run mrs-cwc --methods all --group all && terrabench report mrs-cwc --out docs/results/mrs-cwc"


def mrs_variant(label: str) -> tuple[str, str]:
    """(base label, variant description; '' for the released protocol)."""
    base, parts = label_parts(label)
    extra = [p for p in parts if p not in MRS_DEFAULT_PARTS]
    named = [MRS_VARIANT_NAMES[p] for p in extra if p in MRS_VARIANT_NAMES]
    return base, ", ".join(named) if named else ", ".join(extra)


def _mrs_rows(src: Sources, folder: str) -> tuple[list[dict], dict[str, dict[tuple[str, str], dict]]]:
    """Rows in table order (method, config_hash) and group -> key -> CSV row."""
    by_group: dict[str, dict[tuple[str, str], dict]] = {}
    order: list[tuple[str, str]] = []
    for g in ("A", "B"):
        rows = src.read(f"{folder}/table_{g}.csv", MRS_REPORT)
        by_group[g] = {}
        for r in rows:
            key = (r.get("method", ""), r.get("config_hash", ""))
            by_group[g][key] = r
            if key not in order:
                order.append(key)
    lines = []
    for key in order:
        r = by_group["A"].get(key) or by_group["B"][key]
        base, variant = mrs_variant(r.get("label", key[0]))
        lines.append({"key": key, "method": key[0], "base": base, "variant": variant})
    return lines, by_group


def block_mrs_table(src: Sources) -> Block:
    lines, by_group = _mrs_rows(src, "docs/results/mrs-cwc")
    default = [ln for ln in lines if not ln["variant"]]
    variants = [ln for ln in lines if ln["variant"]]

    def trio(r: dict | None) -> list[str]:
        if r is None:
            return ["-", "-", "-"]
        return [f"{num(r.get('NSR'), 0)} ({num(r.get('NSR_paper'), 0)})",
                f"{num(r.get('NCR'), 1)} ({num(r.get('NCR_paper'), 1)})",
                f"{num(r.get('NEF'), 3)} ({num(r.get('NEF_paper'), 3)})"]

    rows = []
    for ln in default + variants:
        name = ln["base"] + (f", {ln['variant']}" if ln["variant"] else "")
        rows.append([cell(name)] + trio(by_group["A"].get(ln["key"])) + trio(by_group["B"].get(ln["key"])))

    def trials(lns: list[dict]) -> int:
        return int(sum(fnum(by_group[g].get(ln["key"], {}).get("n")) or 0 for ln in lns for g in ("A", "B")))

    terrains = {g: max((int(fnum(r.get("n")) or 0) for r in by_group[g].values()), default=0) for g in ("A", "B")}
    n_methods = len({ln["method"] for ln in default})
    head = (f"MRS-CWC benchmark, seed 0, default config: the {trials(default)} trials of the released laws "
            f"({n_methods} methods x {terrains['A'] + terrains['B']} terrains, "
            f"`terrabench run mrs-cwc --methods all --group all`)")
    if variants:
        head += (f" and {len(variants)} config variant{'s' * (len(variants) > 1)} "
                 f"({trials(variants)} trials: {', '.join(sorted({ln['variant'] for ln in variants}))})")
    head += ". Ours (paper's Tables II/III):"
    order = f"The first {len(default)} rows are the default (released) laws"
    order += f"; the last {len(variants)} are the variants." if variants else "."
    body = "\n\n".join([head, table(["method", "A: NSR %", "A: NCR %", "A: NEF", "B: NSR %", "B: NCR %", "B: NEF"],
                                    rows), order + " " + _mrs_leader(lines, by_group["B"]),
                          *_mrs_starts(src, "docs/results/mrs-cwc", by_group)])
    return src.block(body)


def _mrs_starts(src: Sources, folder: str, by_group: dict[str, dict[tuple[str, str], dict]]) -> list[str]:
    """The methods of the report run from several starts: NSR over them beside seed 0, each with
    its 95 % interval (the report's ``nsr_seeds.csv``); [] when every method has one seed."""
    seeds = [r for r in src.read(f"{folder}/nsr_seeds.csv", required=False) or ()
             if (fnum(r.get("n_seeds")) or 0) > 1]
    if not seeds:
        return []
    out = []
    for s in seeds:
        g, method = s.get("group", ""), s.get("method", "").partition("@")[0]
        seed0 = next((r for (m, _), r in by_group.get(g, {}).items()
                      if m == method and not mrs_variant(r.get("label", m))[1]), None)
        out.append([cell(mrs_variant(s.get("label", method))[0]), cell(g),
                    f"{num(seed0.get('NSR'), 0)} [{num(seed0.get('NSR_lo'), 0)}, {num(seed0.get('NSR_hi'), 0)}]"
                    if seed0 else "-",
                    f"{num(s.get('NSR'), 1)} [{num(s.get('NSR_lo'), 1)}, {num(s.get('NSR_hi'), 1)}]",
                    num(s.get("n_seeds"), 0), num(s.get("flip_share"), 0), num(s.get("NSR_paper"), 0)])
    head = ("The same report's trials from several starts (seeds > 0 move the start by up to 5 cm; the chain is "
            "chaotic, so one start is one draw): NSR over all starts with its 95 % bootstrap interval over "
            "terrains, beside seed 0 with its table's interval; *flips*: the share of terrains whose outcome "
            "differs between starts:")
    return [head, table(["method", "group", "seed 0: NSR % [95 % CI]", "all starts: NSR % [95 % CI]", "starts",
                         "flips %", "paper NSR %"], out)]


def _mrs_leader(lines: list[dict], rows_b: dict) -> str:
    """Whether the paper's method (CWC + TDT) leads the other TDT rows of group B in NSR, per law."""
    others = [(ln, rows_b[ln["key"]]) for ln in lines
              if not ln["variant"] and ln["method"].endswith("-tdt") and ln["method"] != "cwc-tdt"
              and ln["key"] in rows_b]
    cwc = [(ln, rows_b[ln["key"]]) for ln in lines if ln["method"] == "cwc-tdt" and ln["key"] in rows_b]
    if not others or not cwc:
        return ""
    best_ln, best = max(others, key=lambda o: (fnum(o[1].get("NSR")) or 0, o[0]["base"]))
    best_nsr = fnum(best.get("NSR")) or 0
    out = []
    for i, (ln, r) in enumerate(cwc):
        nsr = fnum(r.get("NSR")) or 0
        verb = "leads" if nsr > best_nsr else ("ties" if nsr == best_nsr else "does not lead")
        law = f"the {ln['variant']}" if ln["variant"] else "the released law"
        if i == 0:
            out.append(f"{verb} with {law} (NSR {num(r.get('NSR'), 0)} % against {best_ln['base']}'s "
                       f"{num(best.get('NSR'), 0)} %; paper {num(r.get('NSR_paper'), 0)} % against "
                       f"{num(best.get('NSR_paper'), 0)} %)")
        else:
            out.append(f"{verb} with {law} ({num(r.get('NSR'), 0)} %)")
    return f"Group B, TDT rows: the paper's method, {cwc[0][0]['base']}, " + " and ".join(out) + "."


def _terrain_span(src: Sources, folder: str, group: str) -> str:
    rows = src.read(f"{folder}/outcomes.csv", required=False)
    ids = sorted({r["terrain"] for r in rows or () if r.get("group") == group and r.get("terrain")}, key=natural)
    if not ids:
        return ""
    return ids[0] if len(ids) == 1 else f"{ids[0]}..{ids[-1]}"


class _SeedsLine(TypedDict):
    """One row of the several-starts table: a report folder's ``nsr_seeds.csv`` row and its seed-0 row."""

    folder: str
    group: str
    row: Row
    seed0: Row | None
    n_seeds: int
    n: int


def block_mrs_seeds(src: Sources) -> Block:
    """NSR over several starts (nsr_seeds.csv of each docs/results/mrs-cwc-seeds* report) beside
    the same report's seed-0 NSR."""
    paths = sorted(src.glob("docs/results/mrs-cwc-seeds*/nsr_seeds.csv"), key=lambda p: p.rsplit("/", 1)[0])
    if not paths:
        return Block("No report with several seeds per terrain is landed (`docs/results/mrs-cwc-seeds*/`).", ())
    lines: list[_SeedsLine] = []
    for rel in paths:
        folder = rel.rsplit("/", 1)[0]
        seeds = src.read(rel)
        tables = {g: {(r.get("method", ""), r.get("config_hash", "")): r
                      for r in src.read(f"{folder}/table_{g}.csv", required=False) or ()} for g in ("A", "B")}
        for s in seeds:
            g = s.get("group", "")
            method, _, short = s.get("method", "").partition("@")
            seed0 = next((r for (m, h), r in tables.get(g, {}).items()
                          if m == method and (not short or h.startswith(short))), None)
            lines.append({"folder": folder, "group": g, "row": s, "seed0": seed0,
                          "n_seeds": int(fnum(s.get("n_seeds")) or 0), "n": int(fnum(s.get("n_terrains")) or 0)})
    same = len({ln["n_seeds"] for ln in lines}) == 1
    out = []
    for ln in lines:
        s, seed0 = ln["row"], ln["seed0"]
        base, variant = mrs_variant(s.get("label", s.get("method", "")))
        terrains = _terrain_span(src, ln["folder"], ln["group"]) or "terrains"
        out.append([f"`{ln['folder'].rsplit('/', 1)[1]}/`", cell(ln["group"]),
                    cell(base + (f", {variant}" if variant else "")), f"{terrains} ({ln['n']})",
                    (f"{num(seed0.get('NSR'), 0)} [{num(seed0.get('NSR_lo'), 0)}, {num(seed0.get('NSR_hi'), 0)}]"
                     if seed0 else "-"),
                    f"{num(s.get('NSR'), 0)} [{num(s.get('NSR_lo'), 0)}, {num(s.get('NSR_hi'), 0)}]"
                    + ("" if same else f" ({ln['n_seeds']} seeds)"),
                    num(s.get("flip_share"), 0), num(s.get("NSR_paper"), 0)])
    over = f"seeds 0-{lines[0]['n_seeds'] - 1}" if same else "all seeds"
    body = ("NSR over several starts (seeds > 0 move the start by up to 5 cm) with its 95 % bootstrap interval "
            "over terrains, beside the same report's seed 0 (its table's 95 % interval); *flips*: the share of "
            "terrains whose outcome differs between starts:\n\n"
            + table(["report", "group", "method", "terrains (n)", "seed 0: NSR % [95 % CI]",
                     f"{over}: NSR % [95 % CI]", "flips %", "paper NSR %"], out))
    return src.block(body)


# ---------------------------------------------------------------------------------------- OCTOPUS
OCTO_REPORT = "terrabench report octopus --out docs/results/octopus"


def _paren(text: str) -> tuple[str, str]:
    """``"+0.34 (+0.60)"`` -> ``("+0.34", "+0.60")``; no parenthesis: (text, '')."""
    m = re.match(r"^\s*(.*?)\s*\((.*)\)\s*$", text or "")
    return (m.group(1), m.group(2)) if m else ((text or "").strip(), "")


def block_octopus(src: Sources) -> Block:
    rows = src.read("docs/results/octopus/tasks.csv", OCTO_REPORT)
    modes = list(dict.fromkeys(r.get("mode", "") for r in rows))
    tasks = list(dict.fromkeys(r.get("task", "") for r in rows))
    by = {(r.get("task"), r.get("mode")): r for r in rows}

    def outcome(r: dict | None) -> str:
        if r is None:
            return "-"
        text = cell(r.get("success"))
        statuses = r.get("statuses", "").strip()
        if statuses and (not statuses.startswith("success") or "," in statuses):
            text += f", {cell(statuses)}"
        paper = (r.get("paper") or "").strip()
        return text + (f"; paper: {cell(paper)}" if paper and paper != "-" else "")

    def paired(r: dict | None, col: str) -> str:
        if r is None or not r.get(col):
            return "-"
        ours, paper = _paren(r[col])
        return cell(ours) + (f" ({cell(paper)})" if paper and paper != "-" else "")

    lead = modes[0] if modes else ""
    out = [[f"`{t}`"] + [outcome(by.get((t, m))) for m in modes]
           + [paired(by.get((t, lead)), c) for c in ("max pitch rad", "max roll rad", "min margin m")] for t in tasks]
    n = sorted({int(fnum(r.get("n")) or 0) for r in rows})
    seeds = "/".join(str(k) for k in n)
    body = (f"`terrabench run octopus --methods clm,ccm --group steps --seeds {seeds}` (and `--group rough` for "
            f"the rough-ground rows, beyond the paper): successes of {seeds} seeds per task and mode, with how the "
            f"others ended and the paper's result; the extreme pitch and roll and the lowest static stability "
            f"margin of {lead} over the seeds, the paper's in parentheses:\n\n"
            + table(["task"] + modes + [f"{lead} max pitch rad", f"{lead} max roll rad", f"{lead} min margin m"], out))
    pairs = [(fnum(o), fnum(p)) for o, p in (_paren(r.get("min margin m", "")) for r in rows if r.get("mode") == lead)]
    margins = [(o, p) for o, p in pairs if o is not None and p is not None]
    if margins:
        body += (f"\n\nWhere the paper gives a static margin, {lead}'s is {span([o for o, _ in margins], 2, ' m')} "
                 f"against its {span([p for _, p in margins], 2, ' m')}.")
    from terrabench.systems.octopus.report import LOW_COLUMN

    counts = [(t, by[(t, lead)].get(LOW_COLUMN) or "") for t in tasks if (t, lead) in by]
    if counts and all(k for _, k in counts):  # a tasks.csv written before the column has none
        low = [f"{t} {k}" for t, k in counts if not k.startswith("0/")]
        body += (f" Its {LOW_COLUMN.replace('trials with ', 'trials with a ')} (from the front, the release "
                 "teeter on the first edge, which trials fall there decided by sub-micrometre differences in the "
                 "start, `benchmarks/start_sensitivity_study.py`; from the side, the walk mounting the second riser "
                 "at an angle, nose and roll up: `docs/octopus.md`): " + (", ".join(low) or "none")
                 + (", none in the other tasks." if low and len(low) < len(counts) else "."))
    return src.block(body)


# ---------------------------------------------------------------------------------------- soil
SOIL_REPORT = "terrabench run soil --group single-wheel && terrabench report soil --out docs/results/soil"


def block_soil_single(src: Sources) -> Block:
    paths = src.glob("docs/results/soil/single_*.csv")
    if not paths:
        raise MissingSource(f"docs/results/soil/single_*.csv are missing; they are written by `{SOIL_REPORT}`")
    soils: dict[str, list[dict]] = {}
    for rel in paths:
        soils[rel.rsplit("/", 1)[1][len("single_"):-len(".csv")]] = src.read(rel)
    first = next(iter(soils.values()))
    cols = list(first[0]) if first else []
    dp_cols = [c for c in cols if c.startswith("DP/W s=")]
    sink_cols = [c for c in cols if c.startswith("sinkage mm")]
    loads = sorted(v for v in {fnum(r.get("load N")) for rs in soils.values() for r in rs} if v is not None)
    ref = 100.0 if 100.0 in loads else (loads[0] if loads else None)
    heavy = loads[-1] if loads else None

    def pick(rs: list[dict], load: float | None) -> dict | None:
        got = [r for r in rs if fnum(r.get("load N")) == load]
        return next((r for r in got if r.get("variant") == "rig"), got[0] if got else None)

    rows = []
    for name, rs in soils.items():
        a, b = pick(rs, ref), pick(rs, heavy)
        rows.append([f"`{name}`"] + [num(a.get(c), 3) if a else "-" for c in dp_cols]
                    + [num(b.get(dp_cols[-1]), 3) if b and dp_cols else "-"])
    header = ["soil"] + [f"DP/W {c[len('DP/W '):]}, {num(ref, 0)} N" for c in dp_cols]
    if dp_cols:
        header.append(f"DP/W {dp_cols[-1][len('DP/W '):]}, {num(heavy, 0)} N")
    dp_err, sink_err = [], []
    for rs in soils.values():
        for load in loads:
            rig = next((r for r in rs if r.get("variant") == "rig" and fnum(r.get("load N")) == load), None)
            ana = next((r for r in rs if r.get("variant") == "analytic" and fnum(r.get("load N")) == load), None)
            if rig and ana:
                dp_err += _abs_diffs(rig, ana, dp_cols)
                sink_err += _abs_diffs(rig, ana, sink_cols)
    body = (f"`terrabench run soil --group single-wheel` ({len(soils)} soils, loads "
            f"{' / '.join(num(v, 0) for v in loads)} N, the MuJoCo rig and the analytic steady state): "
            "drawbar-pull coefficient DP/W of the rig on the HIT-MRII wheel")
    if dp_err:
        body += (f"; the rig, with the soil forces applied in the episode loop's per-substep hook, is within "
                 f"{num(100 * max(dp_err), 2)} % of the load of the equations' drawbar pull"
                 + (f" and {num(max(sink_err), 1)} mm of their sinkage" if sink_err else "")
                 + " at these slips")
    body += ":\n\n" + table(header, rows)
    return src.block(body)


def _abs_diffs(a: Row, b: Row, cols: Sequence[str]) -> list[float]:
    """``|a[c] - b[c]|`` for each column ``c`` where both cells are numbers."""
    out = []
    for c in cols:
        x, y = fnum(a.get(c)), fnum(b.get(c))
        if x is not None and y is not None:
            out.append(abs(x - y))
    return out


def _rms(text: str) -> tuple[str, str, bool | None]:
    """``"24.7 (target 3: misses by 21.7)"`` -> ("24.7", "3", False)."""
    m = re.match(r"^\s*([-+\d.]+)\s*\(target\s*([-+\d.]+):\s*(meets|misses[^)]*)\)\s*$", text or "")
    if not m:
        return (text or "").strip(), "", None
    return m.group(1), m.group(2), m.group(3) == "meets"


def block_soil_cmu(src: Sources) -> Block:
    rows = src.read("docs/results/soil/cmu_rms.csv",
                    "terrabench run soil --group cmu-smooth && terrabench report soil --out docs/results/soil")
    cols = list(rows[0]) if rows else []
    metric_cols = cols[3:] if len(cols) > 3 else []
    targets = {c: next((t for t in (_rms(r.get(c, ""))[1] for r in rows) if t), "") for c in metric_cols}
    out = []
    for r in rows:
        line = [cell(r.get(c)) for c in cols[:3]]
        for c in metric_cols:
            value, _, ok = _rms(r.get(c, ""))
            line.append(f"**{cell(value)}**" if ok else cell(value))
        out.append(line)
    header = cols[:3] + [c + (f", target {targets[c]}" if targets[c] else "") for c in metric_cols]
    totals = [int(m.group(1)) for r in rows for m in [re.search(r"/(\d+)\s*$", r.get(cols[2], "") if cols[2:] else "")]
              if m]
    n = max(totals) if totals else 0
    body = (f"The {n} measured CMU smooth-wheel trials beside the model (`terrabench run soil --group cmu-smooth`, "
            "`docs/soil.md`): RMS error of each parameter set, drawbar pull and lateral force in % of the load "
            "(bold: meets its target):\n\n" + table(header, out))
    return src.block(body)


# ---------------------------------------------------------------------------------------- srwmr
SRWMR_REPORT = ("terrabench run srwmr --group tasks && terrabench run srwmr --group steer && "
                "terrabench report srwmr --out docs/results/srwmr")


def _status_counts(rows: list[dict]) -> dict[str, int]:
    counts: dict[str, int] = {}
    for r in rows:
        for part in (r.get("statuses") or "").split(","):
            m = re.match(r"^\s*([a-z_]+)\s+(\d+)\s*$", part)
            if m:
                counts[m.group(1)] = counts.get(m.group(1), 0) + int(m.group(2))
    return counts


def block_srwmr_tasks(src: Sources) -> Block:
    rows = src.read("docs/results/srwmr/tasks.csv", SRWMR_REPORT)
    rows = sorted(rows, key=lambda r: natural(r.get("task", "")))
    counts = _status_counts(rows)
    n = sum(int(fnum(r.get("n")) or 0) for r in rows)
    out = []
    for r in rows:
        status = (r.get("statuses") or "").strip()
        status = re.sub(r"^([a-z_]+) 1$", r"\1", status)
        out.append([f"`{r.get('task', '')}`", cell(r.get("mode", "").upper()), cell(status),
                    num(r.get("body slip"), 2), num(r.get("progress m"), 2), num(r.get("time s"), 0),
                    num(r.get("energy kJ"), 2), cell(r.get("paper"))])
    statuses = ", ".join(f"{k} {v}" for k, v in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])))
    body = (f"`terrabench run srwmr --group tasks` and `--group steer` (sec. 8.6's in-place steering) ({n} trials, "
            "seed 0, on "
            f"{len({r.get('task') for r in rows})} task instances: {statuses}): body slip s_b, progress along the "
            "task, simulated time and energy beside what the paper reports for the task. Our energies are the "
            "motors' electrical input (the motor model, `motors.HIT_MRII`; the mechanical |tau w| is the CSV's "
            "`mech kJ`); the paper's units are inconsistent (`docs/srwmr.md`), so the two are not on one scale:\n\n"
            + table(["task", "mode", "status", "s_b", "progress m", "time s", "energy kJ", "paper"], out))
    return src.block(body)


def block_srwmr_t14(src: Sources) -> Block:
    rows = src.read("docs/results/srwmr/t14.csv", SRWMR_REPORT)
    out = []
    for r in rows:
        done = fnum(r.get("success"))
        n = fnum(r.get("n"))
        finished = "-" if done is None else (f"{int(done)}/{int(n)}" if n else str(int(done)))
        out.append([cell(r.get("mode", "").upper()), finished,
                    f"{num(r.get('distance mm'), 0)} ({num(r.get('paper distance mm'), 0)})",
                    f"{num(r.get('time s'), 0)} ({num(r.get('paper time s'), 0)})",
                    f"{num(r.get('energy kJ'), 1)} ({num(r.get('paper energy kJ'), 0)})"]
                   + ([cell(r.get("note"))] if any(x.get("note") for x in rows) else []))
    header = ["mode", "success", "distance mm (paper)", "time s (paper)", "energy kJ (paper)"]
    if any(x.get("note") for x in rows):
        header.append("note")
    body = (f"T14, the obstacle task, in {len(rows)} modes (ours, the paper's in parentheses):\n\n"
            + table(header, out) + "\n\n" + _t14_order(rows))
    t10 = src.read("docs/results/srwmr/t10.csv", required=False)
    if t10:
        held = [r for r in t10 if fnum(r.get("paper power W")) is not None and fnum(r.get("power W")) is not None]
        if held:
            body += (f"\n\nT10 (RCLM, chassis held at {', '.join(r.get('period mm', '') for r in held)} mm): "
                     f"mean electrical input power (the motor model) {span(_nums(held, 'power W'), 1, ' W')}, "
                     "the paper's "
                     f"{span(_nums(held, 'paper power W'), 0, ' W')}.")
    return src.block(body)


def _nums(rows: Sequence[Row], col: str) -> list[float]:
    """The numbers in column ``col`` of ``rows`` (cells that are not numbers skipped)."""
    return [v for v in (fnum(r.get(col)) for r in rows) if v is not None]


def _t14_order(rows: list[dict]) -> str:
    """The modes ordered by time and energy: ours among the modes that finished, the paper's."""
    def order(rs: list[dict], col: str) -> str:
        got = [(fnum(r.get(col)), r.get("mode", "").upper()) for r in rs if fnum(r.get(col)) is not None]
        return " < ".join(m for _, m in sorted(got))

    done = [r for r in rows if (fnum(r.get("success")) or 0) > 0]
    names = ", ".join(r.get("mode", "").upper() for r in done) or "none"
    text = f"Finished: {names}."
    if len(done) > 1:
        text += (f" Among them, by time {order(done, 'time s')} (paper {order(done, 'paper time s')}), by energy "
                 f"{order(done, 'energy kJ')} (paper {order(done, 'paper energy kJ')}).")
    return text + (f" The paper's order over all {len(rows)}: time {order(rows, 'paper time s')}, energy "
                   f"{order(rows, 'paper energy kJ')}.")


# ---------------------------------------------------------------------------------------- beams
def block_beams(src: Sources) -> Block:
    rows = src.read("docs/results/beams/paper_vs_readings.csv",
                    "terrabench run beams && terrabench report beams --out docs/results/beams")
    cols = list(rows[0]) if rows else ["result", "paper", "edge", "centre"]
    names = {"edge": "edge (default)", "centre": "centre (`--set layout.gap_reading=centre`)"}
    out = [[cell(r.get(c)) for c in cols] for r in rows]
    body = ("The paper's stated results beside both readings of the gap d = 0.12 m: between the plates' inner "
            "edges (default) and between their centre lines:\n\n" + table([names.get(c, c) for c in cols], out))
    return src.block(body)


#: block name -> renderer (README.md holds exactly these blocks)
BLOCKS: dict[str, Callable[[Sources], Block]] = {
    "systems-table": block_systems,
    "envs": block_envs,
    "mrs-cwc-table": block_mrs_table,
    "mrs-cwc-seeds": block_mrs_seeds,
    "octopus-tasks": block_octopus,
    "soil-single-wheel": block_soil_single,
    "soil-cmu": block_soil_cmu,
    "srwmr-tasks": block_srwmr_tasks,
    "srwmr-t14": block_srwmr_t14,
    "beams-readings": block_beams,
}


# ---------------------------------------------------------------------------------------- README
def render(root: Path | None = None) -> dict[str, str]:
    """Every block's full text (markers included), rendered fresh from ``root``'s CSVs."""
    root = Path(root) if root is not None else default_root()
    return {name: fn(Sources(root)).text(name) for name, fn in BLOCKS.items()}


def found_blocks(text: str) -> dict[str, str]:
    """The blocks in a README's text: name -> full text (markers included)."""
    out: dict[str, str] = {}
    for m in BLOCK_RE.finditer(text):
        if m.group(1) in out:
            raise ValueError(f"README.md has block {m.group(1)!r} twice")
        out[m.group(1)] = m.group(0)
    return out


def problems(text: str, fresh: dict[str, str]) -> list[str]:
    """What differs between a README's blocks and a fresh render (empty: up to date)."""
    have = found_blocks(text)
    out = []
    for name in have:
        if name not in fresh:
            out.append(f"README.md block {name!r} is not one this module renders (known: {', '.join(fresh)})")
    for name, want in fresh.items():
        if name not in have:
            out.append(f"README.md has no block {name!r}: add `<!-- generated: {name} -->` ... "
                       f"`<!-- /generated -->` where it belongs, then run `{WRITE_COMMAND}`")
        elif have[name] != want:
            diff = "\n".join(list(difflib.unified_diff(have[name].splitlines(), want.splitlines(), "README.md",
                                                       "fresh render", lineterm="", n=0))[:40])
            out.append(f"README.md block {name!r} differs from a fresh render of its sources: run "
                       f"`{WRITE_COMMAND}`\n{diff}")
    return out


def rewrite(text: str, fresh: dict[str, str]) -> str:
    """``text`` with every known block replaced by its fresh render (others left for --check)."""
    return BLOCK_RE.sub(lambda m: fresh.get(m.group(1), m.group(0)), text)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m terrabench.report.readme", description=__doc__.split("\n\n")[0])
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", action="store_true", help="rewrite README.md's generated blocks in place")
    mode.add_argument("--check", action="store_true", help="exit 1 if README.md differs from a fresh render")
    ap.add_argument("--root", type=Path, default=None, help="the source checkout (default: this one)")
    args = ap.parse_args(argv)
    root = args.root or default_root()
    readme = root / "README.md"
    try:
        fresh = render(root)
    except MissingSource as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    text = readme.read_text()
    if args.write:
        new = rewrite(text, fresh)
        if new != text:
            readme.write_text(new)
        left = problems(new, fresh)
        for p in left:
            print(p, file=sys.stderr)
        print(f"README.md: {len(fresh) - len(left)} of {len(fresh)} blocks rendered"
              + (" (changed)" if new != text else " (unchanged)"))
        return 1 if left else 0
    left = problems(text, fresh)
    for p in left:
        print(p, file=sys.stderr)
    return 1 if left else 0


if __name__ == "__main__":
    sys.exit(main())
