"""The eight methods of the paper's Table I, as (link variant, guidance, body law).

A body law is built by a factory ``(n_units, cfg: MRSConfig) -> BodyLaw`` looked up in
:data:`BODY_LAWS` by the method's ``body`` id. :func:`register_method` adds a method of your
own (for parallel runs, put the call in a module named in ``TERRABENCH_PLUGINS``, which every
worker imports).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable

from terrabench.systems.mrs_cwc import control as ctl


@dataclass(frozen=True)
class Method:
    """One benchmark method.

    Attributes:
        id: CLI id, e.g. ``"cwc-tdt"``.
        label: the paper's name, e.g. ``"MRS-CWC + TDT"``.
        variant: robot build: ``"spring"``, ``"motor"`` or ``"none"``.
        body: body law: ``"cwc"``, ``"cs"``, ``"mj"`` or ``"d"``.
        guidance: ``"tdt"`` (no map) or ``"astar"`` (waypoints from a map).
        summary: one line for ``terrabench list``.
        reads: the :class:`~terrabench.systems.mrs_cwc.config.MRSConfig` sections the method
            uses; only these are stored with (and hashed into) its trials, so changing, say,
            the D law's settings re-runs the D trials and nothing else. ``None``: all of them.
    """

    id: str
    label: str
    variant: str
    body: str
    guidance: str
    summary: str
    reads: tuple[str, ...] | None = None


_BODIES = {
    "cwc": ("MRS-CWC", "spring", "elastic links, yaw stiffness switched by sensed torques"),
    "mj": ("MRS-MJ", "motor", "motorised yaw joints, ACM-R4-like head following"),
    "cs": ("MRS-CS", "spring", "constantly soft yaw joints (K = 5), Genbu-like"),
    "d": ("MRS-D", "none", "six independent units following by position"),
}
_GUIDANCE = {"tdt": ("TDT", "target-direction tracking"), "astar": ("A*", "A* waypoints over the height map")}

#: config sections every built-in method reads, then those of each body law and guidance
COMMON_SECTIONS = ("physics", "chain", "protocol", "drive")
_BODY_SECTIONS = {"cwc": ("stiffness",), "cs": ("stiffness",), "mj": ("head_following",), "d": ("follow",)}
_GUIDANCE_SECTIONS = {"tdt": (), "astar": ("waypoints", "waypoint_source", "planner")}

METHODS: dict[str, Method] = {}
for _b, (_name, _variant, _what) in _BODIES.items():
    for _g, (_gl, _gwhat) in _GUIDANCE.items():
        _id = f"{_b}-{_g}"
        _reads = COMMON_SECTIONS + _BODY_SECTIONS[_b] + _GUIDANCE_SECTIONS[_g]
        METHODS[_id] = Method(_id, f"{_name} + {_gl}", _variant, _b, _g, f"{_what}; {_gwhat}", _reads)


def config_for(method: Method, cfg: dict[str, Any]) -> dict[str, Any]:
    """The part of a full config dict (``to_dict(MRSConfig)``) that ``method`` reads.

    The planner's settings matter only when the waypoints come from our planner.
    """
    if method.reads is None:
        return dict(cfg)
    keep = set(method.reads)
    if cfg.get("waypoint_source") != "planner":
        keep.discard("planner")
    unknown = keep - set(cfg)
    if unknown:
        raise ValueError(f"method {method.id!r} reads unknown config section(s) {sorted(unknown)}; "
                         f"valid: {sorted(cfg)}")
    return {k: v for k, v in cfg.items() if k in keep}


#: body id -> factory (n_units, MRSConfig) -> body law
BODY_LAWS: dict[str, Callable[[int, Any], Any]] = {
    "cwc": lambda n, cfg: ctl.CWCLaw(n, cfg.drive, cfg.stiffness, cfg.protocol.control_period),
    "cs": lambda n, cfg: ctl.CWCLaw(n, cfg.drive, replace(cfg.stiffness, mode="constant"), cfg.protocol.control_period),
    "mj": lambda n, cfg: ctl.HeadFollowing(n, cfg.drive, cfg.head_following),
    "d": lambda n, cfg: ctl.FollowByPosition(n, cfg.drive, cfg.follow),
}


def register_method(method: Method, body_factory: Callable[[int, Any], Any] | None = None) -> Method:
    """Add a method (and, if its ``body`` id is new, the factory of its body law).

    The body law is called every control period as ``law(obs, heading_ref, cmd)`` with an
    :class:`~terrabench.systems.mrs_cwc.sensing.Observation` and fills the
    :class:`~terrabench.systems.mrs_cwc.control.Command`; it must expose ``tau_env`` (NaN if
    it has none). The robot build is chosen by ``method.variant``.
    """
    if method.id in METHODS:
        raise ValueError(f"method id {method.id!r} already exists")
    if body_factory is not None:
        BODY_LAWS[method.body] = body_factory
    if method.body not in BODY_LAWS:
        raise ValueError(f"unknown body law {method.body!r}; valid: {', '.join(BODY_LAWS)} (or pass body_factory)")
    METHODS[method.id] = method
    return method


def get_method(mid: str) -> Method:
    if mid not in METHODS:
        raise ValueError(f"unknown method {mid!r}; valid: {', '.join(METHODS)}")
    return METHODS[mid]
