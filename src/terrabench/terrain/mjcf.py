"""Put a heightfield into a :class:`mujoco.MjSpec` as the ground."""

from __future__ import annotations

import mujoco
import numpy as np

#: Collision bit carried by the ground; robot geoms that should touch it set it in conaffinity.
GROUND_BIT = 1


def add_heightfield(
    spec: mujoco.MjSpec,
    h: np.ndarray,
    x: np.ndarray,
    y: np.ndarray,
    *,
    name: str = "terrain",
    friction: float = 2.0,
    base: float = 1.0,
) -> mujoco.MjsGeom:
    """Add a grid of heights as a MuJoCo hfield geom.

    Args:
        spec: the scene under construction.
        h: heights, shape (nx, ny), ``h[i, j]`` at world ``(x[i], y[j])`` (m).
        x: vertex x coordinates, shape (nx,), evenly spaced and increasing (m).
        y: vertex y coordinates, shape (ny,), evenly spaced, either direction (m).
        friction: sliding friction of the ground.
        base: thickness of the solid below the lowest vertex (m).

    MuJoCo stores an hfield row-major with rows along +y and columns along +x, normalised
    to [0, 1] and scaled by an elevation; the geom sits at the lowest height.
    """
    if y[0] > y[-1]:
        h, y = h[:, ::-1], y[::-1]
    lo, hi = float(h.min()), float(h.max())
    elev = max(hi - lo, 1e-6)
    data = ((h - lo) / elev).T  # (ny, nx): rows along y
    hf = spec.add_hfield(
        name=name,
        nrow=data.shape[0],
        ncol=data.shape[1],
        size=[(x[-1] - x[0]) / 2, (y[-1] - y[0]) / 2, elev, base],
    )
    hf.userdata = data.ravel().astype(np.float32).tolist()
    return spec.worldbody.add_geom(
        name=name,
        type=mujoco.mjtGeom.mjGEOM_HFIELD,
        hfieldname=name,
        pos=[(x[0] + x[-1]) / 2, (y[0] + y[-1]) / 2, lo],
        friction=[friction, 0.005, 0.0001],
        contype=GROUND_BIT,
        conaffinity=0,
        rgba=[0.55, 0.5, 0.42, 1],
    )


#: name of the ground's checker material (one per model)
GROUND_MATERIAL = "ground_grid"


def ground_material(spec: mujoco.MjSpec, rgb=(0.72, 0.55, 0.38), cell: float = 0.25) -> str:
    """A checker material for a ground plane or heightfield, squares ``cell`` m wide (a 2 x 2
    checker repeated once per 2 ``cell``), so motion over flat ground reads in a clip; two shades
    of ``rgb``. Visual only: no contact parameter changes. Returns the material's name (added
    once per ``spec``)."""
    if not any(m.name == GROUND_MATERIAL for m in spec.materials):
        lo = [max(0.0, c * 0.82) for c in rgb]
        spec.add_texture(name=GROUND_MATERIAL, type=mujoco.mjtTexture.mjTEXTURE_2D,
                         builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER, rgb1=list(rgb), rgb2=lo, width=64, height=64)
        mat = spec.add_material(name=GROUND_MATERIAL, texuniform=True, texrepeat=[1.0 / (2 * cell)] * 2)
        mat.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = GROUND_MATERIAL
    return GROUND_MATERIAL
