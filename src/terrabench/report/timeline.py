"""Mode timelines from a controller's stored events (``info["events"]``, see
:class:`terrabench.systems.base.Transition`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Sequence

from terrabench.systems.base import Transition

if TYPE_CHECKING:
    from matplotlib.axes import Axes

#: one stored event: a :class:`Transition` or its ``[t, src, dst, reason]`` list (``info["events"]``)
Event = Transition | Sequence[Any]


def segments(events: Sequence[Event], t_end: float, start: str | None = None) -> list[tuple[str, float, float]]:
    """``[(state, t0, t1), ...]`` covering ``[0, t_end]`` from stored events (lists or Transitions).

    The first state is ``start`` if given, else the first event's ``src``; an event's ``dst`` holds
    until the next event. Events must be in time order (a controller appends them so).
    """
    evs = [e if isinstance(e, Transition) else Transition.from_list(e) for e in events]
    if any(b.t < a.t for a, b in zip(evs, evs[1:])):
        raise ValueError("events must be in time order")
    state = start if start is not None else (evs[0].src if evs else "")
    out, t0 = [], 0.0
    for e in evs:
        if e.t > t0:
            out.append((state, t0, min(e.t, t_end)))
        state, t0 = e.dst, e.t
    if t_end > t0 or not out:
        out.append((state, t0, max(t_end, t0)))
    return out


def draw_timelines(ax: Axes, timelines: Sequence[tuple[str, Sequence[Event], float]], *, start: str | None = None,
                   palette: dict[str, Any] | None = None) -> dict[str, Any]:
    """One bar per trial on ``ax``: ``(label, events, t_end)``; states coloured consistently.

    Returns the state -> colour map used (for a legend)."""
    import matplotlib.pyplot as plt

    colours = dict(palette or {})
    cycle = plt.rcParams["axes.prop_cycle"].by_key().get("color", ["C0", "C1", "C2", "C3"])
    for i, (_, events, t_end) in enumerate(timelines):
        for state, t0, t1 in segments(events, t_end, start):
            c = colours.setdefault(state, cycle[len(colours) % len(cycle)])
            ax.barh(i, t1 - t0, left=t0, height=0.6, color=c, edgecolor="none")
    ax.set_yticks(range(len(timelines)))
    ax.set_yticklabels([lb for lb, _, _ in timelines])
    ax.set_xlabel("t (s)")
    from matplotlib.patches import Patch

    ax.legend(handles=[Patch(color=c, label=s) for s, c in colours.items()], loc="upper left",
              bbox_to_anchor=(1.0, 1.0), fontsize="small", frameon=False)
    return colours
