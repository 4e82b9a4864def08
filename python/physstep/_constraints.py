"""What a run did to its position constraints (``physstep run`` reports it)."""

from __future__ import annotations

import copy
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from . import Trajectory


def summary(traj: Trajectory) -> dict[str, Any] | None:
    """``{"max_violation": m}``, the largest constraint violation (m) over the recorded rows
    of the world that ran: a system's own World (``traj.world``: a scene file, a callable),
    else the built-in scene ``traj.scene`` rebuilt; None when that world has no constraints.
    A scene file named like a built-in (``pendulum.toml``) is measured by its own
    constraints, never by the built-in's."""
    from . import World, scene

    if traj.world is not None:
        world = copy.copy(traj.world)
    else:
        try:
            scene(traj.scene)
        except ValueError:
            return None
        world = World.from_scene(traj.scene, traj.method, traj.dt, dict(traj.params))
    shape = world.positions.shape
    if world.constraint_count == 0 or traj.x.shape[1] != world.positions.size:
        return None
    worst = 0.0
    for row in traj.x:
        world.positions = row.reshape(shape)
        worst = max(worst, world.constraint_violation())
    return {"max_violation": worst}
