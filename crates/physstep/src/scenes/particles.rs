//! The particle scenes: a spring, a throw, drag, orbits, a pendulum, n bodies and a chain,
//! with their exact solutions where one is known (see [`super::Scene::exact`]).

use super::{Exact, Param, Result, SplitMix};
use crate::forces::{Endpoint, Force};
use crate::world::World;

/// The `spring` scene: a mass on a spring (and damper) to the origin; exact: the damped oscillator, or linear drag when `k = 0`.
pub(super) fn spring(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (m, k, c, x0, v0) = (v("m"), v("k"), v("c"), v("x0"), v("v0"));
    w.add_particle(&[x0], &[v0], m, false)?;
    w.add_force(Force::Spring {
        i: 0,
        j: Endpoint::Anchor([0.0; 3]),
        stiffness: k,
        rest_length: 0.0,
        damping: c,
    })?;
    let w0 = (k / m).sqrt();
    let zeta = if w0 > 0.0 { c / (2.0 * (k * m).sqrt()) } else { 0.0 };
    Ok(Some(if k == 0.0 && c > 0.0 {
        Exact::Drag { rate: c / m, x0, v0 }
    } else {
        Exact::Oscillator { w0, zeta, x0, v0 }
    }))
}

/// The `projectile` scene: a throw under uniform gravity; exact: the parabola.
pub(super) fn projectile(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (x0, v0, a) = ([v("x0"), v("y0")], [v("vx"), v("vy")], [0.0, -v("g")]);
    w.add_particle(&x0, &v0, v("m"), false)?;
    w.add_force(Force::Gravity { g: [a[0], a[1], 0.0] })?;
    Ok(Some(Exact::Ballistic { x0, v0, a }))
}

/// The `drag` scene: a particle slowed by linear drag; exact: the exponential decay.
pub(super) fn drag(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (m, c, x0, v0) = (v("m"), v("c"), v("x0"), v("v0"));
    w.add_particle(&[x0], &[v0], m, false)?;
    w.add_force(Force::Drag { linear: c, quadratic: 0.0 })?;
    Ok(Some(Exact::Drag { rate: c / m, x0, v0 }))
}

/// The `orbit` scene: a circular orbit about a fixed centre; exact: the circle.
pub(super) fn orbit(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (gm, r) = (v("gm"), v("r"));
    let speed = (gm / r).sqrt();
    w.add_particle(&[r, 0.0], &[0.0, speed], 1.0, false)?;
    w.add_force(Force::CentralGravity { center: [0.0; 3], gm })?;
    // x = r cos(wt), y = r sin(wt) = Circle with phase pi/2, sign -1 mapping.
    Ok(Some(Exact::Circle { r, w: speed / r, phase: std::f64::consts::FRAC_PI_2, sign: -1.0 }))
}

/// The `kepler` scene: a Kepler ellipse from its pericentre; exact: Kepler's equation solved.
pub(super) fn kepler(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let e = v("e");
    w.add_particle(&[1.0 - e, 0.0], &[0.0, ((1.0 + e) / (1.0 - e)).sqrt()], 1.0, false)?;
    w.add_force(Force::CentralGravity { center: [0.0; 3], gm: 1.0 })?;
    Ok(Some(Exact::Kepler { e }))
}

/// The `pendulum` scene: a particle on a rod (a distance constraint, or the notes' rod force) to a fixed point; exact without gravity: the circle.
pub(super) fn pendulum(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let (l, g, th, om) = (v("length"), v("g"), v("theta0"), v("omega0"));
    let (s, c) = th.sin_cos();
    w.add_particle(&[l * s, -l * c], &[l * om * c, l * om * s], v("m"), false)?;
    if v("rod") == 0.0 {
        w.add_force(Force::Rod { i: 0, j: Endpoint::Anchor([0.0; 3]), length: l })?;
    } else {
        w.add_distance_constraint(0, Endpoint::Anchor([0.0; 3]), Some(l), 0.0)?;
    }
    Ok(if g != 0.0 {
        w.add_force(Force::Gravity { g: [0.0, -g, 0.0] })?;
        None
    } else {
        Some(Exact::Circle { r: l, w: om, phase: th, sign: -1.0 })
    })
}

/// The `nbody` scene: softened gravity among `n` equal bodies in a unit disc (seeded).
pub(super) fn nbody(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = v("n") as usize;
    let mut rng = SplitMix(v("seed") as u64);
    let mut x = Vec::with_capacity(2 * n);
    let mut vel = Vec::with_capacity(2 * n);
    for _ in 0..n {
        // Uniform in the unit disc, on a slow rotation so the cluster does not just fall in.
        let (r, th) = (rng.unit().sqrt(), std::f64::consts::TAU * rng.unit());
        let (s, c) = th.sin_cos();
        x.extend([r * c, r * s]);
        let speed = 0.5 * r;
        vel.extend([-speed * s + 0.05 * (rng.unit() - 0.5), speed * c + 0.05 * (rng.unit() - 0.5)]);
    }
    // Zero total momentum (equal masses): subtract the mean velocity.
    for k in 0..2 {
        let mean = vel.iter().skip(k).step_by(2).sum::<f64>() / n as f64;
        vel.iter_mut().skip(k).step_by(2).for_each(|u| *u -= mean);
    }
    w.add_particles(&x, Some(&vel), Some(&vec![1.0 / n as f64; n]), false)?;
    w.add_force(Force::NBody { g: 1.0, softening: v("softening") })?;
    Ok(None)
}

/// The `chain` scene: particles joined by springs, hanging from a fixed point under gravity.
pub(super) fn chain(v: &Param<'_>, w: &mut World) -> Result<Option<Exact>> {
    let n = v("n") as usize;
    let (k, c, sp, g, m) = (v("k"), v("c"), v("spacing"), v("g"), v("m"));
    // Starts horizontal so it swings: particle i at ((i+1) spacing, 0).
    let x: Vec<f64> = (0..n).flat_map(|i| [(i + 1) as f64 * sp, 0.0]).collect();
    w.add_particles(&x, None, Some(&vec![m; n]), false)?;
    w.add_force(Force::Spring {
        i: 0,
        j: Endpoint::Anchor([0.0; 3]),
        stiffness: k,
        rest_length: sp,
        damping: c,
    })?;
    for i in 1..n {
        w.add_force(Force::Spring {
            i,
            j: Endpoint::Particle(i - 1),
            stiffness: k,
            rest_length: sp,
            damping: c,
        })?;
    }
    w.add_force(Force::Gravity { g: [0.0, -g, 0.0] })?;
    Ok(None)
}
