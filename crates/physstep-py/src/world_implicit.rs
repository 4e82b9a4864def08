//! `World`'s implicit-solver settings and what the latest implicit step's solve did.

use crate::convert::{count, flag, float, invalid, text, whole};
use crate::handle::World;
use crate::py_err;
use pyo3::prelude::*;
use pyo3::types::PyDict;

#[pymethods]
impl World {
    /// Sets the implicit methods' solver: Newton's relative tolerance `tol` and iteration
    /// cap `max_iter`, the conjugate-gradient tolerance `cg_tol` and cap `cg_max_iter` of
    /// the sparse solve and its `preconditioner` (`"cholesky"`: the complete sparse Cholesky
    /// factor in a minimum-degree order, the exact solve, made at a step's first Newton update
    /// and kept for its next where that is cheaper; `"incomplete-cholesky"`: block IC(0) on
    /// the springs, exact on a chain; `"block-jacobi"`: the particles' diagonal blocks), and
    /// `dense_up_to` (systems of at most this many unknowns are solved densely; 0 always
    /// sparse), and `exact_jacobian` (with `"cholesky"`, each sparse Newton update of
    /// backward Euler and implicit midpoint takes the springs' exact Jacobian where the whole
    /// matrix is positive definite, the semidefinite one elsewhere; `False`: the semidefinite
    /// one always, the iteration before 2026-11-27), and `energy_halvings` (the linearly
    /// implicit step: a step that would raise the energy by more than rounding is taken again
    /// as two of half the size, each checked the same way, at most this many times over,
    /// 0 to 16; 0 takes one linear solve a step always). Arguments left out keep their values;
    /// the defaults are `tol=1e-11, max_iter=500, cg_tol=1e-10, cg_max_iter=1000,
    /// preconditioner="cholesky", dense_up_to=64, exact_jacobian=True, energy_halvings=4`.
    /// `tol` is relative to the terms Newton balances, stiffness included: with the exact
    /// Jacobian the last update lands on the rounding floor and a backward-Euler step of a
    /// stiff chain at the default is the converged one; with the semidefinite matrix alone its
    /// velocities were about 1e-6 (relative) from the converged step's (docs/stiff.md);
    /// `tol=1e-13` gives the converged step either way.
    #[pyo3(signature = (*, tol=None, max_iter=None, cg_tol=None, cg_max_iter=None, dense_up_to=None, preconditioner=None, exact_jacobian=None, energy_halvings=None))]
    #[allow(clippy::too_many_arguments)]
    fn set_implicit(
        &self,
        tol: Option<&Bound<'_, PyAny>>,
        max_iter: Option<&Bound<'_, PyAny>>,
        cg_tol: Option<&Bound<'_, PyAny>>,
        cg_max_iter: Option<&Bound<'_, PyAny>>,
        dense_up_to: Option<&Bound<'_, PyAny>>,
        preconditioner: Option<&Bound<'_, PyAny>>,
        exact_jacobian: Option<&Bound<'_, PyAny>>,
        energy_halvings: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let mut g = self.lock()?;
        let mut p = g.engine.implicit();
        // An iteration cap: at least one, and what the solver counts in (no silent clamp).
        let iterations =
            |o: &Bound<'_, PyAny>, f: &str| whole(o, f, 1, i64::from(u32::MAX)).map(|n| n as u32);
        if let Some(o) = tol {
            p.tol = float(o, "tol")?;
        }
        if let Some(o) = max_iter {
            p.max_iter = iterations(o, "max_iter")?;
        }
        if let Some(o) = cg_tol {
            p.cg.tol = float(o, "cg_tol")?;
        }
        if let Some(o) = cg_max_iter {
            p.cg.max_iter = iterations(o, "cg_max_iter")?;
        }
        if let Some(o) = dense_up_to {
            p.dense_up_to = usize::try_from(count(o, "dense_up_to")?).unwrap_or(usize::MAX);
        }
        if let Some(o) = preconditioner {
            let names = physstep::linalg::Preconditioner::NAMES;
            let expected = format!("one of '{}'", names.join("', '"));
            p.cg.preconditioner = physstep::linalg::Preconditioner::named(&text(o, "preconditioner")?)
                .ok_or_else(|| invalid("preconditioner", o, &expected))?;
        }
        if let Some(o) = exact_jacobian {
            p.exact_jacobian = flag(o, "exact_jacobian")?;
        }
        if let Some(o) = energy_halvings {
            let most = i64::from(physstep::integrators::MAX_ENERGY_HALVINGS);
            p.energy_halvings = whole(o, "energy_halvings", 0, most)? as u32;
        }
        g.engine.set_implicit(p).map_err(py_err)
    }

    /// What the latest step's implicit solve did: `newton` (updates; under
    /// `linearly-implicit-euler` its linear solves, 1, or 3 and more where the step was halved
    /// to keep the energy from rising), `cg` (conjugate-gradient iterations over them, 0 for
    /// the dense solve), `residual` (Newton's final, relative), `sparse`; None under an
    /// explicit method.
    #[getter]
    fn solve_stats<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(s) = self.lock()?.engine.integrator().solve_stats() else { return Ok(None) };
        let d = PyDict::new(py);
        d.set_item("newton", s.newton)?;
        d.set_item("cg", s.cg)?;
        d.set_item("residual", s.residual)?;
        d.set_item("sparse", s.sparse)?;
        Ok(Some(d))
    }
}
