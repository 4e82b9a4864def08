"""What a run did to its scene's position constraints (``physstep run`` reports it)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from . import Trajectory


def summary(traj: Trajectory) -> dict[str, Any] | None:
    """``{"max_violation": m}``, the largest constraint violation (m) over the recorded rows of
    a built-in scene's run, or None when the scene has no constraints (or is a user system,
    whose constraints the trajectory does not carry)."""
    from . import World, scene

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
