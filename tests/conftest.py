import os

os.environ.setdefault("MPLBACKEND", "Agg")

import pytest  # noqa: E402

from terrabench import portable  # noqa: E402
from terrabench.terrain.dataset import Terrain  # noqa: E402
from terrabench.terrain.sine_sum import SineSumParams  # noqa: E402


def pytest_configure(config):
    """The suite runs on the CPU code paths every trial process runs on (terrabench.portable),
    so a number a test computes in-process is the same on every CI machine: re-execute pytest
    once under the pins, with pytest's output capture released first."""
    if os.environ.get("TERRABENCH_PINNED") == "1" or not portable.wanted():
        return
    capman = config.pluginmanager.getplugin("capturemanager")
    if capman is not None:
        capman.stop_global_capturing()
    portable.reexec_pinned()


@pytest.fixture
def flat_terrain() -> Terrain:
    """A perfectly flat terrain of the benchmark's size (all amplitudes zero)."""
    p = SineSumParams(size=0.05, xy_proportion=0.5, height=0.1, freq=(0.3, 0.3, 0.3), ampl=(0.0, 0.0, 0.0),
                      phase=(0.0, 0.0, 0.0))
    return Terrain("FLAT", "A", 0, p)
