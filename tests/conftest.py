import os

os.environ.setdefault("MPLBACKEND", "Agg")

import pytest  # noqa: E402

from terrabench.terrain.dataset import Terrain  # noqa: E402
from terrabench.terrain.sine_sum import SineSumParams  # noqa: E402


@pytest.fixture
def flat_terrain() -> Terrain:
    """A perfectly flat terrain of the benchmark's size (all amplitudes zero)."""
    p = SineSumParams(size=0.05, xy_proportion=0.5, height=0.1, freq=(0.3, 0.3, 0.3), ampl=(0.0, 0.0, 0.0),
                      phase=(0.0, 0.0, 0.0))
    return Terrain("FLAT", "A", 0, p)
