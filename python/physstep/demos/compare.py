"""The same scene under several methods side by side: the notes' orbit picture, live."""

from __future__ import annotations

from physstep.demos.particles import OrbitDemo


class CompareDemo(OrbitDemo):
    """The circular orbit at dt = 0.1 s under four methods, one panel each, as the notes draw
    it: explicit Euler spirals out, backward Euler spirals in (until its equation has no
    root near the centre, a ConvergenceError the panel shows), symplectic Euler keeps a
    closed curve, RK4 the circle. ``Tab`` picks the panel the ``m`` key changes."""

    name = "compare"
    dt = 0.1
    methods = ("explicit-euler", "symplectic-euler", "rk4", "backward-euler")
    draggable = False
    view = (0.0, 0.0, 1.9)
