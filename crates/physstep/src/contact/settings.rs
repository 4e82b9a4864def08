//! The contact solvers by name ([`SOLVERS`], one [`Info`] each, as the integrators have) and
//! the settings a world gives them (substeps, passes, a contact's stiffness): what the World,
//! scene files and the bindings set, apart from how a solver steps (`solver.rs`).

use crate::error::{num, Error, Result};

/// What a solver is, as the lab lists it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Info {
    /// The registry name.
    pub name: &'static str,
    /// One line on what it does.
    pub summary: &'static str,
    /// What it corrects: `"velocity"` (impulses on the velocities, positions follow by the
    /// drift) or `"velocity + position"` (impulses, then passes that move the positions).
    pub family: &'static str,
    /// Constraint passes over every contact a step, in the settings' terms (equal by default:
    /// the lab compares solvers at equal cost).
    pub passes: &'static str,
    /// How it steps (`solver.rs`).
    pub schedule: Schedule,
}

/// How a contact solver steps (`solver.rs`): the passes it makes and the coefficients of its
/// constraints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Schedule {
    /// Substeps, each a soft solve, a drift and a relax (Box2D v3).
    SoftStep,
    /// One step: every pass a rigid solve with a Baumgarte bias, then one drift (sequential
    /// impulses, Box2D v2 and Chipmunk).
    Pgs,
    /// One step: rigid velocity passes without a position bias, one drift, then passes that
    /// move the positions apart (non-linear Gauss-Seidel, Box2D v2.4's position solver).
    PgsNgs,
    /// One step: soft solve passes, one drift, then relax passes (Catto's soft PGS).
    SoftPgs,
    /// Substeps of one rigid pass each with a Baumgarte bias on the separation as it is now,
    /// static friction holding anchors, no warm starting, then relax passes after the last
    /// (Catto's sticky TGS).
    TgsSticky,
    /// The soft PGS schedule with Jacobi passes: every pair solved from the velocities of
    /// the pass's start, the changes summed and applied after the pass (the parallel form).
    Jacobi,
    /// Substeps, each a drift, one pass of position corrections and one velocity pass
    /// (rigid-body XPBD, `xpbd.rs`).
    Xpbd,
    /// One step: the drift, then position passes that move the solids apart (and joints
    /// together), the velocities the motion they leave (the notes' Verlet position
    /// projection, Jakobsen 2001, on solids; `xpbd.rs`).
    Projection,
}

/// Every contact solver, in registry order.
pub const SOLVERS: &[Info] = &[
    Info {
        name: "soft-step",
        summary: "Box2D v3's soft step: substeps of symplectic Euler, soft contacts, warm starting, relax, \
                  restitution",
        family: "velocity",
        passes: "2 x substeps x solver_iterations (a solve and a relax a substep)",
        schedule: Schedule::SoftStep,
    },
    Info {
        name: "pgs",
        summary: "projected Gauss-Seidel (sequential impulses, Box2D v2): one step of symplectic Euler, \
                  rigid contacts with a Baumgarte position bias, plain Coulomb friction, warm starting, \
                  restitution",
        family: "velocity",
        passes: "2 x substeps x solver_iterations velocity passes in one step (the soft step's count)",
        schedule: Schedule::Pgs,
    },
    Info {
        name: "pgs-ngs",
        summary: "PGS with non-linear Gauss-Seidel (Box2D v2.4): rigid velocity passes without a position \
                  bias, then position passes that push overlaps apart from the current poses (0.2 of the \
                  overlap past a 5 mm slop, at most 0.2 m), plain Coulomb friction, warm starting, restitution",
        family: "velocity + position",
        passes: "2 x substeps x solver_iterations in one step: three quarters velocity passes, a quarter \
                 position passes (at least one)",
        schedule: Schedule::PgsNgs,
    },
    Info {
        name: "soft-pgs",
        summary: "soft PGS (Catto, Solver2D): one step of symplectic Euler, soft contacts (at most half the \
                  step's rate in Hz), warm starting, solve passes, the drift, relax passes, restitution",
        family: "velocity",
        passes: "2 x substeps x solver_iterations in one step: half solve passes, half relax passes",
        schedule: Schedule::SoftPgs,
    },
    Info {
        name: "tgs-sticky",
        summary: "sticky TGS (Catto, Solver2D): substeps of one rigid pass with a Baumgarte bias of 0.8 on \
                  the separation as it is now, static friction holding the anchors, no warm starting, then \
                  relax passes, restitution",
        family: "velocity",
        passes: "2 x substeps x solver_iterations: three quarters substeps of one pass, a quarter relax \
                 passes after the last (at least one)",
        schedule: Schedule::TgsSticky,
    },
    Info {
        name: "jacobi",
        summary: "soft Jacobi (Catto, Solver2D): soft PGS's schedule, each pass solving every contact \
                  from the velocities of the pass's start and applying the sum of the changes after it \
                  (the parallel form; joints stay Gauss-Seidel), contacts at most a third of the step's rate",
        family: "velocity",
        passes: "2 x substeps x solver_iterations in one step: half solve passes, half relax passes",
        schedule: Schedule::Jacobi,
    },
    Info {
        name: "xpbd",
        summary: "rigid-body XPBD (Mueller et al. 2020): substeps of one position pass (rigid contacts, \
                  static friction and ball, hinge, weld and rod joints as position corrections) and one \
                  velocity pass (dynamic friction, restitution), velocities from the positions, no warm start",
        family: "position + velocity",
        passes: "2 x substeps x solver_iterations: substeps x solver_iterations substeps, each one position \
                 pass and one velocity pass",
        schedule: Schedule::Xpbd,
    },
    Info {
        name: "projection",
        summary: "the notes' Verlet position projection (Jakobsen 2001) on solids: one step of symplectic \
                  Euler's velocities, the drift, then position passes (rigid contacts, static friction at \
                  most mu times the normal correction, joints in XPBD form), the velocities the motion \
                  they leave; no velocity pass (no restitution)",
        family: "position",
        passes: "2 x substeps x solver_iterations position passes in one step",
        schedule: Schedule::Projection,
    },
];

/// The solver and its settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// The solver's registry name.
    pub solver: &'static str,
    /// Substeps a step (>= 1).
    pub substeps: u32,
    /// Solve and relax passes a substep (>= 1).
    pub iterations: u32,
    /// Stiffness of a contact, Hz (capped at an eighth of the substep rate; twice this against a
    /// static or kinematic solid).
    pub contact_hertz: f64,
    /// Damping ratio of a contact.
    pub damping_ratio: f64,
    /// The fastest a contact pushes overlapping solids apart, m/s.
    pub push_speed: f64,
    /// Normal speeds below this do not bounce, m/s.
    pub restitution_threshold: f64,
    /// How far apart two solids may be and still get a (speculative) contact, m.
    pub speculative_distance: f64,
    /// Stiffness of a joint, Hz (capped at a quarter of the substep rate).
    pub joint_hertz: f64,
    /// Damping ratio of a joint.
    pub joint_damping_ratio: f64,
    /// Passes that move jointed solids' positions back together after a step (0: none).
    pub joint_projection: u32,
    /// Continuous collision of fast solids against static and kinematic ones (on by
    /// default; docs/contact.md, Fast solids).
    pub continuous: bool,
    /// How long an island of solids must be slow before it falls asleep, s (0, the
    /// default: never; Box2D's is 0.5; docs/contact.md, Sleeping).
    pub sleep_time: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            solver: SOLVERS[0].name,
            substeps: 8,
            iterations: 1,
            contact_hertz: 60.0,
            damping_ratio: 10.0,
            push_speed: 3.0,
            restitution_threshold: 1.0,
            speculative_distance: 0.02,
            joint_hertz: 120.0,
            joint_damping_ratio: 2.0,
            joint_projection: 0,
            continuous: true,
            sleep_time: 0.0,
        }
    }
}

impl Settings {
    /// How the chosen solver steps ([`Info::schedule`]).
    #[must_use]
    pub fn schedule(&self) -> Schedule {
        // `solver` is a registry name: `set_solver` is the only way a world takes one (the
        // World checks a whole `Settings` through it), so the lookup finds it.
        SOLVERS.iter().find(|i| i.name == self.solver).map_or(Schedule::SoftStep, |i| i.schedule)
    }

    /// Chooses the solver by name.
    ///
    /// # Errors
    /// [`Error::UnknownName`] listing the solvers.
    pub fn set_solver(&mut self, name: &str) -> Result<()> {
        match SOLVERS.iter().find(|i| i.name == name) {
            Some(i) => {
                self.solver = i.name;
                Ok(())
            }
            None => Err(Error::UnknownName {
                kind: "contact solver".into(),
                name: name.into(),
                valid: SOLVERS.iter().map(|i| i.name.to_string()).collect(),
            }),
        }
    }

    /// Sets the substeps a step.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `substeps` unless it is 1 to 1000.
    pub fn set_substeps(&mut self, n: u32) -> Result<()> {
        if (1..=1000).contains(&n) {
            self.substeps = n;
            Ok(())
        } else {
            Err(Error::invalid("substeps", n, "1 to 1000"))
        }
    }

    /// Sets the solve and relax passes a substep.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming `solver_iterations` unless it is 1 to 1000.
    pub fn set_iterations(&mut self, n: u32) -> Result<()> {
        if (1..=1000).contains(&n) {
            self.iterations = n;
            Ok(())
        } else {
            Err(Error::invalid("solver_iterations", n, "1 to 1000"))
        }
    }

    /// Checks the contact's tuning numbers.
    ///
    /// # Errors
    /// [`Error::InvalidValue`] naming the first that is not finite and positive (the
    /// restitution threshold and the speculative distance may be 0).
    pub fn check(&self) -> Result<()> {
        if self.joint_projection > 1000 {
            return Err(Error::invalid("joint_projection", self.joint_projection, "0 to 1000"));
        }
        for (f, v, zero) in [
            ("contact_hertz", self.contact_hertz, false),
            ("damping_ratio", self.damping_ratio, false),
            ("push_speed", self.push_speed, false),
            ("restitution_threshold", self.restitution_threshold, true),
            ("speculative_distance", self.speculative_distance, true),
            ("joint_hertz", self.joint_hertz, false),
            ("joint_damping_ratio", self.joint_damping_ratio, false),
            ("sleep_time", self.sleep_time, true),
        ] {
            if !(v.is_finite() && (v > 0.0 || (zero && v == 0.0))) {
                return Err(Error::invalid(
                    f,
                    num(v),
                    if zero { "finite and >= 0" } else { "finite and > 0" },
                ));
            }
        }
        Ok(())
    }
}
