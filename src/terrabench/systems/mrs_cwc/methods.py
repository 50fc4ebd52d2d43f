"""The eight methods of the paper's Table I, as (link variant, guidance, body law)."""

from __future__ import annotations

from dataclasses import dataclass


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
    """

    id: str
    label: str
    variant: str
    body: str
    guidance: str
    summary: str


_BODIES = {
    "cwc": ("MRS-CWC", "spring", "elastic links, yaw stiffness switched by sensed torques"),
    "mj": ("MRS-MJ", "motor", "motorised yaw joints, ACM-R4-like head following"),
    "cs": ("MRS-CS", "spring", "constantly soft yaw joints (K = 5), Genbu-like"),
    "d": ("MRS-D", "none", "six independent units following by position"),
}
_GUIDANCE = {"tdt": ("TDT", "target-direction tracking"), "astar": ("A*", "A* waypoints over the height map")}

METHODS: dict[str, Method] = {}
for _b, (_name, _variant, _what) in _BODIES.items():
    for _g, (_gl, _gwhat) in _GUIDANCE.items():
        _id = f"{_b}-{_g}"
        METHODS[_id] = Method(_id, f"{_name} + {_gl}", _variant, _b, _g, f"{_what}; {_gwhat}")


def get_method(mid: str) -> Method:
    if mid not in METHODS:
        raise ValueError(f"unknown method {mid!r}; valid: {', '.join(METHODS)}")
    return METHODS[mid]
