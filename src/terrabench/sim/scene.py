"""Scene assembly: physics options + the task's arena and robot, compiled with ``MjSpec``.

A task adds what it needs to an empty :class:`mujoco.MjSpec` in ``task.build(spec)`` (a
terrain height field with :func:`terrabench.terrain.mjcf.add_heightfield`, terrain pieces, its
robot builder); the hallway sets the physics options, compiles, and runs ``mj_forward`` so that
sensors read the start state before the task binds its names to ids.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Callable, Protocol

import mujoco

if TYPE_CHECKING:
    from terrabench.sim.physics import PhysicsConfig


class SceneTask(Protocol):
    """What scene assembly reads of a task: the scene-building part of
    :class:`terrabench.systems.base.Task` (restated structurally, as that module imports the loop)."""

    @property
    def physics(self) -> PhysicsConfig: ...

    def build(self, spec: mujoco.MjSpec) -> None: ...


def compile_scene(task: SceneTask) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Build ``task``'s scene into a new spec, compile it and forward the start state."""
    spec = mujoco.MjSpec()
    task.physics.apply(spec)
    task.build(spec)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data


def index_view(array: Any, ids: Any) -> Any:
    """``array[ids]`` as a view when the ids are evenly spaced (a slice), else a copy.

    Tasks write commands into ``MjData.ctrl`` and model fields every control period; through a
    view ``view[:] = x`` writes in place without numpy's fancy-indexing path. The caller must
    treat the result as writable only when ``numpy.shares_memory(result, array)``; use
    :func:`writer` for a setter that always writes through.
    """
    import numpy as np

    ids = np.asarray(ids, int).ravel()
    if len(ids) == 0:
        return array[ids]
    if len(ids) == 1:
        return array[ids[0]: ids[0] + 1]
    step = int(ids[1] - ids[0])
    if step > 0 and np.array_equal(ids, ids[0] + step * np.arange(len(ids))):
        return array[ids[0]: ids[-1] + 1: step]
    return array[ids]


def writer(array: Any, ids: Any) -> Callable[[Any], None]:
    """A function ``set(values)`` doing ``array[ids] = values``, through a view when it can."""
    import numpy as np

    view = index_view(array, ids)
    if len(view) and np.shares_memory(view, array):
        def set_view(values: Any) -> None:
            view[:] = values
        return set_view
    ids = np.asarray(ids, int)

    def set_fancy(values: Any) -> None:
        array[ids] = values
    return set_fancy
