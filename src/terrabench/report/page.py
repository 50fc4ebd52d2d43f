"""One static HTML report page for every system: sections, tables, figures, CSVs, provenance.

A system's report builds a :class:`Page`, adds sections in reading order and calls
:meth:`Page.finish`. The page

* writes every figure and CSV beside ``index.html`` and links it (nothing is loaded from
  outside the folder);
* remembers what it wrote in ``.terrabench-report.json`` and, on the next report into the same
  folder, removes the files of the earlier report that this one no longer writes, so a folder
  never shows figures from another store;
* ends with one provenance block (:func:`provenance_html`): the store, counts, times, and every
  config used, as its difference from this version's defaults plus the full JSON.

Tables are lists of dicts (one per line) with an explicit column order; the same lines go to
the HTML table and to the CSV (:meth:`Page.csv`), so what a reader sees is what they download.
"""

from __future__ import annotations

import csv
import datetime as _dt
import html
import json
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Sequence

from terrabench.paths import check_out_dir
from terrabench.report.variants import settings_diff

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from terrabench.benchmark.trial import TrialSpec
    from terrabench.systems.base import System

#: what a page wrote last time (pruned on the next report into the same folder)
MANIFEST = ".terrabench-report.json"

CSS = (
    "body{font-family:sans-serif;max-width:1400px;margin:1em auto;padding:0 1em}"
    "table{border-collapse:collapse;margin:.5em 0;font-size:90%}"
    "td,th{border:1px solid #bbb;padding:2px 6px;text-align:right}td:first-child{text-align:left}"
    "th{background:#eee}.far{background:#fdd;font-weight:bold}.note{color:#a60}"
    "img{max-width:100%}small{color:#777}pre{background:#f6f6f6;padding:.5em;font-size:80%}"
    "figure{margin:1em 0}figcaption{font-size:90%;color:#333}"
)


def cell(v: Any, digits: int = 4) -> str:
    """A CSV/HTML cell: blank for missing or NaN, floats rounded to ``digits`` decimals."""
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return ""
    if isinstance(v, float):
        return str(round(v, digits))
    return str(v)


def table_html(lines: Sequence[dict[str, Any]], columns: Iterable[str], *,
               headers: dict[str, str] | None = None, far: Callable[[dict[str, Any], str], bool] | None = None,
               fmt: Callable[[str, Any], str] | None = None) -> str:
    """An HTML table of ``lines`` (dicts), one column per name in ``columns``.

    Args:
        headers: column name -> header text (HTML); the name itself by default.
        far: ``(line, column) -> bool``: highlight that cell (class ``far``).
        fmt: ``(column, value) -> text`` for a cell (default :func:`cell`); escaped here.
    """
    columns = list(columns)
    headers = headers or {}
    head = "".join(f"<th>{headers.get(c, html.escape(c))}</th>" for c in columns)
    body = []
    for ln in lines:
        tds = []
        for c in columns:
            text = html.escape(fmt(c, ln.get(c)) if fmt else cell(ln.get(c)))
            cls = " class=far" if far is not None and far(ln, c) else ""
            tds.append(f"<td{cls}>{text}</td>")
        body.append("<tr>" + "".join(tds) + "</tr>")
    return f"<table><tr>{head}</tr>{''.join(body)}</table>"


def note(s: str) -> str:
    """A highlighted remark (escaped)."""
    return f"<p class=note>{html.escape(s)}</p>"


class Page:
    """The HTML body being assembled, and the files written beside it.

    Args:
        out_dir: the report folder (checked with :func:`terrabench.paths.check_out_dir`, then
            created if missing).
        title: the page title and its heading.
        outputs: names of files earlier versions of this report wrote without a manifest;
            removed when this report does not write them (the manifest covers the rest).
    """

    def __init__(self, out_dir: str | Path, title: str, outputs: Iterable[str] = ()):
        self.out_dir = check_out_dir(out_dir)
        self.out_dir.mkdir(parents=True, exist_ok=True)
        self.title = title
        self.legacy_outputs = tuple(outputs)
        self.written: set[str] = set()
        self.parts: list[str] = []

    # ------------------------------------------------------------------ content
    def raw(self, s: str) -> None:
        self.parts.append(s)

    def h2(self, s: str) -> None:
        self.raw(f"<h2>{s}</h2>")

    def h3(self, s: str) -> None:
        self.raw(f"<h3>{s}</h3>")

    def p(self, s: str) -> None:
        self.raw(f"<p>{s}</p>")

    def note(self, s: str) -> None:
        self.raw(note(s))

    def table(self, lines: Sequence[dict[str, Any]], columns: Iterable[str], *, csv_name: str | None = None,
              **kwargs: Any) -> None:
        """Show ``lines`` as a table (see :func:`table_html`); with ``csv_name`` also write and link the CSV."""
        columns = list(columns)
        if csv_name:
            self.csv(csv_name, lines, columns)
        link = f" <a href='{csv_name}'>{csv_name}</a>" if csv_name else ""
        self.raw(table_html(lines, columns, **kwargs) + link)

    def figure(self, fig: Figure, name: str, caption: str, dpi: int = 110) -> None:
        """Save the matplotlib ``fig`` as ``name`` (PNG) beside the page, close it, show it with
        ``caption`` (HTML)."""
        import matplotlib.pyplot as plt

        fig.savefig(self.out_dir / name, dpi=dpi, bbox_inches="tight")
        plt.close(fig)
        self.image(name, caption)

    def image(self, name: str, caption: str) -> None:
        """Show a file already written beside the page (e.g. a rendered strip) and keep it."""
        self.written.add(name)
        self.raw(f"<figure><a href='{name}'><img src='{name}' alt='{name}'></a>"
                 f"<figcaption>{caption}</figcaption></figure>")

    def csv(self, name: str, lines: Sequence[dict[str, Any]], columns: Iterable[str]) -> Path:
        """Write ``lines`` as ``name`` beside the page, one column per name in ``columns``."""
        columns = list(columns)
        path = self.out_dir / name
        with path.open("w", newline="") as f:
            w = csv.writer(f)
            w.writerow(columns)
            for ln in lines:
                w.writerow([cell(ln.get(c)) for c in columns])
        self.written.add(name)
        return path

    def snapshots(self, name: str, caption: str, system: System, spec: TrialSpec, times: Sequence[float],
                  **kwargs: Any) -> bool:
        """Render a strip of ``spec``'s episode at ``times`` as ``name`` and show it with ``caption``
        (:func:`terrabench.report.render.snapshot_strip`; ``kwargs``: width, height, overlay, track).
        Without headless GL, or for a stored trial whose config this version cannot run (a field
        since removed), the page says so in one note instead; returns whether it rendered."""
        from terrabench.report.render import GLUnavailable, snapshot_strip

        try:
            snapshot_strip(system, spec, times, self.out_dir / name, **kwargs)
        except GLUnavailable as exc:
            self.note(f"Snapshots skipped: {exc}. Set MUJOCO_GL=egl (Mesa) or MUJOCO_GL=osmesa (libosmesa6).")
            return False
        except ValueError as exc:  # a stored config this version cannot run any more (a field since removed)
            self.note(f"Snapshots skipped: the stored trial cannot be re-run by this version ({exc}); "
                      "the tables and figures above come from the stored rows.")
            return False
        self.image(name, caption)
        return True

    def clip(self, name: str, caption: str, system: System, spec: TrialSpec, seconds: float, *, every: int,
             fps: float = 25.0, start: float = 0.0, **kwargs: Any) -> bool:
        """Render ``seconds`` simulated seconds of ``spec``'s episode from ``start`` as the ``.mp4``
        clip ``name`` (a frame every ``every`` control periods, played at ``fps``) and show it with
        ``caption`` (:func:`terrabench.report.render.render_trial`; ``kwargs``: width, height,
        overlay, track). The episode is cut at ``start + seconds`` through the system's ``timeout_key``.
        Without headless GL, or for a stored config this version cannot run, one note instead
        (as :meth:`snapshots`); a replay that stops before the clip's start writes no clip and says
        so, one that stops inside it keeps the frames it has and says that; returns whether it
        rendered."""
        from terrabench.report.render import GLUnavailable, render_trial

        try:
            out = render_trial(system, cut_at(system, spec, start + seconds), self.out_dir / name, fps=fps,
                               every=every, start=start, **kwargs)
        except GLUnavailable as exc:
            self.note(f"Clip skipped: {exc}. Set MUJOCO_GL=egl (Mesa) or MUJOCO_GL=osmesa (libosmesa6).")
            return False
        except ValueError as exc:
            self.note(f"Clip skipped: the stored trial cannot be re-run by this version ({exc}).")
            return False
        if out["frames"] < out["expected"]:
            why = (f"the replay of {spec.method} on {spec.instance} seed {spec.seed} ended ({out['status']}) at "
                   f"{out['sim_time']:.2f} s")
            if not out["frames"]:
                (self.out_dir / name).unlink(missing_ok=True)
                self.note(f"Clip {name} skipped: {why}, before its start at {start:.2f} s.")
                return False
            self.note(f"Clip {name} is short: {why}, {out['frames']} of {out['expected']} frames.")
        self.written.add(name)
        self.raw(f"<figure><video src='{name}' controls muted loop preload='metadata' style='max-width:100%'>"
                 f"</video><figcaption>{caption} (<a href='{name}'>{name}</a>)</figcaption></figure>")
        return True

    def keep(self, name: str) -> Path:
        """Claim a file the caller writes itself (e.g. a clip); returns its path."""
        self.written.add(name)
        return self.out_dir / name

    # ------------------------------------------------------------------ finishing
    def finish(self) -> Path:
        """Write ``index.html`` and the manifest, remove outputs of earlier reports not written
        now; returns the path of ``index.html``."""
        index = self.out_dir / "index.html"
        title = html.escape(self.title)
        index.write_text(
            f"<!doctype html><html><head><meta charset='utf-8'><title>terrabench: {title}</title>"
            f"<style>{CSS}</style></head><body><h1>{title}</h1>\n" + "\n".join(self.parts) + "</body></html>")
        self.written.add(index.name)
        manifest = self.out_dir / MANIFEST
        earlier: list[str] = []
        if manifest.is_file():
            try:
                earlier = list(json.loads(manifest.read_text()).get("files", []))
            except (ValueError, AttributeError):
                earlier = []
        for name in {*earlier, *self.legacy_outputs} - self.written:
            if "/" not in name and name != MANIFEST:  # only files this page family writes, never outside
                (self.out_dir / name).unlink(missing_ok=True)
        manifest.write_text(json.dumps({"title": self.title, "files": sorted(self.written)}, indent=1))
        return index


def made_by(rows: Sequence[dict[str, Any]]) -> str:
    """One HTML line: the code and the machines that made ``rows`` (each row's ``info.host``:
    ``code``, ``cpu``, ``avx512``, ``pinned``), with counts, beside this installation's code."""
    from terrabench.benchmark.worker import code_fingerprint

    def tally(key: Callable[[dict[str, Any]], str]) -> str:
        n: dict[str, int] = {}
        for r in rows:
            k = key((r.get("info") or {}).get("host") or {})
            n[k] = n.get(k, 0) + 1
        return ", ".join(f"{html.escape(k)} ({c})" for k, c in sorted(n.items(), key=lambda kv: -kv[1]))

    def machine(h: dict[str, Any]) -> str:
        if not h:
            return "a host not recorded"
        cpu = h.get("cpu") or "a CPU not recorded"
        return f"{cpu}{', AVX-512' if h.get('avx512') else ''}{', pinned' if h.get('pinned') else ', unpinned'}"

    code = tally(lambda h: h.get("code") or "not recorded")
    return f"made by code {code} (this installation: {code_fingerprint()}); on {tally(machine)}"


def provenance_html(store: Any, rows: Sequence[dict[str, Any]], *, system_id: str,
                    default_config: Callable[[str, str], dict[str, Any] | None] | None = None,
                    extra: Sequence[str] = ()) -> str:
    """The provenance block: store, trial counts, total times, the version, and every config used
    (its difference from this version's defaults for the same method and instance, and the full JSON).

    Args:
        default_config: ``(method, instance) -> config dict`` this version plans without overrides
            (e.g. :meth:`terrabench.report.variants.Defaults.__call__`); None: no difference shown.
        extra: more ``<li>`` lines (HTML) for the list.
    """
    from terrabench._version import __version__

    configs: dict[str, dict[str, Any]] = {}
    first: dict[str, dict[str, Any]] = {}
    users: dict[str, list[str]] = {}
    counts: dict[str, int] = {}
    for r in rows:
        h = r["config_hash"]
        configs.setdefault(h, r["config"])
        first.setdefault(h, r)
        counts[h] = counts.get(h, 0) + 1
        if r["method"] not in users.setdefault(h, []):
            users[h].append(r["method"])
    sim = sum(float(r["metrics"].get("sim_time", 0.0) or 0.0) for r in rows)
    wall = sum(float(r.get("wall_time") or 0.0) for r in rows)
    seeds = sorted({r["seed"] for r in rows})
    parts = [
        "<ul>",
        f"<li>store: <code>{html.escape(str(Path(store.path).resolve()))}</code></li>",
        f"<li>{html.escape(system_id)} trials stored: {len(rows)}; seeds {html.escape(_ranges(seeds))}</li>",
        f"<li>total simulated time {sim / 3600:.3f} h, total trial wall time {wall / 3600:.3f} h</li>",
        f"<li>{made_by(rows)}</li>",
        *[f"<li>{x}</li>" for x in extra],
        f"<li>written by terrabench {__version__} at {_dt.datetime.now().isoformat(timespec='seconds')}</li>",
        "</ul><h3>Configs used</h3>",
    ]
    for h, cfg in sorted(configs.items(), key=lambda kv: (-counts[kv[0]], kv[0])):
        diff_text = ""
        if default_config is not None:
            r0 = first[h]
            d = default_config(r0["method"], r0.get("instance", ""))
            if d is not None:
                diff = [f"{k}={v!r}" for k, v in settings_diff(cfg, d).items()]
                diff_text = f"; differs from this version's defaults in: {'; '.join(diff) or 'nothing'}"
        parts.append(
            f"<details id='cfg-{h}'><summary><code>{h}</code>: {counts[h]} trial(s), methods "
            f"{html.escape(', '.join(users[h]))}{html.escape(diff_text)}</summary>"
            f"<pre>{html.escape(json.dumps(cfg, indent=2, sort_keys=True))}</pre></details>")
    return "\n".join(parts)


def _ranges(values: Sequence[int]) -> str:
    """``[0, 1, 2, 5]`` -> ``"0-2, 5"``."""
    out: list[str] = []
    for v in values:
        if out and "-" not in out[-1].lstrip("-") and int(out[-1]) == v - 1:
            out[-1] = f"{out[-1]}-{v}"
        elif out and "-" in out[-1].lstrip("-") and int(out[-1].rsplit("-", 1)[1]) == v - 1:
            out[-1] = f"{out[-1].rsplit('-', 1)[0]}-{v}"
        else:
            out.append(str(v))
    return ", ".join(out) or "none"


def cut_at(system: Any, spec: Any, seconds: float) -> Any:
    """``spec`` with its simulated time limit (the system's ``timeout_key``) at most ``seconds``."""
    import copy
    import dataclasses

    key = getattr(system, "timeout_key", None)
    if key is None:
        return spec
    config = copy.deepcopy(dict(spec.config))
    node = config
    *path, last = key.split(".")
    for part in path:
        node = node.setdefault(part, {})
    now = node.get(last)  # None: the spec carries no limit of its own
    node[last] = float(seconds) if now is None else min(float(now), float(seconds))
    return dataclasses.replace(spec, config=config)
