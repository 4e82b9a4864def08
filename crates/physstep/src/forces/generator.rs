//! User forces: any force law, written by the user, behind the [`ForceGenerator`] trait.
//!
//! Built-in forces stay a closed enum on the hot path; a generator is called once per force
//! evaluation for all particles at once (never per particle), so its cost is one dynamic call
//! per evaluation, however many particles there are.

use std::fmt;
use std::sync::Arc;

/// A force law on every particle of a world, written by the user.
///
/// `x`, `v` and `f` are flat, `n * dim` long (particle `p`, axis `k` at `p * dim + k`). A
/// generator is shared, not copied, by clones of its world, hence `&self` and `Send + Sync`.
pub trait ForceGenerator: Send + Sync {
    /// A name for messages (`"wind"`).
    fn name(&self) -> &str {
        "user force"
    }

    /// Adds the forces, N, at time `t` (s), positions `x` (m) and velocities `v` (m/s) to
    /// `f`.
    ///
    /// # Errors
    /// Any message: the step that asked is rolled back and fails with
    /// [`crate::Error::Force`] naming the force.
    fn add_forces(&self, t: f64, x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String>;

    /// Hands the forces, N, at `t`, `x`, `v` to `take` as one `x.len()`-long slice, the way a
    /// world with a single generator reads them: it adds them to the accelerations in the same
    /// pass that checks them, so a generator that already holds its forces in a buffer of its
    /// own (a Python force's array) saves the copy into `scratch` and a pass over it. The
    /// default zeroes `scratch`, calls [`ForceGenerator::add_forces`] into it and hands it on.
    ///
    /// # Errors
    /// As [`ForceGenerator::add_forces`]; `take` is then not called.
    fn forces_to(
        &self,
        t: f64,
        x: &[f64],
        v: &[f64],
        scratch: &mut Vec<f64>,
        take: &mut dyn FnMut(&[f64]),
    ) -> Result<(), String> {
        scratch.clear();
        scratch.resize(x.len(), 0.0);
        self.add_forces(t, x, v, scratch)?;
        take(scratch);
        Ok(())
    }

    /// Whether the forces depend on `v` (the default, the safe answer). Methods that would
    /// re-evaluate at an end-of-step velocity skip it when no force depends on velocity.
    fn velocity_dependent(&self) -> bool {
        true
    }

    /// Potential energy at positions `x`, J, or `None` when the force has none (then the
    /// world's energy is unknown rather than wrong).
    fn potential(&self, x: &[f64]) -> Option<f64> {
        let _ = x;
        None
    }

    /// Adds `dF/dx` (N/m) and `dF/dv` (N s/m), row-major `(n dim) x (n dim)`, and returns
    /// `true`; `false` (the default) lets the implicit methods use finite differences.
    fn jacobian(&self, t: f64, x: &[f64], v: &[f64], dfdx: &mut [f64], dfdv: &mut [f64]) -> bool {
        let _ = (t, x, v, dfdx, dfdv);
        false
    }
}

/// A generator in a world: shared with the world's clones.
#[derive(Clone)]
pub struct UserForce(pub Arc<dyn ForceGenerator>);

impl fmt::Debug for UserForce {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "UserForce({:?})", self.0.name())
    }
}
