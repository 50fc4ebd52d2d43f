"""Scene assembly: physics options + the task's arena and robot, compiled with ``MjSpec``.

A task adds what it needs to an empty :class:`mujoco.MjSpec` in ``task.build(spec)`` (a
terrain height field with :func:`terrabench.terrain.mjcf.add_heightfield`, terrain pieces, its
robot builder); the hallway sets the physics options, compiles, and runs ``mj_forward`` so that
sensors read the start state before the task binds its names to ids.
"""

from __future__ import annotations

from typing import Any

import mujoco


def compile_scene(task: Any) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """Build ``task``'s scene into a new spec, compile it and forward the start state."""
    spec = mujoco.MjSpec()
    task.physics.apply(spec)
    task.build(spec)
    model = spec.compile()
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    return model, data
