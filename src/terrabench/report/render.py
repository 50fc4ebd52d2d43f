"""Headless MuJoCo rendering of benchmark trials on the CPU: clips, snapshots, frame strips.

A :class:`SceneRenderer` draws one compiled scene offscreen (EGL, or OSMesa if EGL cannot
start; ``MUJOCO_GL`` chooses which one is tried first) from a free camera whose look-at point
follows the robot: by default the centre of mass of everything that moves (``subtree_com`` of
the world body; the terrain is static and massless), or a named body's subtree. A small text
overlay (time, status and a system-chosen line, drawn with PIL) sits in the top-left corner.

:func:`render_trial` runs the benchmark episode of a trial spec (the same task, controller and
loop as ``terrabench run``) and grabs a frame every ``1/fps`` simulated seconds through
``Episode(..., on_step=...)``; rendering never changes the state, so the trial's numbers are
those of the benchmark. :func:`snapshots` gives frames at chosen simulated times (reports);
:func:`frame_strip` puts frames side by side in one PNG.

We create the GL context ourselves rather than through :class:`mujoco.Renderer`, because
``mujoco`` picks its default context class when it is first imported (by the simulator, long
before this module), and its default on Linux is GLFW, which needs a display.
"""

from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import math  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import TYPE_CHECKING, Any, Callable, Sequence  # noqa: E402

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

if TYPE_CHECKING:
    from terrabench.benchmark.trial import TrialSpec
    from terrabench.sim.episode import Episode as SimEpisode
    from terrabench.systems.base import System, Task

#: ``overlay(task, obs) -> str``: a system's line of the text overlay (e.g. the stiffness K)
Overlay = Callable[["Task", Any], str]

VIDEO_SUFFIXES = (".mp4", ".gif", ".png")


class GLUnavailable(RuntimeError):
    """No headless OpenGL context could be made (reports fall back to a note, the CLI to one line)."""


#: the MUJOCO_GL values this renderer understands (unset: EGL, then OSMesa)
GL_BACKENDS = ("egl", "osmesa")


def check_gl_env() -> None:
    """ValueError (one line) if ``MUJOCO_GL`` names a backend this headless renderer cannot use."""
    value = os.environ.get("MUJOCO_GL", "egl")
    if value.lower().strip() not in GL_BACKENDS:
        raise ValueError(f"MUJOCO_GL={value!r} is not a headless OpenGL backend; valid: {', '.join(GL_BACKENDS)} "
                         "(unset: egl, then osmesa)")


def check_renderable(system: System) -> None:
    """ValueError (one line) if ``system`` has no MuJoCo episode to render (no ``make_task``)."""
    from terrabench.systems.base import System

    if type(system).make_task is System.make_task:
        raise ValueError(f"system {system.id!r} does not run through the MuJoCo episode loop, so it has no "
                         "clip to render; render the systems that do (e.g. mrs-cwc, octopus)")


def _gl_context(width: int, height: int):
    """A current offscreen GL context: EGL, then OSMesa (or the reverse if MUJOCO_GL=osmesa)."""
    first = os.environ.get("MUJOCO_GL", "egl").lower()
    order = ("osmesa", "egl") if first == "osmesa" else ("egl", "osmesa")
    errors = []
    for backend in order:
        try:
            if backend == "egl":
                from mujoco.egl import GLContext
            else:
                from mujoco.osmesa import GLContext
            ctx = GLContext(width, height)
            ctx.make_current()
            return ctx
        except Exception as exc:  # noqa: BLE001 - try the next backend, report all at the end
            errors.append(f"{backend}: {type(exc).__name__}: {exc}")
    raise GLUnavailable("no headless OpenGL context could be created (" + "; ".join(errors) + ")")


class SceneRenderer:
    """Offscreen RGB frames of one compiled model from a camera that follows the robot.

    Args:
        model: the compiled ``MjModel`` (its offscreen buffer is enlarged if needed).
        width, height: frame size in pixels.
        track: body name whose subtree centre of mass the camera looks at; None = the whole
            model's centre of mass (every moving body).
        distance: camera distance (m); None = 3.5 x the robot's extent at the first frame
            (at least 1.5 m).
        azimuth, elevation: camera angles (deg).
    """

    def __init__(self, model: mujoco.MjModel, width: int = 640, height: int = 480, *, track: str | None = None,
                 distance: float | None = None, azimuth: float = 135.0, elevation: float = -30.0):
        for name, v in (("width", width), ("height", height)):
            if isinstance(v, bool) or not isinstance(v, int) or v <= 0:
                raise ValueError(f"{name} must be a positive whole number of pixels, got {v!r}")
        self.model, self.width, self.height = model, width, height
        self.track_body = 0 if track is None else model.body(track).id
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, height)
        # scenes without lights of their own: a brighter headlight (visual only, no physics)
        model.vis.headlight.ambient[:] = np.maximum(model.vis.headlight.ambient, 0.35)
        model.vis.headlight.diffuse[:] = np.maximum(model.vis.headlight.diffuse, 0.6)
        self._ctx = _gl_context(width, height)
        try:
            self.context = mujoco.MjrContext(model, mujoco.mjtFontScale.mjFONTSCALE_150)
        except mujoco.FatalError as exc:
            self._ctx.free()
            raise ValueError(f"a {width}x{height} frame does not fit this OpenGL's offscreen framebuffer ({exc}); "
                             "give a smaller --width/--height, e.g. 1920x1080") from None
        self.scene = mujoco.MjvScene(model, maxgeom=10000)
        self.option = mujoco.MjvOption()
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.azimuth, self.camera.elevation = azimuth, elevation
        self.elevation = elevation
        self.distance = distance
        mujoco.mjr_setBuffer(mujoco.mjtFramebuffer.mjFB_OFFSCREEN, self.context)
        self.rect = mujoco.MjrRect(0, 0, width, height)
        self._moving = np.flatnonzero(model.body_mass > 0)

    def lookat(self, data: mujoco.MjData) -> np.ndarray:
        """The point the camera looks at (m, world frame)."""
        return np.array(data.subtree_com[self.track_body])

    def render(self, data: mujoco.MjData, text: str | None = None) -> np.ndarray:
        """One (height, width, 3) uint8 frame of ``data``'s state, with ``text`` overlaid."""
        self._ctx.make_current()
        centre = self.lookat(data)
        if self.distance is None:
            spread = np.linalg.norm(data.xpos[self._moving] - centre, axis=1).max() if len(self._moving) else 0.5
            self.distance = max(1.5, 3.5 * float(spread))
        self.camera.lookat[:] = centre
        self.camera.distance = self.distance
        self.camera.elevation = self._clear_elevation(data, centre)
        mujoco.mjv_updateScene(self.model, data, self.option, None, self.camera,
                               mujoco.mjtCatBit.mjCAT_ALL, self.scene)
        mujoco.mjr_render(self.rect, self.scene, self.context)
        rgb = np.empty((self.height, self.width, 3), np.uint8)
        mujoco.mjr_readPixels(rgb, None, self.rect, self.context)
        frame = np.flipud(rgb)
        return draw_text(frame, text) if text else np.ascontiguousarray(frame)

    def _clear_elevation(self, data: mujoco.MjData, centre: np.ndarray, clearance: float = 0.3) -> float:
        """The set elevation, steepened in 10 deg steps (to -85) while the camera would sit inside
        the ground (a hill between the camera and a robot in a valley renders black)."""
        az = np.radians(self.camera.azimuth)
        geomid = np.zeros(1, np.int32)
        el = self.elevation
        while el > -85.0:
            e = np.radians(el)
            cam = centre - self.distance * np.array([np.cos(e) * np.cos(az), np.cos(e) * np.sin(az), np.sin(e)])
            top = np.array([cam[0], cam[1], centre[2] + 100.0])
            hit = mujoco.mj_ray(self.model, data, top, np.array([0.0, 0.0, -1.0]), None, 1, -1, geomid)
            if hit < 0 or top[2] - hit + clearance <= cam[2]:
                break
            el -= 10.0
        return el

    def close(self) -> None:
        """Free the GL resources (the renderer cannot be used afterwards)."""
        if self._ctx is not None:
            self.context.free()
            self._ctx.free()
            self._ctx = None

    def __enter__(self) -> "SceneRenderer":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def draw_text(frame: np.ndarray, text: str) -> np.ndarray:
    """``frame`` with ``text`` (one or more lines) in white on a dark box, top left."""
    from PIL import Image, ImageDraw, ImageFont

    img = Image.fromarray(np.ascontiguousarray(frame))
    draw = ImageDraw.Draw(img)
    size = max(8, frame.shape[0] // 24)
    try:
        font = ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1
        font = ImageFont.load_default()
    box = draw.multiline_textbbox((4, 3), text, font=font)
    draw.rectangle((box[0] - 3, box[1] - 2, box[2] + 3, box[3] + 2), fill=(0, 0, 0))
    draw.multiline_text((4, 3), text, fill=(255, 255, 255), font=font)
    return np.asarray(img)


def overlay_text(t: float, status: str, extra: str = "") -> str:
    """The overlay: simulated time, status and the system's line."""
    return f"t = {t:6.2f} s  {status}" + (f"\n{extra}" if extra else "")


def _check_fps(fps: object) -> None:
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not math.isfinite(fps) or fps <= 0:
        raise ValueError(f"fps must be a positive number of frames per simulated second, got {fps!r}")


def _check_suffix(path: Path) -> None:
    if path.suffix.lower() not in VIDEO_SUFFIXES:
        raise ValueError(f"output {str(path)!r}: unknown suffix {path.suffix!r}; valid: {', '.join(VIDEO_SUFFIXES)} "
                         "(.png writes a frame strip)")


def check_frame_size(path: str | Path, width: int, height: int) -> None:
    """ValueError (one line) for a frame size the output cannot take: H.264 in yuv420p (.mp4)
    needs even sizes (ffmpeg would fail after the episode has run)."""
    if Path(path).suffix.lower() == ".mp4" and (width % 2 or height % 2):
        raise ValueError(f"--width/--height {width}x{height}: an .mp4 (H.264, yuv420p) needs even sizes, e.g. "
                         f"{width + width % 2}x{height + height % 2}; .gif and .png take any size")


def check_frame_fits(width: int, height: int) -> None:
    """ValueError (one line) if this machine's offscreen framebuffer cannot hold a ``width`` x
    ``height`` frame: tried on an empty model (tens of ms) so that it fails before an episode.
    No GL at all (:class:`GLUnavailable`) is left to the caller, which reports it its own way."""
    model = mujoco.MjModel.from_xml_string("<mujoco/>")
    SceneRenderer(model, width, height).close()


def frame_times(control_period: float, n_periods: int, fps: float | None, every: int | None) -> list[int]:
    """Control-period indices (0 .. n_periods - 1) at which a frame is grabbed.

    ``every`` (periods) wins over ``fps``; with ``fps`` a frame is grabbed at the first period
    at or after each multiple of ``1 / fps`` simulated seconds (at most one per period).
    """
    if every is not None:
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            raise ValueError(f"every must be a whole number of control periods >= 1, got {every!r}")
        return list(range(0, n_periods, every))
    _check_fps(fps)
    assert fps is not None  # _check_fps refused it
    out, next_t, j = [], 0.0, 0
    for i in range(n_periods):
        if i * control_period + 1e-9 >= next_t:
            out.append(i)
            while j / fps <= i * control_period + 1e-9:
                j += 1
            next_t = j / fps
    return out


def camera_of(task: object) -> dict[str, float]:
    """A task's camera angles for :class:`SceneRenderer` (``task.camera``: azimuth and/or
    elevation in deg, e.g. a side view of a step), or ``{}`` for the default view."""
    cam = getattr(task, "camera", None) or {}
    return {k: float(cam[k]) for k in ("azimuth", "elevation") if k in cam}


def _episode(system: System, spec: TrialSpec) -> tuple[Task, Callable[[Any], Any], type[SimEpisode]]:
    from terrabench.sim.episode import Episode

    cfg = system.load_config(spec.config)
    task = system.make_task(spec, cfg)
    controller = system.make_controller(spec, cfg, task)
    return task, controller, Episode


def render_trial(system: System, spec: TrialSpec, out_path: str | Path, fps: float = 30, width: int = 640,
                 height: int = 480, every: int | None = None, progress: Callable[[int, int], None] | None = None,
                 overlay: Overlay | None = None, track: str | None = None, start: float = 0.0,
                 speedup: float = 1.0) -> dict[str, Any]:
    """Run the benchmark episode of ``spec`` and write a clip of it.

    Args:
        system: the :class:`~terrabench.systems.base.System`.
        spec: a :class:`~terrabench.benchmark.trial.TrialSpec` (e.g. from ``system.plan``).
        out_path: ``.mp4`` (H.264 via imageio-ffmpeg), ``.gif`` or ``.png`` (a frame strip).
        fps: frames per simulated second (the clip plays in real time).
        every: grab a frame every this many control periods instead (the clip keeps ``fps``).
        progress: ``progress(done, expected)`` after every frame.
        overlay: ``overlay(task, obs) -> str``, the system's overlay line (None: time and status).
        track: body the camera follows (None: the robot's centre of mass).
        start: the clip's first frame (simulated s): the episode runs from 0, frames are kept from
            here (cut the end with the system's timeout, :func:`terrabench.report.page.cut_at`).
        speedup: the clip plays this many times faster than real time (frames are grabbed at
            ``fps / speedup`` per simulated second and played at ``fps``; ignored with ``every``).

    Returns:
        ``dict(path, frames, expected, seconds, fps_rendered, status, sim_time)``: ``seconds``
        is the wall time of the whole run, ``fps_rendered`` the frames rendered per wall second.
    """
    out_path = Path(out_path)
    _check_suffix(out_path)
    _check_fps(fps)
    if isinstance(speedup, bool) or not isinstance(speedup, (int, float)) or not (
            math.isfinite(speedup) and speedup > 0):
        raise ValueError(f"speedup must be a finite number > 0, got {speedup!r}")
    check_frame_size(out_path, width, height)
    t0 = time.perf_counter()
    task, controller, Episode = _episode(system, spec)
    frames_at: set[int] = set()
    state: dict[str, Any] = {"i": 0, "frames": []}
    ep: SimEpisode  # bound below, before the first step calls grab

    def grab(task_, obs, cmd) -> None:
        i = state["i"]
        state["i"] = i + 1
        if i in frames_at:
            text = overlay_text(i * ep.period, "running", overlay(task_, obs) if overlay else "")
            sink(renderer.render(ep.data, text))

    ep = Episode(task, on_step=grab)
    if not (start >= 0.0) or not math.isfinite(start):
        raise ValueError(f"start must be a finite number of simulated seconds >= 0, got {start!r}")
    grab_fps = fps / speedup
    expected_idx = [i for i in frame_times(ep.period, ep.n_max - 1, grab_fps, every)
                    if i * ep.period >= start - 1e-9]
    if not expected_idx:
        raise ValueError(f"start {start:g} s is past the episode's end ({(ep.n_max - 1) * ep.period:g} s)")
    frames_at.update(expected_idx)
    expected = len(expected_idx)
    renderer = SceneRenderer(ep.model, width, height, track=track, **camera_of(task))
    out_path.parent.mkdir(parents=True, exist_ok=True)
    writer = None
    kept: list[np.ndarray] = []
    if out_path.suffix.lower() == ".mp4":
        import imageio_ffmpeg

        writer = imageio_ffmpeg.write_frames(str(out_path), (width, height), fps=fps, codec="libx264",
                                             pix_fmt_out="yuv420p", macro_block_size=1, quality=7,
                                             ffmpeg_log_level="error")
        writer.send(None)
    count = [0]

    def sink(frame: np.ndarray) -> None:
        if writer is not None:
            writer.send(np.ascontiguousarray(frame).tobytes())
        else:
            kept.append(frame)
        count[0] += 1
        if progress is not None:
            progress(count[0], expected)

    t_render = time.perf_counter()
    try:
        obs, stop = ep.begin()
        while stop is None:
            obs, stop = ep.step(controller(obs))
    finally:
        renderer.close()
        if writer is not None:
            writer.close()
    wall = time.perf_counter() - t_render
    if writer is None:
        if out_path.suffix.lower() == ".gif":
            _write_gif(kept, out_path, fps)
        else:
            frame_strip(kept, out_path)
    log = ep.log()
    return {"path": out_path, "frames": count[0], "expected": expected, "seconds": time.perf_counter() - t0,
            "fps_rendered": count[0] / wall if wall > 0 else float("nan"), "status": log.status,
            "sim_time": log.sim_time}


def _write_gif(frames: list[np.ndarray], path: Path, fps: float) -> None:
    from PIL import Image

    if not frames:
        raise ValueError("no frames to write")
    imgs = [Image.fromarray(f) for f in frames]
    imgs[0].save(path, save_all=True, append_images=imgs[1:], duration=int(round(1000 / fps)), loop=0)


def snapshots(system: System, spec: TrialSpec, times: Sequence[float], width: int = 480, height: int = 360,
              overlay: Overlay | None = None, track: str | None = None) -> list[np.ndarray]:
    """RGB uint8 frames (height, width, 3) of ``spec``'s benchmark episode at simulated ``times`` (s).

    Each frame is taken at the first control instant at or after its time; the episode runs
    only until the last one. Times after the episode's stop show its final state.
    """
    ts = sorted(float(t) for t in times)
    if not ts or any(not math.isfinite(t) or t < 0 for t in ts):
        raise ValueError(f"times must be a non-empty list of finite simulated seconds >= 0, got {list(times)!r}")
    task, controller, Episode = _episode(system, spec)
    ep = Episode(task)
    renderer = SceneRenderer(ep.model, width, height, track=track, **camera_of(task))
    frames: list[np.ndarray] = []
    try:
        obs, stop = ep.begin()
        k = 0
        while len(frames) < len(ts):
            t = k * ep.period
            while len(frames) < len(ts) and (t + 1e-9 >= ts[len(frames)] or stop is not None):
                status = stop[0] if stop else "running"
                frames.append(renderer.render(ep.data, overlay_text(t, status, overlay(task, obs) if overlay else "")))
            if stop is not None or len(frames) == len(ts):
                break
            obs, stop = ep.step(controller(obs))
            k += 1
    finally:
        renderer.close()
    order = np.argsort(np.asarray([float(t) for t in times]), kind="stable")
    out = list(frames)  # placeholders: ``order`` is a permutation, every slot is set below
    for rank, idx in enumerate(order):
        out[idx] = frames[rank]
    return out


def frame_strip(frames: Sequence[np.ndarray], path: str | Path, gap: int = 4) -> Path:
    """Write ``frames`` side by side (``gap`` white pixels apart) as one PNG; returns the path."""
    from PIL import Image

    if not frames:
        raise ValueError("frame_strip needs at least one frame")
    h = max(f.shape[0] for f in frames)
    w = sum(f.shape[1] for f in frames) + gap * (len(frames) - 1)
    strip = np.full((h, w, 3), 255, np.uint8)
    x = 0
    for f in frames:
        strip[: f.shape[0], x : x + f.shape[1]] = f[..., :3]
        x += f.shape[1] + gap
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(strip).save(path)
    return path


def snapshot_strip(system: System, spec: TrialSpec, times: Sequence[float], path: str | Path, *, width: int = 320,
                   height: int = 240, overlay: Overlay | None = None, track: str | None = None) -> Path:
    """Frames of ``spec``'s benchmark episode at ``times`` (:func:`snapshots`) side by side in one
    PNG at ``path`` (:func:`frame_strip`); returns the path.

    Raises:
        GLUnavailable: no headless GL on this machine (:meth:`terrabench.report.page.Page.snapshots`
            turns it into a note on the page).
    """
    return frame_strip(snapshots(system, spec, times, width=width, height=height, overlay=overlay, track=track), path)
