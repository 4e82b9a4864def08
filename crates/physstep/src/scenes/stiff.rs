//! The stiff spring networks: a chain and a cloth whose springs are far stiffer than the
//! game step resolves (k / m dt^2 in the thousands), where explicit methods explode and the
//! implicit ones take large steps (Baraff and Witkin).

use super::{Exact, Param, Result};
use crate::forces::{Endpoint, Force};
use crate::world::World;

/// An undamped spring of stiffness `k` and rest length `rest` from particle `i` to `j`.
fn spring(i: usize, j: Endpoint, k: f64, rest: f64) -> Force {
    Force::Spring { i, j, stiffness: k, rest_length: rest, damping: 0.0 }
}

/// The `stiff-chain` scene: `n` particles on 1 m of stiff springs after a pinned one, swinging down.
///
/// # Errors
/// As [`World::add_particles`] and [`World::add_force`].
pub(super) fn chain(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    // n moving particles on 1 m of chain after one pinned at the origin, laid out
    // horizontally so the chain swings down.
    let (n, k, m) = (v("n") as usize, v("k"), v("m"));
    let sp = 1.0 / n as f64;
    let x: Vec<f64> = (1..=n).flat_map(|i| [i as f64 * sp, 0.0]).collect();
    w.add_particles(&[0.0, 0.0], None, Some(&[m]), true)?;
    w.add_particles(&x, None, Some(&vec![m; n]), false)?;
    for i in 1..=n {
        w.add_force(spring(i, Endpoint::Particle(i - 1), k, sp))?;
    }
    w.add_force(Force::Gravity { g: [0.0, -v("g"), 0.0] })?;
    Ok(None)
}

/// The `stiff-cloth` scene: an `n x n` cloth of stiff structural and shear springs, two corners pinned, falling.
///
/// # Errors
/// As [`World::add_particles`] and [`World::add_force`].
pub(super) fn cloth(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    // An n x n grid 1 m square lying flat (z = 0), its two corners on the y = 1 edge
    // pinned; structural springs along the grid and shear springs across each cell.
    let (n, k, m) = (v("n") as usize, v("k"), v("m"));
    // n may be up to a million; the grid of n^2 particles is refused before it is built.
    if n.saturating_mul(n) > super::specs::MAX_PARTICLES {
        return Err(crate::Error::invalid(
            "n x n",
            format!("{n} x {n}"),
            format!("at most {} particles", super::specs::MAX_PARTICLES),
        ));
    }
    let sp = 1.0 / (n - 1).max(1) as f64;
    let id = |r: usize, c: usize| r * n + c;
    for r in 0..n {
        for c in 0..n {
            let pinned = r == n - 1 && (c == 0 || c == n - 1);
            w.add_particles(&[c as f64 * sp, r as f64 * sp, 0.0], None, Some(&[m]), pinned)?;
        }
    }
    let diag = sp * std::f64::consts::SQRT_2;
    for r in 0..n {
        for c in 0..n {
            if c + 1 < n {
                w.add_force(spring(id(r, c), Endpoint::Particle(id(r, c + 1)), k, sp))?;
            }
            if r + 1 < n {
                w.add_force(spring(id(r, c), Endpoint::Particle(id(r + 1, c)), k, sp))?;
            }
            if r + 1 < n && c + 1 < n {
                w.add_force(spring(id(r, c), Endpoint::Particle(id(r + 1, c + 1)), k, diag))?;
                w.add_force(spring(id(r, c + 1), Endpoint::Particle(id(r + 1, c)), k, diag))?;
            }
        }
    }
    w.add_force(Force::Gravity { g: [0.0, 0.0, -v("g")] })?;
    Ok(None)
}
