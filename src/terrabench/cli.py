"""The ``terrabench`` command line: list, run, report, perf, terrain.

Bad input (unknown ids, a broken CSV, an incompatible results file, a non-positive timeout)
ends with one red line naming the bad value and the valid choices, exit status 2, and no
traceback; nothing already stored is touched.
"""

from __future__ import annotations

import functools
import math
import os
import signal
from pathlib import Path
from typing import Callable, Optional

import typer
from rich.console import Console
from rich.markup import escape as rich_escape

from terrabench import portable

app = typer.Typer(add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  help="Robots that cross unknown rough terrain by touching it.")
terrain_app = typer.Typer(no_args_is_help=True, help="Inspect benchmark terrains.")
app.add_typer(terrain_app, name="terrain")
console = Console()
err_console = Console(stderr=True)

DEFAULT_STORE = Path("results") / "terrabench.duckdb"
#: Commands that run trials (a report re-runs stored trials for its clips): they re-execute under
#: the CPU-path pins of :mod:`terrabench.portable`, so their bits do not depend on the CPU.
SIMULATING_COMMANDS = ("run", "perf", "render", "report")

#: ``terrabench --debug``: bad input also prints its traceback (e.g. a system that fails to import)
DEBUG = {"on": False}


def friendly(fn: Callable) -> Callable:
    """Turn ValueError (our 'bad input' signal) into one clear line and exit status 2."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except ValueError as exc:
            if DEBUG["on"]:
                err_console.print_exception()
            err_console.print(f"[bold red]error:[/] {rich_escape(str(exc))}", highlight=False, soft_wrap=True)
            raise typer.Exit(2) from None

    return wrapper

def _split(value: Optional[str], flag: str = "", valid: Optional[Callable[[], str]] = None) -> Optional[list[str]]:
    """``"a,b"`` -> ``["a", "b"]``; None stays None; an empty list is bad input, not 'all', and so
    is an empty item (``"a,,b"``, ``"a,"``): refused, not dropped. ``valid()`` gives the valid ids."""
    if value is None:
        return None
    items = [v.strip() for v in value.split(",")]
    choices = f"; valid: {valid()}" if valid is not None else ""
    if not any(items):
        raise ValueError(f"{flag or 'a list option'} was given an empty list ({value!r}); name at least one id"
                         + choices)
    if not all(items):
        raise ValueError(f"{flag or 'a list option'} {value!r} has an empty item (ids are separated by single "
                         f"commas){choices}")
    return items


def _valid_methods(sysobj) -> Callable[[], str]:
    return lambda: ", ".join(list(sysobj.methods()) + ["all"])


def _valid_instances(sysobj) -> Callable[[], str]:
    def text() -> str:
        from terrabench.benchmark.plan import choices_text
        from terrabench.describe import instances_of

        return choices_text(instances_of(sysobj, None), sysobj.id)

    return text

def _limit_overrides(sysobj, overrides: dict, *, timeout: Optional[float] = None,
                     threshold: Optional[float] = None) -> dict:
    """``--timeout`` / ``--threshold`` as the config keys the system names (one mapping for every
    command); checked positive; ValueError when the system has no such setting."""
    from terrabench.systems.base import check_finite_positive

    for value, key, flag, unit in ((timeout, sysobj.timeout_key, "--timeout", "simulated seconds"),
                                   (threshold, sysobj.threshold_key, "--threshold", "m")):
        if value is not None:
            check_finite_positive(flag, value, unit)
            if key is None:
                raise ValueError(f"system {sysobj.id!r} has no {flag} setting")
            overrides[key] = value
    return overrides


def _version(value: bool) -> None:
    if value:
        from terrabench._version import __version__

        console.print(f"terrabench {__version__}")
        raise typer.Exit()

@app.callback()
def _main(ctx: typer.Context,
          version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                       help="print the version and exit"),
          debug: bool = typer.Option(False, "--debug", help="print the traceback of an error, too")) -> None:
    """Robots that cross unknown rough terrain by touching it."""
    DEBUG["on"] = debug
    if ctx.invoked_subcommand != "list":  # list ends with the error itself
        _warn_broken_systems()


def _warn_broken_systems() -> None:
    """One stderr line per installed system that failed to load."""
    import sys

    from terrabench.catalog import SystemImportError, load_failures

    try:
        failures = load_failures()
    except SystemImportError:
        return  # a bad TERRABENCH_PLUGINS item: the command itself reports it
    for err in failures.values():
        if DEBUG["on"] and err.__cause__ is not None:
            import traceback

            traceback.print_exception(err.__cause__, file=sys.stderr)
        err_console.print(f"[yellow]warning:[/] {rich_escape(str(err))}", highlight=False, soft_wrap=True)

@app.command("list")
@friendly
def list_cmd(
    system: Optional[str] = typer.Argument(None, help="a system id: its methods, groups (sizes) and instance ids"),
    statuses: bool = typer.Option(False, "--statuses", help="what each trial status means"),
) -> None:
    """Systems, scenarios and methods, one line each; `list SYSTEM` for one system's groups and ids."""
    from terrabench.catalog import populate

    if statuses:
        from terrabench.catalog import system as get_system
        from terrabench.describe import statuses_table

        console.print(statuses_table([get_system(sid) for sid in populate().ids("system")]))
        return
    if system is not None:
        from terrabench.catalog import system as get_system
        from terrabench.describe import system_tables

        for part in system_tables(get_system(system)):
            console.print(part, highlight=False)
        return
    reg = populate()
    for kind in ("system", "scenario", "method"):
        console.print(f"[bold]{kind}s[/]")
        for r in reg.entries(kind):
            prefix = f"{r.system}:" if kind == "method" else ""
            console.print(f"  {prefix}{r.id:<28} {r.summary}", highlight=False)
    console.print("[bold]environments[/] (gymnasium.make)")
    from terrabench.catalog import load_failures
    from terrabench.catalog import system as get_system

    for r in reg.entries("system"):
        for env_id in get_system(r.id).env_ids:
            console.print(f"  {env_id:<28} {r.id}", highlight=False)
    console.print("more: `terrabench list SYSTEM` (groups, sizes, instance ids), `terrabench config SYSTEM` "
                  "(--set keys and ranges), `terrabench list --statuses`", highlight=False)
    for err in load_failures().values():
        raise err

@app.command("pins")
def pins_cmd() -> None:
    """The environment that pins every library's CPU code path (`eval "$(terrabench pins)"` before
    starting Python makes a notebook or a learner give the stored rows' bits)."""
    import shlex

    for key, value in portable.pins().items():
        typer.echo(f"export {key}={shlex.quote(value)}")


@app.command("config")
@friendly
def config_cmd(system: str = typer.Argument(..., help="system id, e.g. mrs-cwc")) -> None:
    """Every `--set KEY=VALUE` key of a system: default, type, valid range and meaning."""
    from terrabench.catalog import system as get_system
    from terrabench.describe import config_table

    console.print(config_table(get_system(system)))

@app.command()
@friendly
def run(
    system: str = typer.Argument(..., help="system id, e.g. mrs-cwc"),
    methods: Optional[str] = typer.Option(None, help="comma-separated method ids, or 'all'"),
    terrains: Optional[str] = typer.Option(None, help="comma-separated terrain/case ids, e.g. A-01,B-07"),
    group: Optional[str] = typer.Option(None, help="instance group, e.g. mrs-cwc A or B; see `terrabench list SYSTEM`"),
    seeds: int = typer.Option(1, help="seeds per (method, terrain); seed 0 is the released protocol"),
    backend: str = typer.Option("local", help="local or ray"),
    workers: Optional[int] = typer.Option(None, help="parallel trials (default: all cores)"),
    address: Optional[str] = typer.Option(None, help="Ray cluster address (with --backend ray)"),
    store: Path = typer.Option(DEFAULT_STORE, help="DuckDB results file"),
    timeout: Optional[float] = typer.Option(None, help="simulated-time limit per trial (s)"),
    threshold: Optional[float] = typer.Option(None, help="success distance to the target (m)"),
    set_: list[str] = typer.Option([], "--set", help="config override KEY=VALUE (repeatable)"),
    vary: list[str] = typer.Option([], "--vary", help="run every value of a setting, KEY=V1,V2,... (repeatable: "
                                   "every combination); the variants side by side at the end, as `compare`"),
    quiet: bool = typer.Option(False, help="no per-trial table"),
    rerun_other_code: bool = typer.Option(False, help="run again the stored trials another terrabench code "
                                          "made (a different package digest): their rows are replaced"),
) -> None:
    """Run a system's trials (skipping those already stored) and print its table."""
    from terrabench.benchmark.runner import BACKENDS, run_trials
    from terrabench.benchmark.store import ResultsStore
    from terrabench.catalog import system as get_system
    from terrabench.config import parse_overrides, parse_variations

    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; valid: {', '.join(BACKENDS)}")
    if backend == "ray":
        import importlib.util

        if importlib.util.find_spec("ray") is None:
            raise ValueError("backend 'ray' needs the ray extra: pip install 'terrabench[ray]'")
    if workers is not None and workers < 1:
        raise ValueError(f"--workers must be at least 1, got {workers}")
    if address is not None and backend != "ray":
        raise ValueError(f"--address {address!r} needs --backend ray (the local backend has no cluster)")
    if seeds < 1:
        raise ValueError(f"--seeds must be at least 1, got {seeds}")
    from terrabench.paths import check_out_file

    check_out_file(store, flag="--store")  # a results file this run can create or write
    sysobj = get_system(system)
    overrides = parse_overrides(set_)
    _limit_overrides(sysobj, overrides, timeout=timeout, threshold=threshold)
    if group is not None and not group.strip():
        raise ValueError(f"--group was given an empty value; valid: {', '.join(list(sysobj.groups) + ['all'])}")
    request = dict(methods=_split(methods, "--methods", _valid_methods(sysobj)),
                   instances=_split(terrains, "--terrains", _valid_instances(sysobj)), group=group, seeds=seeds)
    variations = parse_variations(vary)
    if variations:
        from terrabench.benchmark.plan import plan_variations

        specs = plan_variations(sysobj, vary=variations, overrides=overrides, **request)
    else:
        specs = sysobj.plan(overrides=overrides, **request)
    if not specs:  # e.g. a method that does not apply to the group: an error, not a silent no-op
        from terrabench.describe import methods_for

        where = f"group {group!r}" if group else f"instances {terrains!r}" if terrains else "the default group"
        valid = methods_for(sysobj, group=group, instances=_split(terrains, "--terrains"))
        raise ValueError(f"{system}: --methods {methods!r} plan no trials in {where}; "
                         f"methods that apply there: {', '.join(valid) or 'none'}")
    signal.signal(signal.SIGTERM, _interrupt)  # a scheduler's TERM stops as cleanly as Ctrl-C
    new_store = not store.exists()
    with ResultsStore(store) as st:
        try:
            summary = _run_with_progress(run_trials, specs, st, backend, workers, address, tuple(variations),
                                         rerun_other_code)
        except BaseException:
            if new_store and st.trial_count() == 0:  # e.g. no Ray cluster: leave no empty store behind
                st.close()
                for leftover in (store, store.with_name(store.name + ".wal")):
                    leftover.unlink(missing_ok=True)
            raise
        rows = st.rows(keys=[s.key for s in specs])
    if not quiet:
        console.print(_trial_table(rows, sysobj))
    if variations:  # the system's summary would mix the variants: them side by side instead
        from terrabench.report import compare as cmp

        lines = cmp.compare(rows, sysobj)
        shown = cmp.shown_metrics(lines, sysobj)
        console.print(_compare_table(lines, shown))
        console.print(f"more metrics: terrabench compare {sysobj.id} --store {store} --metrics NAME,...",
                      highlight=False)
    else:
        console.print(sysobj.summarize(rows))
    console.print(f"{summary.describe()}; store: {store}", highlight=False)
    if summary.interrupted:
        err_console.print("[yellow]interrupted:[/] finished trials are stored; run the same command to resume.")
        raise typer.Exit(130)
    if summary.faults:
        err_console.print(f"[yellow]{summary.faults} trial(s) ended in error[/] (a fault, not physics; see the "
                          "reasons above); run the same command to retry them.")
        raise typer.Exit(1)

def _clip_window(sysobj, spec, start, span, at, store) -> tuple[float, float | None]:
    """(first frame s, length s or None = to the end) of a clip from ``--start``/``--span``/``--at``."""
    for name, v in (("--start", start), ("--span", span)):
        if v is not None and not (math.isfinite(v) and v >= (0.0 if name == "--start" else 1e-9)):
            raise ValueError(f"{name} must be a finite number of seconds {'>= 0' if name == '--start' else '> 0'}, "
                             f"got {v}")
    if at is None:
        return (start or 0.0), span
    if start is not None:
        raise ValueError("--at and --start both place the clip; give one")
    from terrabench.benchmark.store import ResultsStore

    if not store.exists():
        raise ValueError(f"--at {at!r} reads the stored trial, but the store {store} does not exist; run it first "
                         f"(terrabench run {sysobj.id} --methods {spec.method} --terrains {spec.instance} "
                         f"--store {store})")
    with ResultsStore(store, read_only=True) as st:
        rows = st.rows(keys=[spec.key])
        if not rows:
            raise ValueError(f"--at {at!r}: {spec.method} on {spec.instance} seed {spec.seed} with this config is not "
                             f"in {store}; run it first (terrabench run {sysobj.id} --methods {spec.method} "
                             f"--terrains {spec.instance} --store {store})")
        events = sysobj.clip_events(rows[0], st.timeseries(spec.key))
    if at not in events:
        raise ValueError(f"--at {at!r} is not an event of this trial; valid: {', '.join(sorted(events))}")
    length = 60.0 if span is None else span
    return max(0.0, events[at] - 0.25 * length), length


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt

def _run_with_progress(run_trials, specs, store, backend, workers, address, varied=(), rerun_other_code=False):
    """Run ``specs`` with a progress bar (a plain line per trial when not on a terminal); a sweep's
    lines name each trial's values of the ``varied`` keys."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    plain = not console.is_terminal  # piped or in CI: one plain line per trial instead of a bar
    progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
                        TimeElapsedColumn(), TimeRemainingColumn(), TextColumn("{task.fields[last]}"),
                        console=console, transient=False, disable=plain)
    task = None

    def on_start(n: int) -> None:
        nonlocal task
        task = progress.add_task("trials", total=n, last="")

    done = 0

    def values(spec) -> str:
        from terrabench.report.variants import flatten

        flat = flatten(dict(spec.config))
        return "".join(f" {k}={flat[k]}" for k in varied if k in flat)

    def on_result(spec, result) -> None:
        nonlocal done
        done += 1
        progress.update(task, advance=1, last=f"{spec.method} {spec.instance}{values(spec)}: {result.status}")
        if plain:
            print(f"[{done}/{progress.tasks[0].total:.0f}] {spec.method} {spec.instance}{values(spec)} seed "
                  f"{spec.seed}: {result.status} ({result.wall_time:.1f} s)", flush=True)

    with progress:
        # in_process=False: even --workers 1 runs trials in a child process, so a trial that
        # crashes the interpreter or hangs costs only itself
        return run_trials(specs, store, backend=backend, workers=workers, address=address,
                          on_result=on_result, on_start=on_start, in_process=False,
                          rerun_other_code=rerun_other_code)

def _trial_table(rows, sysobj):
    from rich.table import Table

    t = Table(title="trials")
    for c in ("method", "instance", "seed", "status", "metrics", "wall s"):
        t.add_column(c)
    for r in rows:
        m = r["metrics"]
        keys = sysobj.headline_metrics or [k for k, v in m.items() if isinstance(v, (int, float))][:6]
        shown = " ".join(f"{k}={m[k]:.3g}" for k in keys if k in m)
        t.add_row(r["method"], r["instance"], str(r["seed"]), r["status"], shown, f"{r['wall_time']:.1f}")
    return t

def _compare_table(lines, metrics, hidden: int = 0):
    """The variants side by side (:mod:`terrabench.report.compare`'s lines) in ``metrics``;
    ``hidden``: how many more metrics the lines carry (said under the table)."""
    from rich.table import Table

    from terrabench.report import compare as cmp

    caption = f"{hidden} more metrics: --metrics NAME,... (every one in --out CSV)" if hidden else None
    t = Table(title="variants side by side: median \\[min, max] over seeds", caption=caption)
    for c in ["instance", "variant", "statuses"] + list(metrics):
        t.add_column(c, overflow="fold")  # a label is what tells the lines apart: never cut
    for ln in lines:
        t.add_row(ln.instance, ln.label, cmp.statuses_text(ln), *(cmp.cell_text(ln.metrics[m]) for m in metrics))
    return t


@app.command()
@friendly
def compare(
    system: str = typer.Argument(..., help="system id"),
    store: Path = typer.Option(DEFAULT_STORE, help="DuckDB results file"),
    methods: Optional[str] = typer.Option(None, help="comma-separated method ids (default: every stored one)"),
    terrains: Optional[str] = typer.Option(None, help="comma-separated instance ids (default: every stored one)"),
    group: Optional[str] = typer.Option(None, help="instance group (with no --terrains)"),
    metrics: Optional[str] = typer.Option(None, help="comma-separated metric names (default: the system's "
                                          "headline metrics; every numeric one in the CSV)"),
    out: Optional[Path] = typer.Option(None, help="also write the lines as CSV here"),
    plot: Optional[Path] = typer.Option(None, help="also draw the table's metrics here (PNG): per metric, each "
                                        "variant's median and range over seeds, one series per instance"),
) -> None:
    """Stored trials side by side: one line per (instance, config variant), statuses and metrics."""
    from terrabench.benchmark.store import ResultsStore
    from terrabench.catalog import system as get_system
    from terrabench.paths import check_out_file
    from terrabench.report import compare as cmp

    sysobj = get_system(system)
    if out is not None:
        check_out_file(out, flag="--out", suffixes=(".csv",))
    if plot is not None:
        check_out_file(plot, flag="--plot", suffixes=(".png",))
    if not store.exists():
        raise ValueError(f"--store {str(store)!r} does not exist; run `terrabench run {sysobj.id}` into it first")
    chosen = dict(methods=_split(methods, "--methods", _valid_methods(sysobj)),
                  instances=_split(terrains, "--terrains", _valid_instances(sysobj)), group=group)
    cmp.check_selection(sysobj, **chosen)
    with ResultsStore(store, read_only=True) as st:
        rows = cmp.select(st.rows(system=sysobj.id), sysobj, **chosen)
    if not rows:
        raise ValueError(f"no {sysobj.id} trials in {str(store)!r} match; `terrabench run {sysobj.id} --store "
                         f"{store}` stores them")
    names = _split(metrics, "--metrics", lambda: ", ".join(cmp.metric_names(rows)))
    lines = cmp.compare(rows, sysobj, names)  # every numeric metric when none are named (the CSV's)
    shown = names or cmp.shown_metrics(lines, sysobj)
    console.print(_compare_table(lines, shown, 0 if names else len(lines[0].metrics) - len(shown)))
    if out is not None:
        cmp.write_csv(lines, out)
        console.print(f"written: {out}", highlight=False)
    if plot is not None:
        cmp.plot(lines, shown, plot)
        console.print(f"written: {plot}", highlight=False)


@app.command()
@friendly
def report(
    system: str = typer.Argument(..., help="system id"),
    store: Path = typer.Option(DEFAULT_STORE, help="DuckDB results file"),
    out: Optional[Path] = typer.Option(None, help="output folder (default reports/SYSTEM)"),
) -> None:
    """Write a system's report (HTML + PNG + CSV) from stored trials."""
    from terrabench.benchmark.store import ResultsStore
    from terrabench.catalog import system as get_system
    from terrabench.paths import check_out_dir

    sysobj = get_system(system)
    out = check_out_dir(out or Path("reports") / system)
    with ResultsStore(store, read_only=True) as st:
        if not st.query("SELECT count(*) FROM trials WHERE system = ?", [sysobj.id])[0][0]:
            raise ValueError(f"no {sysobj.id} trials in {str(store)!r}; run `terrabench run {sysobj.id}` first")
        path = sysobj.report(st, out)
    console.print(f"report written: {path}")

@app.command()
@friendly
def perf(
    system: str = typer.Argument(..., help="system id, e.g. mrs-cwc"),
    method: Optional[str] = typer.Option(None, help="method whose model and loop are timed "
                                         "(default: the system's first default method)"),
    terrains: Optional[str] = typer.Option(None, help="instance ids (default: the system's perf sample)"),
    seconds: float = typer.Option(30.0, help="simulated seconds per measurement (systems with a time limit)"),
    repeats: int = typer.Option(2, help="loop and raw passes alternate this often; each keeps its fastest"),
    set_: list[str] = typer.Option([], "--set", help="config override KEY=VALUE (repeatable): time a variant"),
    parts: bool = typer.Option(False, "--parts", help="also time each part of the loop (controller, the task's "
                               "observe/check/row/apply/power, mj_step): us per control tick"),
) -> None:
    """The episode loop vs raw mj_step replaying the same commands: steps/s, RTF, ratio (CPU time)."""
    from terrabench.catalog import system as get_system
    from terrabench.config import parse_overrides
    from terrabench.sim import perf as pf

    sysobj = get_system(system)
    chosen = _split(terrains, "--terrains", _valid_instances(sysobj))
    overrides = parse_overrides(set_)
    rows = pf.measure(sysobj, method, chosen, seconds, repeats, overrides)
    console.print(pf.perf_table(system, rows))
    if parts:
        console.print(pf.parts_table(system, pf.parts(sysobj, method, chosen, seconds, repeats, overrides)))

@terrain_app.command("stats")
@friendly
def terrain_stats(
    group: Optional[str] = typer.Option(None, help="A, B or all"),
    terrains: Optional[str] = typer.Option(None, help="comma-separated ids"),
    csv: Optional[Path] = typer.Option(None, help="a terrain CSV in the released format instead"),
) -> None:
    """Mean per-axis slope and maximum slope of each terrain."""
    from rich.table import Table

    from terrabench.terrain import dataset

    t = Table(title="terrain slope statistics")
    for c in ("id", "mean axis slope deg", "max slope deg", "mean slope deg", "relief m"):
        t.add_column(c, justify="right")
    if csv is not None:
        chosen = [dataset.Terrain(f"row-{k}", "-", k, p) for k, p in enumerate(dataset.load_csv(csv), start=1)]
    else:
        chosen = dataset.select(_split(terrains, "--terrains", lambda: "A-01 ... A-50, B-01 ... B-50"), group)
    for ter in chosen:
        s = ter.stats()
        t.add_row(ter.id, f"{s['mean_axis_slope_deg']:.1f}", f"{s['max_slope_deg']:.1f}",
                  f"{s['mean_slope_deg']:.1f}", f"{s['relief_m']:.2f}")
    console.print(t)

@terrain_app.command("generate")
@friendly
def terrain_generate(
    n: int = typer.Option(10, help="how many terrains"),
    band: str = typer.Option("30,45", help="mean per-axis slope band in degrees, LOW,HIGH"),
    seed: int = typer.Option(0, help="random seed"),
    out: Path = typer.Option(Path("terrains.csv"), help="CSV written in the released format"),
) -> None:
    """New random terrains of the benchmark's family, filtered by a slope band (as the paper made its groups)."""
    import numpy as np

    from terrabench.paths import check_out_file
    from terrabench.terrain import dataset

    if n < 1:
        raise ValueError(f"--n must be at least 1, got {n}")
    check_out_file(out)
    try:
        lo, hi = (float(v) for v in band.split(","))
    except ValueError:
        raise ValueError(f"--band must be LOW,HIGH in degrees, e.g. 30,45; got {band!r}") from None
    params = dataset.generate(n, np.random.default_rng(seed), slope_band_deg=(lo, hi))
    dataset.write_csv(params, out)
    console.print(f"wrote {n} terrains with mean axis slope in [{lo}, {hi}) deg to {out}")

@terrain_app.command("show")
@friendly
def terrain_show(
    terrain: str = typer.Argument(..., help="terrain id, e.g. B-07"),
    out: Optional[Path] = typer.Option(None, help="PNG path (default TERRAIN.png)"),
    store: Path = typer.Option(DEFAULT_STORE, help="results file with trials to overlay"),
    methods: Optional[str] = typer.Option(None, help="methods whose leader paths to draw (default: all stored)"),
) -> None:
    """Picture of a terrain with start, target and stored leader paths."""
    from terrabench.paths import check_out_file
    from terrabench.report.terrain_plot import plot_terrain
    from terrabench.terrain import dataset

    ter = dataset.get(terrain)
    out = check_out_file(out or Path(f"{ter.id}.png"))
    paths = {}
    if store.exists():
        from terrabench.benchmark.store import ResultsStore

        wanted = _split(methods, "--methods")
        with ResultsStore(store, read_only=True) as st:
            for r in st.rows():
                if r["instance"] == ter.id and r["seed"] == 0 and (wanted is None or r["method"] in wanted):
                    ts = st.timeseries(r["key"])
                    if "x" in ts:
                        paths[f"{r['method']} ({r['status']})"] = (ts["x"], ts["y"])
    plot_terrain(ter, out, paths)
    console.print(f"wrote {out} ({len(paths)} stored path(s) drawn)")


@app.command("render")
@friendly
def render(
    system: str = typer.Argument(..., help="system id, e.g. mrs-cwc"),
    method: Optional[str] = typer.Option(None, help="method id (default: the system's first default method)"),
    terrain: str = typer.Option(..., help="instance (terrain) id, e.g. B-07"),
    seed: int = typer.Option(0, help="trial seed (0 = the released start)"),
    timeout: Optional[float] = typer.Option(None, help="simulated-time limit (s)"),
    set_: Optional[list[str]] = typer.Option(None, "--set", help="config override KEY=VALUE (repeatable)"),
    out: Path = typer.Option(Path("trial.mp4"), help="output: .mp4, .gif or .png (a frame strip)"),
    fps: float = typer.Option(30.0, help="frames per simulated second"),
    width: int = typer.Option(640, help="frame width (pixels)"),
    height: int = typer.Option(480, help="frame height (pixels)"),
    start: Optional[float] = typer.Option(None, help="first frame at this simulated time (s; default 0)"),
    span: Optional[float] = typer.Option(None, help="simulated seconds to render (default: to the end; "
                                                     "with --at, 60)"),
    at: Optional[str] = typer.Option(None, help="cut the clip at a named event of the stored trial (a quarter "
                                               "of --span before it), e.g. lift, switch; needs the trial in --store"),
    store: Path = typer.Option(DEFAULT_STORE, help="DuckDB results file --at reads the trial's series from"),
) -> None:
    """Render one trial (the benchmark's own episode) to a clip from a camera following the robot."""
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    from terrabench.catalog import system as get_system
    from terrabench.config import parse_overrides
    from terrabench.paths import check_out_file
    from terrabench.report.render import (
        VIDEO_SUFFIXES,
        GLUnavailable,
        check_frame_fits,
        check_frame_size,
        check_gl_env,
        check_renderable,
    )

    check_out_file(out, suffixes=VIDEO_SUFFIXES)
    if not (fps > 0) or fps == float("inf"):
        raise ValueError(f"--fps must be a positive number, got {fps}")
    if width <= 0 or height <= 0:
        raise ValueError(f"--width and --height must be positive, got {width}x{height}")
    check_frame_size(out, width, height)
    if seed < 0:
        raise ValueError(f"--seed must be >= 0 (0 = the released start), got {seed}")
    check_gl_env()
    sysobj = get_system(system)
    check_renderable(sysobj)
    try:
        check_frame_fits(width, height)
    except GLUnavailable as exc:
        raise ValueError(f"{exc}; set MUJOCO_GL=egl (Mesa) or MUJOCO_GL=osmesa (libosmesa6)") from None
    overrides = parse_overrides(set_ or [])
    _limit_overrides(sysobj, overrides, timeout=timeout)
    spec = sysobj.plan(methods=None if method is None else [method], instances=[terrain], seeds=seed + 1,
                       overrides=overrides)[-1]
    first, length = _clip_window(sysobj, spec, start, span, at, store)
    if length is not None:
        from terrabench.report.page import cut_at

        spec = cut_at(sysobj, spec, first + length)
    from terrabench.report.render import render_trial

    with Progress(TextColumn("rendering"), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                  console=console) as bar:
        job = bar.add_task("frames", total=None)
        result = render_trial(sysobj, spec, out, fps=fps, width=width, height=height, overlay=sysobj.render_overlay,
                              progress=lambda done, total: bar.update(job, completed=done, total=total), start=first)
    console.print(f"wrote {result['path']} ({result['frames']} frames, {result['sim_time']:.2f} simulated s, "
                  f"status {result['status']}); render speed {result['fps_rendered']:.1f} frames/s "
                  f"at {width}x{height}", highlight=False)


#: MUJOCO_GL values ``import mujoco`` accepts on Linux (mujoco/rendering/classic/gl_context.py);
#: any other value makes every import of mujoco raise, so it is refused before one happens
MUJOCO_GL_VALUES = ("egl", "osmesa", "glx", "glfw", "", "enable", "enabled", "on", "true", "1",
                    "disable", "disabled", "off", "false", "0")


def _raw_value(param, args: list[str]) -> str | None:
    """The text the user gave an option (``--seeds abc`` or ``--seeds=abc``), if it can be found."""
    for opt in getattr(param, "opts", []) or []:
        if not opt.startswith("-"):
            continue
        for i, a in enumerate(args):
            if a == opt and i + 1 < len(args):
                return args[i + 1]
            if a.startswith(opt + "="):
                return a[len(opt) + 1:]
    return None


def main() -> None:
    """The console script: typer's app, with every usage error on one line that shows the value."""
    import sys

    try:  # typer >= 0.20 vendors click as typer._click; older ones use click itself
        from typer._click import exceptions as cex
    except ImportError:  # pragma: no cover
        from click import exceptions as cex

    if any(a in SIMULATING_COMMANDS for a in sys.argv[1:3]):  # the same bits on every CPU
        portable.reexec_pinned()
    os.environ.setdefault("MPLBACKEND", "Agg")
    gl = os.environ.get("MUJOCO_GL")
    if gl is not None and gl.lower().strip() not in MUJOCO_GL_VALUES:
        err_console.print(f"[bold red]error:[/] {rich_escape(f'MUJOCO_GL={gl!r} is not a MuJoCo OpenGL backend')}; "
                          "valid: egl, osmesa (headless), glfw, glx, or unset", highlight=False, soft_wrap=True)
        sys.exit(2)
    args = sys.argv[1:]
    try:
        rc = app(args=args, standalone_mode=False)
    except cex.BadParameter as exc:
        if isinstance(exc, cex.MissingParameter):
            cmd = exc.ctx.command_path if exc.ctx is not None else "terrabench"
            err_console.print(f"[bold red]error:[/] {rich_escape(exc.format_message())} (see `{cmd} --help`)",
                              highlight=False, soft_wrap=True)
            sys.exit(exc.exit_code)
        name = exc.param.opts[0] if exc.param is not None and exc.param.opts else (exc.param_hint or "a value")
        raw = _raw_value(exc.param, args)
        shown = f"{name} {raw!r}" if raw is not None else str(name)
        err_console.print(f"[bold red]error:[/] {rich_escape(f'{shown}: {exc.message}')}", highlight=False,
                          soft_wrap=True)
        sys.exit(2)
    except cex.NoArgsIsHelpError as exc:  # bare `terrabench` / `terrabench terrain`: the help
        from typer import rich_utils

        rich_utils.rich_format_error(exc)
        sys.exit(exc.exit_code)
    except cex.ClickException as exc:  # a usage error (unknown option, missing argument): one line
        cmd = exc.ctx.command_path if getattr(exc, "ctx", None) is not None else "terrabench"
        err_console.print(f"[bold red]error:[/] {rich_escape(exc.format_message())} (see `{cmd} --help`)",
                          highlight=False, soft_wrap=True)
        sys.exit(exc.exit_code)
    except typer.Abort:
        err_console.print("Aborted!")
        sys.exit(1)
    sys.exit(rc if isinstance(rc, int) else 0)


if __name__ == "__main__":
    main()
