"""Gymnasium environments of the terrabench systems.

``import terrabench.envs`` registers one versioned id per entry of each system's ``env_ids``
(e.g. ``terrabench/MRSCWC-v1``), all with the generic entry point
``terrabench.envs.core:TerrabenchEnv`` and ``kwargs={"system": <system id>}``; nothing is
built until ``gymnasium.make``::

    import gymnasium, terrabench.envs
    env = gymnasium.make("terrabench/MRSCWC-v1", method="cwc-tdt", group="B",
                         overrides={"protocol.timeout": 60.0})

A system gets an env by implementing ``System.env_adapter()`` (see
:mod:`terrabench.envs.adapter`) and listing its ids in ``System.env_ids``.
"""

from __future__ import annotations

ENTRY_POINT = "terrabench.envs.core:TerrabenchEnv"


def register_envs() -> list[str]:
    """Register every system's ``env_ids`` with Gymnasium (idempotent); returns the ids."""
    import gymnasium

    from terrabench.catalog import populate
    from terrabench.catalog import system as get_system

    ids: list[str] = []
    for sid in populate().ids("system"):
        sysobj = get_system(sid)
        for env_id in sysobj.env_ids:
            if env_id not in gymnasium.registry:
                gymnasium.register(id=env_id, entry_point=ENTRY_POINT, kwargs={"system": sid})
            ids.append(env_id)
    return ids


register_envs()
