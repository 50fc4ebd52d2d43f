"""OCTOPUS report: built from a store on the shared page layer, with the mode timelines."""

from pathlib import Path

import numpy as np
import pytest

from terrabench.benchmark.store import ResultsStore
from terrabench.systems.octopus.scenarios import SYSTEM


def test_report_from_a_store(tmp_path: Path):
    pytest.importorskip("matplotlib")
    store = ResultsStore(tmp_path / "r.duckdb")
    specs = SYSTEM.plan(methods=["clm", "ccm"], instances=["step-400"], seeds=1, overrides={"protocol.timeout": 8.0})
    specs += SYSTEM.plan(methods=["clm"], instances=["step-400"], seeds=1,
                         overrides={"protocol.timeout": 8.0, "clm.press": 0.01})
    for spec in specs:
        store.write(spec, SYSTEM.run_trial(spec))
    rows = store.rows(system="octopus")
    assert all(r["info"]["events"] for r in rows)      # transitions are stored with each trial
    ev = rows[0]["info"]["events"][0]
    assert len(ev) == 4 and isinstance(ev[0], float)   # [t, src, dst, reason]
    index = SYSTEM.report(store, tmp_path / "out")
    text = index.read_text()
    assert "modes_step-400_ccm.png" in text
    assert text.count("<img src='modes_step-400_clm_") == 2  # one mode timeline per CLM variant
    assert "clm.press=0.01" in text                   # the --set variant is its own labelled line
    assert (tmp_path / "out" / "tasks.csv").read_text().count("\n") == 4


def test_climb_share_tells_a_dynamic_drop_from_a_held_run():
    """The two readings of a zero crawler share: one dynamic row (the nose dropping onto its
    crawlers) leaves the quasi-static minimum and a 0.1 s free run; a quasi-static run of
    crawler-free rows (the robot on its arm tips) gives both a zero and the run's length."""
    import numpy as np

    from terrabench.systems.octopus import clm
    from terrabench.systems.octopus.report import climb_share

    t = np.round(np.arange(0.0, 10.0, 0.1), 10)
    mode = np.where((t >= 2.0) & (t < 8.0), clm.CLIMB, clm.WALK).astype(float)
    share = np.full(len(t), 0.7)
    quasi = np.ones(len(t))
    drop = np.flatnonzero(np.isclose(t, 3.0))
    share[drop], quasi[drop] = 0.0, 0.0  # one dynamic row
    c = climb_share({"t": t, "mode": mode, "track_share": share, "quasi": quasi}, "clm")
    assert c["share_min_quasi"] == 0.7 and c["crawler_free_s"] == pytest.approx(0.1)
    held = (t >= 5.0) & (t < 6.5)
    share[held] = 0.01  # 1.5 s held on the arms, quasi-static
    c = climb_share({"t": t, "mode": mode, "track_share": share, "quasi": quasi}, "clm")
    assert c["share_min_quasi"] == pytest.approx(0.01) and c["crawler_free_s"] == pytest.approx(1.5)
    share[(t >= 9.0)] = 0.0  # walking rows do not count
    assert climb_share({"t": t, "mode": mode, "track_share": share, "quasi": quasi}, "clm")["crawler_free_s"] \
        == pytest.approx(1.5)
    # no climb rows: NaN
    assert np.isnan(climb_share({"t": t, "mode": np.zeros(len(t)), "track_share": share, "quasi": quasi},
                                "clm")["share_min_quasi"])


def test_clip_events_read_the_stored_controller_events():
    """--at's events for OCTOPUS: CLM's climb / over / release / walk_on and CCM's press / abort
    from the stored transitions (the first of each), the tip-back crossing from the info."""
    events = [[0.0, "LF.support", "LF.transfer", "gait turn"], [20.7, "walk", "climb", "up-step"],
              [29.5, "climb", "climb", "front pulley 0.030 m over the top: front arms unload"],
              [36.8, "climb", "release", "H > H_EST"], [38.9, "release", "walk", "released"],
              [50.0, "walk", "climb", "a second climb"]]
    ev = SYSTEM.clip_events({"info": {"events": events}, "metrics": {"sim_time": 60.0}}, {})
    assert ev == {"start": 0.0, "end": 60.0, "climb": 20.7, "over": 29.5, "release": 36.8, "walk_on": 38.9}
    # the rear lift's end from the stored stages: the first drive-on row
    series = {"t": np.array([20.6, 20.7, 29.5, 31.2, 31.3, 36.8]), "climb_stage": np.array([0, 1, 2, 3, 3, 4.0])}
    ev = SYSTEM.clip_events({"info": {"events": events}, "metrics": {"sim_time": 60.0}}, series)
    assert ev["rear_up"] == 31.2 and ev["end"] == 36.8
    ccm = [[6.2, "approach", "press", "riser"], [29.2, "push", "abort", "pitch"]]
    ev = SYSTEM.clip_events({"info": {"events": ccm, "tip_back": {"t": 29.0}}, "metrics": {"sim_time": 29.2}}, {})
    assert ev == {"start": 0.0, "end": 29.2, "press": 6.2, "abort": 29.2, "tipped_back": 29.0}


def test_release_points_read_the_position_and_the_tip_back_after_it():
    """Each stored climb -> release: where the chassis was along the axis and how far the pitch
    rose within RELEASE_WATCH s after it (a robot tipping back over the edge rises; one released
    over the top does not); other transitions and rows before the release are not read."""
    import numpy as np

    from terrabench.systems.octopus.report import RELEASE_WATCH, release_points

    t = np.round(np.arange(0.0, 20.0, 0.1), 10)
    s = np.minimum(0.05 * t - 0.5, 0.1)
    pitch = np.zeros(len(t))
    pitch[(t > 4.0) & (t < 5.0)] = 0.9  # before the release: not read
    pitch[(t >= 10.0) & (t <= 10.0 + RELEASE_WATCH)] = np.linspace(0.0, 0.4, int(RELEASE_WATCH / 0.1) + 1)
    pitch[t > 10.0 + RELEASE_WATCH + 0.5] = 0.8  # after the watch: not read
    events = [[9.0, "walk", "climb", "up-step"], [10.0, "climb", "release", "S > L"],
              [11.0, "release", "walk", "released"], [15.0, "climb", "release", "S > L"]]
    pts = release_points(events, {"t": t, "s": s, "pitch": pitch})
    assert len(pts) == 2
    (t1, s1, d1), (t2, s2, d2) = pts
    assert t1 == 10.0 and s1 == pytest.approx(0.0) and d1 == pytest.approx(0.4)
    assert t2 == 15.0 and s2 == pytest.approx(0.1) and d2 == pytest.approx(0.0)
    assert release_points(events, {}) == []


def test_the_stage_figure_draws_the_default_climbs_stage_shares():
    """report._stages: one bar per stage and task for the default CLM variant's climbing tasks, at
    the median of the trials' shares, their range as a line; tasks without a climb and other
    variants are left out, and without any climb there is no figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from terrabench.systems.octopus import report

    class Page:
        def __init__(self):
            self.figs = []

        def h2(self, text):
            pass

        def p(self, text):
            pass

        def figure(self, fig, name, caption, dpi=80):
            self.figs.append((name, fig))

    def row(variant, **m):
        return {"method": "clm", "variant": variant, "metrics": m}

    shares = {"crawler_load_share_lift": 0.6, "crawler_load_share_rear_lift": 0.3, "crawler_load_share_drive_on": 0.4}
    g = {("step-400", "d"): [row("d", **shares), row("d", **{k: v + 0.1 for k, v in shares.items()})],
         ("block-500", "d"): [row("d", crawler_load_share_lift=float("nan"))],
         ("step-400", "other"): [row("other", **shares)]}
    page = Page()
    report._stages(page, plt, g, {"step-400": 0, "block-500": 1}, {"d"})
    (name, fig), = page.figs
    assert name == "stages.png"
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["step-400"]
    heights = sorted(round(b.get_height(), 6) for b in ax.patches)
    assert heights == [0.35, 0.45, 0.65]   # the medians of the two trials per stage
    plt.close(fig)
    page = Page()
    report._stages(page, plt, {("block-500", "d"): g[("block-500", "d")]}, {"block-500": 0}, {"d"})
    assert page.figs == []
