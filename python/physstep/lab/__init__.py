"""The integrator lab: measure how each method behaves on a scene, or on your own system.

Four measurements, each returning a typed result (a frozen dataclass whose fields are
documented in :mod:`physstep.lab.results`; ``.to_dict()`` gives the plain, JSON-ready dict
the command line prints with ``--format json``):

- :func:`compare`: one row per method (order, force evaluations per step, energy error and
  drift, final error, ns per step): a :class:`CompareResult` of :class:`CompareRow`.
- :func:`order`: the observed convergence order from successive halvings of dt: an
  :class:`OrderResult` of :class:`OrderRun`.
- :func:`stability`: the largest stable dt, from the amplification matrix of the repeating
  step map on the linear/affine scenes and from a bounded-growth search on the others: a
  :class:`StabilityResult`.
- :func:`sweep`: work-precision data (error against force evaluations and time): a
  :class:`SweepResult` of :class:`SweepRow`.
- :func:`compare_solvers` (also ``compare(scene, solvers=...)``): the contact solvers side by
  side on a contact scene (penetration, drift, joint error, jitter, the friction test, passes
  and ms a step, a verdict): a :class:`SolverCompareResult` of :class:`SolverRow`
  (:mod:`physstep.lab.solvers`); :func:`sweep_solvers` the same over splits of the passes
  into substeps and iterations: a :class:`SolverSweepResult`.

``compare`` and ``sweep`` take ``jobs=N`` (local processes, where the work pays for them:
:mod:`physstep.lab.parallel`) or ``executor=``.

Each takes, where it takes a scene name, a *system* as :func:`physstep.simulate` does: a
:class:`physstep.Flow`, or a zero-argument callable returning a fresh World (your particles
and Python forces) or a Flow (:mod:`physstep.lab.system`). Errors are measured against the
scene's exact solution where it has one and otherwise against a reference solution (RK4 at
a sixteenth of the finest dt, interpolated with cubic Hermite polynomials between its rows:
:mod:`physstep.lab.reference`); every result says which in ``error_against``. Every run the
lab would make is checked against :func:`physstep.simulate`'s limits before any is made: a
refusal names the lab's own argument (``dt``, ``dts``, ``until``, ``levels``).

The package: :mod:`~physstep.lab.common` (limits, checks, timing, energy statistics),
:mod:`~physstep.lab.system` (a scene or a system, its time scale), :mod:`~physstep.lab.reference`,
:mod:`~physstep.lab.results` (what the measurements return), :mod:`~physstep.lab.parallel`
(rows in processes or on an executor), and one module per measurement.
"""

from __future__ import annotations

from physstep.lab.common import (
    ENERGY_ERROR,
    MAX_RECORDED,
    MAX_STEPS,
    REFERENCE_METHOD,
    REFERENCE_REFINE,
    TIMING_MAX_RUNS,
    TIMING_MAX_S,
    TIMING_MIN_RUNS,
    TIMING_MIN_S,
)
from physstep.lab.common import drift as _drift  # noqa: F401 (the tests use it)
from physstep.lab.compare import compare
from physstep.lab.order import MAX_LEVELS, MAX_ORDER_STEPS, ROUNDOFF, UNTIL_SCALES, order
from physstep.lab.parallel import CHUNKS_PER_WORKER, POOL_START_S
from physstep.lab.reference import reference
from physstep.lab.results import (
    CompareResult,
    CompareRow,
    GrowthTest,
    OrderResult,
    OrderRun,
    SolverCompareResult,
    SolverRow,
    SolverSweepResult,
    StabilityResult,
    SweepResult,
    SweepRow,
)
from physstep.lab.solvers import compare_solvers, sweep_solvers
from physstep.lab.stability import (
    ABOVE_FACTORS,
    CAP_SCALES,
    CLUSTER_TOL,
    GRID_LOW_SCALES,
    GRID_PER_DECADE,
    GROWTH_LIMIT,
    GROWTH_SCREEN_STEPS,
    GROWTH_STEPS,
    GROWTH_STEPS_SYSTEM,
    HORIZON_DT,
    HORIZON_SHRINK,
    HORIZON_STEPS,
    LINEAR_SCENES,
    MAX_BISECTIONS,
    MAX_CAP_SCALES,
    NOISE_REL,
    RHO_TOL,
    RTOL_GROWTH,
    RTOL_LINEAR,
    RTOL_RANGE,
    SCALE_RUN_SCALES,
    SCALE_RUN_STEPS,
    SCAN_FACTORS,
    SCAN_ROUNDS,
    amplification,
    stability,
)
from physstep.lab.sweep import sweep
from physstep.lab.system import FALLBACK_TIME_SCALE, time_scale

__all__ = [
    "ABOVE_FACTORS",
    "CAP_SCALES",
    "CHUNKS_PER_WORKER",
    "CLUSTER_TOL",
    "CompareResult",
    "CompareRow",
    "ENERGY_ERROR",
    "FALLBACK_TIME_SCALE",
    "GRID_LOW_SCALES",
    "GRID_PER_DECADE",
    "GROWTH_LIMIT",
    "GROWTH_SCREEN_STEPS",
    "GROWTH_STEPS",
    "GROWTH_STEPS_SYSTEM",
    "GrowthTest",
    "HORIZON_DT",
    "HORIZON_SHRINK",
    "HORIZON_STEPS",
    "LINEAR_SCENES",
    "MAX_BISECTIONS",
    "MAX_CAP_SCALES",
    "MAX_LEVELS",
    "MAX_ORDER_STEPS",
    "MAX_RECORDED",
    "MAX_STEPS",
    "NOISE_REL",
    "OrderResult",
    "OrderRun",
    "POOL_START_S",
    "REFERENCE_METHOD",
    "REFERENCE_REFINE",
    "RHO_TOL",
    "ROUNDOFF",
    "RTOL_GROWTH",
    "RTOL_LINEAR",
    "RTOL_RANGE",
    "SCALE_RUN_SCALES",
    "SCALE_RUN_STEPS",
    "SCAN_FACTORS",
    "SCAN_ROUNDS",
    "SolverCompareResult",
    "SolverRow",
    "SolverSweepResult",
    "StabilityResult",
    "SweepResult",
    "SweepRow",
    "TIMING_MAX_RUNS",
    "TIMING_MAX_S",
    "TIMING_MIN_RUNS",
    "TIMING_MIN_S",
    "UNTIL_SCALES",
    "amplification",
    "compare",
    "compare_solvers",
    "order",
    "reference",
    "stability",
    "sweep",
    "sweep_solvers",
    "time_scale",
]
