"""Headless rendering on the CPU (EGL/OSMesa): clips, snapshots, frame strips, the CLI command."""

import imageio_ffmpeg
import numpy as np
import pytest
from typer.testing import CliRunner

from terrabench.cli import app
from terrabench.report.render import frame_strip, frame_times, render_trial, snapshots
from terrabench.systems.mrs_cwc.env import overlay
from terrabench.systems.mrs_cwc.scenarios import SYSTEM

W, H = 160, 120


def spec(timeout=1.0, terrain="B-07"):
    return SYSTEM.plan(methods=["cwc-tdt"], instances=[terrain], overrides={"protocol.timeout": timeout})[0]


def decode(path):
    gen = imageio_ffmpeg.read_frames(str(path))
    meta = next(gen)
    w, h = meta["size"]
    return [np.frombuffer(b, np.uint8).reshape(h, w, 3) for b in gen]


def test_a_one_second_trial_renders_to_an_mp4_of_the_expected_frames(tmp_path):
    seen = []
    out = render_trial(SYSTEM, spec(), tmp_path / "t.mp4", fps=10, width=W, height=H, overlay=overlay,
                       progress=lambda done, total: seen.append((done, total)))
    assert out["frames"] == out["expected"] == 10 and out["status"] == "timeout"
    assert seen[-1] == (10, 10) and out["fps_rendered"] > 0
    frames = decode(tmp_path / "t.mp4")
    assert len(frames) == 10 and frames[0].shape == (H, W, 3)
    for f in frames:
        assert f.reshape(-1, 3).std(axis=0).max() > 10  # not one colour: terrain, robot, overlay


def test_the_camera_follows_the_robot():
    # over 19 s the chain drives a few metres (several camera distances' worth of frame); the
    # robot's (blue) pixels stay near the frame centre in both frames, and the view has changed
    sp = spec(timeout=20.0, terrain="A-01")
    f0, f1 = snapshots(SYSTEM, sp, [0.0, 19.0], width=W, height=H)
    centroids = []
    for f in (f0, f1):
        r, g, b = (f[..., i].astype(int) for i in range(3))
        blue = (b > r + 30) & (b > g + 10)
        ys, xs = np.nonzero(blue)
        assert len(xs) > 20  # the robot is in view
        centroids.append((xs.mean(), ys.mean()))
    for cx, cy in centroids:
        assert abs(cx - W / 2) < W / 4 and abs(cy - H / 2) < H / 4
    assert not np.array_equal(f0, f1)


def test_snapshots_count_shape_and_order():
    frames = snapshots(SYSTEM, spec(), [0.5, 0.0, 0.25], width=W, height=H)
    assert len(frames) == 3 and all(f.shape == (H, W, 3) and f.dtype == np.uint8 for f in frames)
    again = snapshots(SYSTEM, spec(), [0.0], width=W, height=H)
    np.testing.assert_array_equal(frames[1], again[0])
    with pytest.raises(ValueError, match="times"):
        snapshots(SYSTEM, spec(), [])


def test_frame_strip_and_gif(tmp_path):
    from PIL import Image

    a = np.zeros((20, 30, 3), np.uint8)
    p = frame_strip([a, a + 255], tmp_path / "s.png")
    assert Image.open(p).size == (30 + 4 + 30, 20)
    out = render_trial(SYSTEM, spec(0.5), tmp_path / "t.gif", fps=4, width=64, height=48)
    assert out["frames"] == 2 and Image.open(tmp_path / "t.gif").n_frames == 2


def test_frame_times():
    assert frame_times(0.025, 40, 10, None) == list(range(0, 40, 4))
    assert frame_times(0.025, 10, 1000, None) == list(range(10))  # at most one per period
    assert frame_times(0.025, 10, None, 3) == [0, 3, 6, 9]
    with pytest.raises(ValueError, match="fps"):
        frame_times(0.025, 10, 0, None)


def test_report_strip(tmp_path):
    from terrabench.report.page import Page
    from terrabench.systems.mrs_cwc.report import _strip
    from terrabench.systems.mrs_cwc.scenarios import SYSTEM

    page = Page(tmp_path, "strip")
    _strip(page, SYSTEM, [], seconds=0.5)
    assert "src='trial_strip.png'" in page.finish().read_text() and (tmp_path / "trial_strip.png").exists()


def test_report_strip_without_gl_is_a_note(tmp_path, monkeypatch):
    from terrabench.report import render as render_mod
    from terrabench.report.page import Page
    from terrabench.systems.mrs_cwc.report import _strip

    def no_gl(width, height):
        raise render_mod.GLUnavailable("no headless OpenGL context could be created (egl: test)")

    from terrabench.systems.mrs_cwc.scenarios import SYSTEM

    monkeypatch.setattr(render_mod, "_gl_context", no_gl)
    page = Page(tmp_path, "strip")
    _strip(page, SYSTEM, [], seconds=0.5)
    text = page.finish().read_text()
    assert "Snapshots skipped: no headless OpenGL" in text and not (tmp_path / "trial_strip.png").exists()


def test_cli_render(tmp_path):
    r = CliRunner().invoke(app, ["render", "mrs-cwc", "--method", "cwc-tdt", "--terrain", "A-01", "--timeout", "0.5",
                                 "--out", str(tmp_path / "c.mp4"), "--fps", "10", "--width", "96", "--height", "64"])
    assert r.exit_code == 0, r.output
    assert "frames/s" in r.output and len(decode(tmp_path / "c.mp4")) == 5


@pytest.mark.parametrize("args, match", [
    (["--terrain", "Z-99"], "unknown terrain"),
    (["--terrain", "A-01", "--method", "nope"], "unknown mrs-cwc method"),
    (["--terrain", "A-01", "--out", "x.avi"], "unknown suffix"),
    (["--terrain", "A-01", "--fps", "0"], "--fps"),
    (["--terrain", "A-01", "--width", "0"], "--width"),
])
def test_cli_render_bad_input_is_one_line(args, match, tmp_path):
    if "--out" not in args:
        args = args + ["--out", str(tmp_path / "x.mp4")]
    r = CliRunner().invoke(app, ["render", "mrs-cwc", *args])
    assert r.exit_code == 2 and match in r.output
    r = CliRunner().invoke(app, ["render", "nosys", "--terrain", "A-01", "--out", str(tmp_path / "x.mp4")])
    assert r.exit_code == 2 and "nosys" in r.output


def test_page_clip_cuts_the_episode_and_shows_a_video(tmp_path, monkeypatch):
    from terrabench.report import render as render_mod
    from terrabench.report.page import Page, cut_at

    long = spec(timeout=50.0)
    short = cut_at(SYSTEM, long, 0.5)
    assert short.config["protocol"]["timeout"] == 0.5 and long.config["protocol"]["timeout"] == 50.0
    assert cut_at(SYSTEM, spec(timeout=0.2), 0.5).config["protocol"]["timeout"] == 0.2  # never longer
    # a system whose limit is the instance's own (srwmr) carries it in the planned config and is cut too
    from terrabench.catalog import system

    rover = system("srwmr").plan(methods=["wrm"], instances=["t1-loose"])[0]
    assert rover.config["protocol"]["timeout"] == 150.0
    assert cut_at(system("srwmr"), rover, 60.0).config["protocol"]["timeout"] == 60.0
    assert cut_at(system("srwmr"), rover, 500.0).config["protocol"]["timeout"] == 150.0  # never longer
    page = Page(tmp_path, "clip")
    assert page.clip("c.mp4", "a clip", SYSTEM, long, 0.5, every=10, width=W, height=H)
    text = page.finish().read_text()
    assert "<video src='c.mp4'" in text and "a clip" in text
    # 0.5 s at the 25 ms control period, a frame every 10 periods: at 0 and 0.25 s (not 50 s of them)
    assert long.config["protocol"]["control_period"] == 0.025
    assert len(decode(tmp_path / "c.mp4")) == 2

    def no_gl(width, height):
        raise render_mod.GLUnavailable("no headless OpenGL context could be created (egl: test)")

    monkeypatch.setattr(render_mod, "_gl_context", no_gl)
    page = Page(tmp_path / "nogl", "clip")
    assert page.clip("c.mp4", "a clip", SYSTEM, long, 0.5, every=10, width=W, height=H) is False
    assert "Clip skipped: no headless OpenGL" in page.finish().read_text()


def test_a_clip_whose_replay_stops_before_its_window_is_not_kept_silently(tmp_path, monkeypatch):
    """A replay that ends before the clip's start (a halt that came sooner than in the stored
    trial) wrote an empty .mp4 that the page showed as a clip; now the page says why instead, and
    a replay that ends inside the window keeps its frames with a note."""
    import terrabench.report.render as render_mod
    from terrabench.report.page import Page

    def replay(frames):
        def fake(system, spec, path, **kw):
            path.write_bytes(b"")
            return {"path": path, "frames": frames, "expected": 4, "seconds": 0.1, "fps_rendered": 1.0,
                    "status": "stuck", "sim_time": 0.3}
        return fake

    monkeypatch.setattr(render_mod, "render_trial", replay(0))
    page = Page(tmp_path, "clip")
    assert page.clip("c.mp4", "a clip", SYSTEM, spec(), 0.4, every=1, start=0.6) is False
    assert not (tmp_path / "c.mp4").exists()
    text = page.finish().read_text()
    assert "Clip c.mp4 skipped" in text and "ended (stuck) at 0.30 s, before its start at 0.60 s" in text
    assert "<video" not in text
    monkeypatch.setattr(render_mod, "render_trial", replay(2))
    page = Page(tmp_path / "short", "clip")
    assert page.clip("c.mp4", "a clip", SYSTEM, spec(), 0.4, every=1, start=0.6)
    assert "2 of 4 frames" in page.finish().read_text()


def test_a_clip_from_a_start_time_keeps_only_its_window(tmp_path):
    # 1 s of episode at 10 frames/s from 0.6 s: the frames at 0.6, 0.7 ... 0.9 s; a start past the
    # end is refused before any frame
    out = render_trial(SYSTEM, spec(), tmp_path / "w.mp4", fps=10, width=W, height=H, start=0.6)
    assert out["frames"] == out["expected"] == 4 and len(decode(tmp_path / "w.mp4")) == 4
    with pytest.raises(ValueError, match="past the episode's end"):
        render_trial(SYSTEM, spec(), tmp_path / "x.mp4", fps=10, width=W, height=H, start=5.0)


def test_cli_render_at_an_event_reads_the_stored_trial(tmp_path):
    from terrabench.benchmark.runner import run_trials
    from terrabench.benchmark.store import ResultsStore

    store = tmp_path / "s.duckdb"
    base = ["render", "mrs-cwc", "--method", "cwc-tdt", "--terrain", "A-01", "--timeout", "1.0",
            "--fps", "10", "--width", "96", "--height", "64", "--store", str(store)]
    r = CliRunner().invoke(app, [*base, "--at", "end", "--out", str(tmp_path / "a.mp4")])
    assert r.exit_code == 2 and "does not exist; run it first" in " ".join(r.output.split())
    with ResultsStore(store) as st:
        run_trials(SYSTEM.plan(methods=["cwc-tdt"], instances=["A-01"], overrides={"protocol.timeout": 1.0}), st,
                   workers=1)
    r = CliRunner().invoke(app, [*base, "--at", "nope", "--out", str(tmp_path / "a.mp4")])
    assert r.exit_code == 2 and "valid: end, start" in " ".join(r.output.split())
    # 'end' (1.0 s) with a 0.4 s span: the clip starts a quarter of the span before it, 0.9 s
    r = CliRunner().invoke(app, [*base, "--at", "end", "--span", "0.4", "--out", str(tmp_path / "a.mp4")])
    assert r.exit_code == 0, r.output
    assert len(decode(tmp_path / "a.mp4")) == 1


def test_srwmr_clip_events_are_read_off_the_series():
    from terrabench.catalog import system
    from terrabench.systems.srwmr.control import MODE_CODE

    t = np.arange(0.0, 10.0, 0.5)
    mode = np.where(t < 4.0, MODE_CODE["SWLM"], MODE_CODE["HALT"]).astype(float)
    w = {f"W_c{i}": np.full(t.size, 300.0) for i in range(1, 7)}
    w["W_c1"] = np.where(t < 0.5, 0.0, np.where(t < 2.0, 300.0, 2.0))  # in the air at first: not a lift
    ev = system("srwmr").clip_events({"metrics": {}}, {"t": t, "mode": mode, **w})
    assert ev == {"start": 0.0, "end": 9.5, "switch": 4.0, "halt": 4.0, "lift": 2.0}


def test_a_sped_up_clip_grabs_fewer_frames_per_simulated_second(tmp_path):
    # 1 s of episode at 10 frames/s played 2x real time: a frame every 0.2 s (0, 0.2 ... 0.8)
    out = render_trial(SYSTEM, spec(), tmp_path / "s.mp4", fps=10, width=W, height=H, speedup=2.0)
    assert out["frames"] == out["expected"] == 5 and len(decode(tmp_path / "s.mp4")) == 5
    with pytest.raises(ValueError, match="speedup must be"):
        render_trial(SYSTEM, spec(), tmp_path / "t.mp4", fps=10, width=W, height=H, speedup=0.0)
