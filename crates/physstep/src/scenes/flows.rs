//! The flow scenes: the Lorenz, Rossler and Thomas attractors from a start `(x0, y0, z0)`.

use super::Param;
use crate::flows::Flow;

/// The start `(x0, y0, z0)` of a flow scene.
fn start(v: &Param<'_>) -> [f64; 3] {
    [v("x0"), v("y0"), v("z0")]
}

/// The `lorenz` scene.
pub(super) fn lorenz(v: &Param<'_>) -> (Flow, [f64; 3]) {
    (Flow::Lorenz { sigma: v("sigma"), rho: v("rho"), beta: v("beta") }, start(v))
}

/// The `rossler` scene.
pub(super) fn rossler(v: &Param<'_>) -> (Flow, [f64; 3]) {
    (Flow::Rossler { a: v("a"), b: v("b"), c: v("c") }, start(v))
}

/// The `thomas` scene.
pub(super) fn thomas(v: &Param<'_>) -> (Flow, [f64; 3]) {
    (Flow::Thomas { b: v("b") }, start(v))
}
