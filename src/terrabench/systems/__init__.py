"""Robot systems. Each subpackage exposes ``SYSTEM``, an object implementing :class:`base.System`."""
