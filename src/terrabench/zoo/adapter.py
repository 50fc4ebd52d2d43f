"""What a system gives the zoo: its robot's size, its go-to-goal methods, the families it enters.

A system's ``zoo.py`` defines one :class:`ZooAdapter` and registers it with
:func:`register_adapter` (the built-in systems' adapters are imported by the zoo system,
:data:`BUILTIN`; a plugin system calls :func:`register_adapter` from its own ``register``
function, which runs through the ``terrabench.systems`` entry point in every process). The zoo's
methods are ``<robot>.<method>`` (``octopus.clm``); a family the robot cannot enter is declared
in :attr:`ZooAdapter.unsupported` with its reason, and asking for it raises that reason.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Any, Mapping

#: the adapters of the built-in systems (modules imported on first use). The ``soil`` system (the
#: CMU single-wheel rig) has none: it is a wheel on a test bed, not a robot that crosses a course.
BUILTIN = ("terrabench.systems.mrs_cwc.zoo", "terrabench.systems.octopus.zoo", "terrabench.systems.srwmr.zoo",
           "terrabench.systems.beams.zoo")


@dataclass(frozen=True)
class Footprint:
    """A robot's size as the courses and the relative severities use it.

    ``length``: rearmost to foremost ground contact (m); ``front``: from the tracked reference
    body's origin forward to the foremost point (m); ``width``: overall, arms or wheels out (m);
    ``height``: body height, ground to top of the body (m); ``wheel_radius``: the radius of its
    ground contact (wheel, track pulley) (m); ``mass``: kg; ``speed``: nominal ground speed (m/s).
    """

    length: float
    front: float
    width: float
    height: float
    wheel_radius: float
    mass: float
    speed: float


class ZooAdapter:
    """Base of a system's zoo adapter (override the hooks; see :mod:`terrabench.systems.octopus.zoo`).

    Class attributes:
        robot: the system id whose robot this is.
        label: display name (``"OCTOPUS"``).
        methods: method -> one line (the go-to-goal controllers).
        default_methods: the methods ``terrabench run zoo`` plans without ``--methods`` (() = all).
        unsupported: family id -> why the robot cannot enter it (one line).
    """

    robot: str = ""
    label: str = ""
    methods: Mapping[str, str] = {}
    default_methods: tuple[str, ...] = ()
    unsupported: Mapping[str, str] = {}

    def footprint(self) -> Footprint:
        raise NotImplementedError

    def method_reason(self, method: str, family: str) -> str | None:
        """Why ``method`` does not apply to ``family`` (None: it applies). Default: the family's
        :attr:`unsupported` reason."""
        return self.unsupported.get(family)

    def supports(self, method: str, family: str) -> bool:
        return self.method_reason(method, family) is None

    def refuse(self, method: str, family: str) -> None:
        """ValueError with the reason when ``method`` cannot enter ``family``."""
        why = self.method_reason(method, family)
        if why is not None:
            raise ValueError(f"{self.robot}.{method} cannot enter the zoo family {family!r}: {why}")

    #: the robot system's config class and its zoo task class (``task_cls(method, course, cfg,
    #: zoo_cfg, footprint, timeout, seed)``), read by the default hooks below
    config_cls: Any = None
    task_cls: Any = None

    def robot_config(self, method: str) -> dict[str, Any]:
        """The robot system's config a trial runs with (stored with the trial, as a dict); default:
        the whole default :attr:`config_cls`."""
        from terrabench.config import to_dict

        return to_dict(self.config_cls())

    def make_task(self, method: str, course: Any, robot_cfg: Mapping[str, Any], zoo_cfg: Any, timeout: float,
                  seed: int) -> Any:
        """The trial's task: :attr:`task_cls` on the stored ``robot_cfg`` read back into :attr:`config_cls`."""
        from terrabench.config import from_dict

        return self.task_cls(method, course, from_dict(self.config_cls, robot_cfg), zoo_cfg, self.footprint(),
                             timeout, seed)

    def make_controller(self, method: str, task: Any) -> Any:
        raise NotImplementedError


#: robot (system id) -> its adapter
ADAPTERS: dict[str, ZooAdapter] = {}
_loaded = False


def register_adapter(adapter: ZooAdapter) -> ZooAdapter:
    """Add ``adapter`` (a plugin system calls this from its ``register``); the same robot twice is refused."""
    if not adapter.robot:
        raise ValueError("a zoo adapter needs a robot id (its system's id)")
    old = ADAPTERS.get(adapter.robot)
    if old is not None and type(old) is not type(adapter):
        raise ValueError(f"a zoo adapter for {adapter.robot!r} is registered already ({type(old).__name__})")
    ADAPTERS[adapter.robot] = adapter
    return adapter


def adapters() -> dict[str, ZooAdapter]:
    """Every registered adapter (the built-in ones imported first), in registration order."""
    global _loaded
    if not _loaded:
        _loaded = True
        for mod in BUILTIN:
            importlib.import_module(mod)
    return ADAPTERS


def split_method(mid: str) -> tuple[ZooAdapter, str]:
    """``"octopus.clm"`` -> (the octopus adapter, ``"clm"``); ValueError naming the valid ids."""
    robot, _, method = mid.partition(".")
    ad = adapters().get(robot)
    if ad is None or method not in ad.methods:
        valid = [f"{r}.{m}" for r, a in adapters().items() for m in a.methods]
        raise ValueError(f"unknown zoo method {mid!r}; valid: {', '.join(valid)}")
    return ad, method
