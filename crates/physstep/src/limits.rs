//! The numbers physstep accepts and the one divergence predicate.
//!
//! A state entry past [`RUNAWAY`] (or NaN, or infinite) is a divergence wherever it is found:
//! the staged step's Check, the fused kernels' folded flag, the Collide stage and the
//! derivative refreshed after a change by hand all ask [`runaway`] (or its scans over a
//! slice, `any_runaway` and `first_runaway`).
//! Parameters are bounded by [`PARAM_MIN`] and [`PARAM_MAX`] so that every accepted value is
//! representable in the physics it feeds.

/// Largest magnitude a state or acceleration entry may reach: beyond it the run has run away
/// (explicit Euler on an oscillator at a large dt), and squares of it (energies) would
/// overflow to infinity. A value past it is a divergence, like a NaN.
pub const RUNAWAY: f64 = 1e100;

/// Largest magnitude of a scene or body parameter. Bounds keep every accepted scene
/// representable: squares, cubes and products of parameters (r^2 in gravity, k x^2 in an
/// energy) neither overflow nor underflow to zero, so no accepted value drops physics in
/// silence.
pub const PARAM_MAX: f64 = 1e12;

/// Smallest magnitude of a nonzero size parameter (mass, length, stiffness).
pub const PARAM_MIN: f64 = 1e-12;

/// Whether `x` is NaN, infinite or past [`RUNAWAY`]: the one divergence predicate. Written
/// `!(|x| <= RUNAWAY)`, true for NaN too (NaN fails every comparison), and without a branch,
/// so a kernel folds it into a flag in registers.
#[inline(always)]
#[must_use]
pub fn runaway(x: f64) -> bool {
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    !(x.abs() <= RUNAWAY)
}

/// Whether any entry of `v` is [`runaway`] (a flag folded without branches).
#[inline]
#[must_use]
pub(crate) fn any_runaway(v: &[f64]) -> bool {
    v.iter().fold(false, |acc, &x| acc | runaway(x))
}

/// Index of the first entry of `v` that is [`runaway`]. The scan is branch-free per block of
/// values, so it runs at memory speed; only a block that holds one is searched element by
/// element.
#[must_use]
pub(crate) fn first_runaway(v: &[f64]) -> Option<usize> {
    const BLOCK: usize = 256;
    v.chunks(BLOCK).enumerate().find_map(|(b, chunk)| {
        if any_runaway(chunk) {
            chunk.iter().position(|&x| runaway(x)).map(|i| b * BLOCK + i)
        } else {
            None
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runaway_is_nan_infinity_or_past_the_limit() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1.000_000_1e100, -2e100] {
            assert!(runaway(bad), "{bad}");
        }
        for good in [0.0, -0.0, 1e100, -1e100, f64::MIN_POSITIVE, 5e-324] {
            assert!(!runaway(good), "{good}");
        }
    }

    #[test]
    fn the_first_runaway_entry_is_found_in_any_block() {
        let mut v = vec![1.0; 1000];
        assert_eq!(first_runaway(&v), None);
        v[700] = f64::NAN;
        v[900] = f64::INFINITY;
        assert_eq!(first_runaway(&v), Some(700));
        v[3] = -1e101;
        assert_eq!(first_runaway(&v), Some(3));
    }
}
