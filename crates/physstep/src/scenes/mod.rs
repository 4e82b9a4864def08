//! The built-in scenes: the defaults of the command line, the demos, the tests and the
//! benchmarks, each a [`World`] with named parameters, its energy and, where one is known,
//! its exact solution.

pub mod balls;
mod bodies;
mod breaking;
mod constrained;
pub mod file;
mod flows;
mod jointed;
mod particles;
mod solids;
mod specs;
mod stiff;

pub use specs::{resolve, spec, Loss, ParamSpec, Rule, SceneSpec, PARAM_MAX, PARAM_MIN, SCENES};

use crate::error::Result;
use crate::flows::Flow;
use crate::world::{World, WorldParams};

/// A built scene: its world, its parameters and its exact solution if known.
#[derive(Debug, Clone)]
pub struct Scene {
    /// What scene this is.
    pub spec: &'static SceneSpec,
    /// Parameter values, in the order of `spec.params`.
    pub values: Vec<f64>,
    /// The world, at t = 0.
    pub world: World,
    exact: Option<Exact>,
}

#[derive(Debug, Clone, Copy)]
enum Exact {
    /// Damped oscillator x'' = -(k/m) x - (c/m) x'.
    Oscillator { w0: f64, zeta: f64, x0: f64, v0: f64 },
    /// Constant acceleration.
    Ballistic { x0: [f64; 2], v0: [f64; 2], a: [f64; 2] },
    /// Linear drag.
    Drag { rate: f64, x0: f64, v0: f64 },
    /// Uniform circular motion: radius, angular velocity, initial phase, centre.
    Circle { r: f64, w: f64, phase: f64, sign: f64 },
    /// Kepler ellipse, GM = 1, a = 1.
    Kepler { e: f64 },
}

impl Scene {
    /// A parameter's value by name.
    #[must_use]
    pub fn param(&self, name: &str) -> Option<f64> {
        self.spec.params.iter().position(|p| p.name == name).map(|i| self.values[i])
    }

    /// Whether an exact solution is known.
    #[must_use]
    pub fn has_exact(&self) -> bool {
        self.exact.is_some()
    }

    /// The exact positions and velocities at time `t` (flat, like the world's), if known.
    #[must_use]
    pub fn exact(&self, t: f64) -> Option<(Vec<f64>, Vec<f64>)> {
        self.exact_rows(&[t])
    }

    /// [`Scene::exact`] at every time of `ts`, one row per time (flat rows, like a
    /// recording's), if known: what a recording asks for, in one pass (the kind of solution
    /// matched once, not per row).
    #[must_use]
    pub fn exact_rows(&self, ts: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
        Some(match self.exact? {
            Exact::Oscillator { w0, zeta, x0, v0 } if w0 != 0.0 && zeta == 0.0 => {
                // Undamped: the branch of `oscillator` a recording of `spring` takes, without
                // its tests per row (the same operations, the same bits).
                let b = v0 / w0;
                ts.iter().map(|&t| undamped(w0, x0, b, t)).unzip()
            }
            Exact::Oscillator { w0, zeta, x0, v0 } => {
                ts.iter().map(|&t| oscillator(w0, zeta, x0, v0, t)).unzip()
            }
            Exact::Ballistic { x0, v0, a } => ts
                .iter()
                .flat_map(|&t| {
                    (0..2).map(move |k| (x0[k] + v0[k] * t + 0.5 * a[k] * t * t, v0[k] + a[k] * t))
                })
                .unzip(),
            Exact::Drag { rate: 0.0, x0, v0 } => ts.iter().map(|&t| (x0 + v0 * t, v0)).unzip(),
            Exact::Drag { rate, x0, v0 } => ts
                .iter()
                .map(|&t| {
                    let decay = (-rate * t).exp();
                    (x0 + v0 / rate * (1.0 - decay), v0 * decay)
                })
                .unzip(),
            Exact::Circle { r, w, phase, sign } => ts
                .iter()
                .flat_map(|&t| {
                    let (s, c) = (phase + w * t).sin_cos();
                    [(r * s, r * w * c), (sign * r * c, -sign * r * w * s)]
                })
                .unzip(),
            Exact::Kepler { e } => ts
                .iter()
                .flat_map(|&t| {
                    // Mean anomaly M = t (n = 1).
                    let (s, c) = eccentric_anomaly(e, t).sin_cos();
                    let b = (1.0 - e * e).sqrt();
                    let de = 1.0 / (1.0 - e * c);
                    [(c - e, -s * de), (b * s, b * c * de)]
                })
                .unzip(),
        })
    }
}

/// Solves Kepler's equation `M = E - e sin E` for the eccentric anomaly, any `e` in [0, 1)
/// and any `M`; the result is `E` reduced to [-pi, pi] (only its sine and cosine are used).
///
/// `M` is first reduced to [-pi, pi] (the equation is 2 pi periodic: E + 2 pi solves
/// M + 2 pi) and, by the odd symmetry, to [0, pi], where the root lies in [M, M + e]
/// (E - M = e sin E is in [0, e] there) and g(E) = E - e sin E - M is increasing and convex.
/// Newton from the upper end of that bracket then converges monotonically for every e < 1
/// (no overshoot on a convex increasing function started right of the root); a bisection
/// fallback keeps every iterate inside the bracket regardless.
#[must_use]
pub fn eccentric_anomaly(e: f64, m: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let mut m = m.rem_euclid(TAU);
    if m > PI {
        m -= TAU;
    }
    let (sign, m) = if m < 0.0 { (-1.0, -m) } else { (1.0, m) };
    let (mut lo, mut hi) = (m, (m + e).min(PI));
    let mut x = hi;
    for _ in 0..200 {
        let g = x - e * x.sin() - m;
        if g == 0.0 {
            break;
        }
        if g > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let dg = 1.0 - e * x.cos();
        let mut next = x - g / dg;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if next == x || hi - lo <= 2.0 * f64::EPSILON * hi.max(1.0) {
            x = next;
            break;
        }
        x = next;
    }
    sign * x
}

/// The undamped oscillator's `(x, v)` at `t`: `x0 cos(w0 t) + b sin(w0 t)`, `b = v0 / w0`.
#[inline]
fn undamped(w0: f64, x0: f64, b: f64, t: f64) -> (f64, f64) {
    let (sn, cs) = (w0 * t).sin_cos();
    (x0 * cs + b * sn, w0 * (-x0 * sn + b * cs))
}

/// The damped oscillator `x'' + 2 zeta w0 x' + w0^2 x = 0` at time `t`, all three regimes.
fn oscillator(w0: f64, zeta: f64, x0: f64, v0: f64, t: f64) -> (f64, f64) {
    if w0 == 0.0 {
        // k = 0: pure damping x'' = -2 zeta w0 x' degenerates to free motion when c = 0 too;
        // the caller passes zeta = 0 then.
        return (x0 + v0 * t, v0);
    }
    if zeta == 0.0 {
        // Undamped (what the general branch below computes, bit for bit, without its sqrt
        // and exp: a recording asks once per row).
        return undamped(w0, x0, v0 / w0, t);
    }
    let s = zeta * w0;
    if (zeta - 1.0).abs() < 1e-12 {
        // Critical: x = (A + B t) e^{-s t}
        let (a, b) = (x0, v0 + s * x0);
        let e = (-s * t).exp();
        return ((a + b * t) * e, (b - s * (a + b * t)) * e);
    }
    if zeta < 1.0 {
        let wd = w0 * (1.0 - zeta * zeta).sqrt();
        let (a, b) = (x0, (v0 + s * x0) / wd);
        let (sn, cs) = (wd * t).sin_cos();
        // Undamped: e^0 is 1 exactly, without the call (a recording asks once per row).
        let e = if s == 0.0 { 1.0 } else { (-s * t).exp() };
        let x = e * (a * cs + b * sn);
        let v = e * (-s * (a * cs + b * sn) + wd * (-a * sn + b * cs));
        return (x, v);
    }
    // Overdamped: x = A e^{r1 t} + B e^{r2 t}
    let q = w0 * (zeta * zeta - 1.0).sqrt();
    let (r1, r2) = (-s + q, -s - q);
    let b = (v0 - r1 * x0) / (r2 - r1);
    let a = x0 - b;
    let (e1, e2) = ((r1 * t).exp(), (r2 * t).exp());
    (a * e1 + b * e2, a * r1 * e1 + b * r2 * e2)
}

/// Builds scene `name` with parameter `overrides`, integrated by `method` at step `dt`.
///
/// # Errors
/// [`Error::UnknownName`](crate::Error::UnknownName) for an unknown scene, parameter or method;
/// [`Error::InvalidValue`](crate::Error::InvalidValue) for a bad parameter value or `dt`.
pub fn build(name: &str, overrides: &[(&str, f64)], method: &str, dt: f64) -> Result<Scene> {
    let spec = spec(name)?;
    let values = resolve(spec, overrides)?;
    let v = |n: &str| values[spec.params.iter().position(|p| p.name == n).expect("param in spec")];
    // A scene with a `dim` parameter (balls) takes its dimension from it (World::new refuses
    // one outside 1..=3).
    let dim = if spec.params.iter().any(|p| p.name == "dim") { v("dim") as usize } else { spec.dim };
    let params = WorldParams { dim, method: method.into(), dt, ..WorldParams::default() };
    let (world, exact) = match spec.build {
        Build::Flow(flow) => {
            let (flow, start) = flow(&v);
            (World::with_flow(flow, &start, params)?, None)
        }
        Build::Parts(parts) => {
            let mut world = World::new(params)?;
            let exact = parts(&v, &mut world)?;
            (world, exact)
        }
    };
    Ok(Scene { spec, values, world, exact })
}

/// How a scene is built from its parameter values (`v` reads one by name): the builder its
/// line of [`SCENES`] names.
#[derive(Clone, Copy)]
enum Build {
    /// A first-order flow and its start `(x, y, z)`.
    Flow(fn(v: &Param<'_>) -> (Flow, [f64; 3])),
    /// Particles, forces, bodies, balls or constraints added to a new world of the scene's
    /// dimension, and the exact solution where one is known.
    Parts(fn(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>>),
}

/// A scene's parameter value by name.
type Param<'a> = dyn Fn(&str) -> f64 + 'a;

/// The same builder: the same function (its address; `std::ptr::fn_addr_eq` is past the
/// MSRV).
impl PartialEq for Build {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Self::Flow(a), Self::Flow(b)) => *a as usize == *b as usize,
            (Self::Parts(a), Self::Parts(b)) => *a as usize == *b as usize,
            _ => false,
        }
    }
}

impl std::fmt::Debug for Build {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Flow(_) => "Build::Flow",
            Self::Parts(_) => "Build::Parts",
        })
    }
}

/// SplitMix64: a tiny seeded generator so scenes are the same on every machine.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}
