//! Unit tests of the forces: accelerations, potentials and Jacobians against finite
//! differences, canonical order, validation.
use super::*;

/// A test world: positions, velocities, masses.
pub(super) struct W {
    pub dim: usize,
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    pub m: Vec<f64>,
}

impl W {
    pub fn inv(&self) -> Vec<f64> {
        self.m.iter().map(|m| 1.0 / m).collect()
    }
    pub fn accel_at(&self, fs: &ForceSet, x: &[f64], v: &[f64]) -> Vec<f64> {
        let mut f = vec![0.0; x.len()];
        let mut a = vec![f64::NAN; x.len()];
        fs.accel(self.dim, 0.0, x, v, &self.m, &self.inv(), &mut f, &mut a);
        a
    }
    pub fn accel(&self, fs: &ForceSet) -> Vec<f64> {
        self.accel_at(fs, &self.x, &self.v)
    }
}

fn set(forces: &[Force], n: usize, dim: usize) -> ForceSet {
    let mut fs = ForceSet::new();
    for f in forces {
        fs.add(*f, n, dim).unwrap();
    }
    fs
}

fn close(a: f64, b: f64, rel: f64, scale: f64) -> bool {
    (a - b).abs() <= rel * scale.max(a.abs()).max(b.abs())
}

/// A pseudo-random world, deterministic.
pub(super) fn world(n: usize, dim: usize, seed: u64) -> W {
    let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    };
    let x = (0..n * dim).map(|_| 3.0 * next()).collect();
    let v = (0..n * dim).map(|_| next()).collect();
    let m = (0..n).map(|_| 1.5 + next()).collect();
    W { dim, x, v, m }
}

fn spring(i: usize, j: Endpoint, k: f64, rest: f64, c: f64) -> Force {
    Force::Spring { i, j, stiffness: k, rest_length: rest, damping: c }
}

#[test]
fn spring_to_anchor_1d() {
    let w = W { dim: 1, x: vec![20.0], v: vec![0.0], m: vec![10.0] };
    let fs = set(&[spring(0, Endpoint::Anchor([0.0; 3]), 5.0, 0.0, 0.0)], 1, 1);
    assert_eq!(w.accel(&fs), vec![-10.0]);

    let w = W { v: vec![3.0], ..w };
    let fs = set(&[spring(0, Endpoint::Anchor([0.0; 3]), 5.0, 0.0, 2.0)], 1, 1);
    let a = w.accel(&fs)[0];
    let want = (-100.0 - 6.0) / 10.0;
    assert!(close(a, want, 1e-15, 0.0), "{a} vs {want}");
    assert!(fs.velocity_dependent());
}

#[test]
fn spring_at_zero_length_is_zero() {
    let w = W { dim: 2, x: vec![1.0, 2.0, 1.0, 2.0], v: vec![1.0, 0.0, -1.0, 0.0], m: vec![1.0, 1.0] };
    let fs = set(&[spring(0, Endpoint::Particle(1), 5.0, 1.0, 2.0)], 2, 2);
    assert_eq!(w.accel(&fs), vec![0.0; 4]);
}

#[test]
fn order_independent_bitwise() {
    let w = world(5, 3, 7);
    let forces = [
        Force::Gravity { g: [0.0, -9.81, 0.0] },
        spring(0, Endpoint::Particle(3), 4.0, 0.5, 0.3),
        spring(2, Endpoint::Particle(1), 7.0, 0.2, 0.1),
        spring(4, Endpoint::Anchor([1.0, 2.0, 3.0]), 2.0, 0.0, 0.7),
        Force::Drag { linear: 0.1, quadratic: 0.05 },
        Force::CentralGravity { center: [0.5, 0.5, 0.5], gm: 3.0 },
        Force::NBody { g: 0.3, softening: 0.1 },
        Force::Rod { i: 3, j: Endpoint::Particle(2), length: 1.0 },
        Force::Gravity { g: [0.1, 0.0, 0.2] },
    ];
    let swapped: Vec<Force> = forces
        .iter()
        .rev()
        .map(|f| match *f {
            Force::Spring { i, j: Endpoint::Particle(j), stiffness, rest_length, damping } => {
                Force::Spring { i: j, j: Endpoint::Particle(i), stiffness, rest_length, damping }
            }
            Force::Rod { i, j: Endpoint::Particle(j), length } => {
                Force::Rod { i: j, j: Endpoint::Particle(i), length }
            }
            f => f,
        })
        .collect();
    let a1 = w.accel(&set(&forces, 5, 3));
    let a2 = w.accel(&set(&swapped, 5, 3));
    let b1: Vec<u64> = a1.iter().map(|a| a.to_bits()).collect();
    let b2: Vec<u64> = a2.iter().map(|a| a.to_bits()).collect();
    assert_eq!(b1, b2);
    assert_eq!(set(&forces, 5, 3), set(&swapped, 5, 3));
}

#[test]
fn springs_between_particles_in_any_order_and_after_a_removal_give_the_same_bits() {
    // The springs between particles are summed from their own list, kept in canonical order
    // on every add (wherever the new spring falls) and gathered again on a removal: a set
    // built in a scrambled order, or holding one more spring that is then removed, steps as
    // the set built in order, in 1, 2 and 3 dimensions.
    for dim in 1..=3 {
        let w = world(9, dim, 11 + dim as u64);
        let mut springs: Vec<Force> = (0..9)
            .flat_map(|i| [(i + 1) % 9, (i + 4) % 9].map(move |j| (i, j)))
            .enumerate()
            .map(|(e, (i, j))| spring(i, Endpoint::Particle(j), 1.0 + e as f64, 0.1 * (e % 3) as f64, 0.05))
            .collect();
        springs.push(spring(2, Endpoint::Anchor([0.5, -0.5, 0.25]), 3.0, 0.2, 0.1));
        let bits = |fs: &ForceSet| -> Vec<u64> { w.accel(fs).iter().map(|a| a.to_bits()).collect() };
        let ordered = set(&springs, 9, dim);
        let scrambled: Vec<Force> = (0..springs.len()).map(|k| springs[(k * 7) % springs.len()]).collect();
        assert_eq!(bits(&set(&scrambled, 9, dim)), bits(&ordered), "dim {dim}");
        let mut more = set(&scrambled, 9, dim);
        let extra = more.add(spring(3, Endpoint::Particle(0), 9.0, 0.3, 0.2), 9, dim).unwrap();
        assert_ne!(bits(&more), bits(&ordered));
        more.remove(extra);
        assert_eq!(bits(&more), bits(&ordered), "dim {dim}");
    }
}

/// `-grad U` by central differences against `m a`.
fn check_potential(w: &W, fs: &ForceSet) {
    let a = w.accel(fs);
    let scale = a.iter().zip(0..).map(|(a, q)| (a * w.m[q / w.dim]).abs()).fold(0.0, f64::max);
    assert!(scale > 0.0);
    for q in 0..w.x.len() {
        let h = 1e-5;
        let mut xp = w.x.clone();
        xp[q] += h;
        let mut xm = w.x.clone();
        xm[q] -= h;
        let grad = (fs.potential(w.dim, &xp, &w.m) - fs.potential(w.dim, &xm, &w.m)) / (2.0 * h);
        let force = w.m[q / w.dim] * a[q];
        assert!(close(-grad, force, 1e-6, scale), "coordinate {q}: {} vs {force}", -grad);
    }
}

#[test]
fn potential_gradient_matches_force() {
    for dim in [2, 3] {
        let w = W { v: vec![0.0; 4 * dim], ..world(4, dim, 11 + dim as u64) };
        let anchor = Endpoint::Anchor([0.3, -0.2, 0.1]);
        let cases = [
            vec![spring(0, Endpoint::Particle(1), 3.0, 0.7, 0.0), spring(2, anchor, 1.5, 0.4, 0.0)],
            vec![Force::CentralGravity { center: [4.0, 0.1, -4.0], gm: 5.0 }],
            vec![Force::NBody { g: 0.7, softening: 0.2 }],
            vec![Force::Gravity { g: [0.3, -9.81, 1.0] }],
        ];
        for forces in &cases {
            check_potential(&w, &set(forces, 4, dim));
        }
        let all: Vec<Force> = cases.concat();
        check_potential(&w, &set(&all, 4, dim));
    }
}

#[test]
fn potential_values() {
    let w = W { dim: 1, x: vec![3.0, 1.0], v: vec![0.0; 2], m: vec![2.0, f64::INFINITY] };
    let fs = set(&[Force::Gravity { g: [-10.0, 0.0, 0.0] }], 2, 1);
    assert_eq!(fs.potential(1, &w.x, &w.m), 60.0);
    assert_eq!(w.accel(&fs), vec![-10.0, 0.0]);
    let fs = set(
        &[spring(0, Endpoint::Particle(1), 4.0, 1.0, 0.0), Force::Drag { linear: 1.0, quadratic: 0.0 }],
        2,
        1,
    );
    assert_eq!(fs.potential(1, &w.x, &w.m), 2.0);
}

#[test]
fn jacobian_matches_finite_differences() {
    for dim in [2, 3] {
        let n = 4;
        let w = world(n, dim, 3 + dim as u64);
        let forces = [
            spring(0, Endpoint::Particle(1), 3.0, 0.7, 0.4),
            spring(3, Endpoint::Particle(1), 2.0, 0.0, 0.9),
            spring(2, Endpoint::Anchor([0.3, -0.2, 0.1]), 1.5, 0.4, 0.6),
            Force::Drag { linear: 0.3, quadratic: 0.2 },
            Force::CentralGravity { center: [4.0, 0.1, -4.0], gm: 5.0 },
            Force::Gravity { g: [0.0, -9.81, 0.0] },
        ];
        let fs = set(&forces, n, dim);
        let len = n * dim;
        let mut dadx = vec![0.0; len * len];
        let mut dadv = vec![0.0; len * len];
        assert!(fs.jacobian(dim, 0.0, &w.x, &w.v, &w.inv(), &mut dadx, &mut dadv));
        for (jac, wrt_x) in [(&dadx, true), (&dadv, false)] {
            let scale = jac.iter().fold(0.0f64, |m, j| m.max(j.abs()));
            for q in 0..len {
                let h = 1e-6;
                let (mut xp, mut xm, mut vp, mut vm) = (w.x.clone(), w.x.clone(), w.v.clone(), w.v.clone());
                if wrt_x {
                    xp[q] += h;
                    xm[q] -= h;
                } else {
                    vp[q] += h;
                    vm[q] -= h;
                }
                let ap = w.accel_at(&fs, &xp, &vp);
                let am = w.accel_at(&fs, &xm, &vm);
                for r in 0..len {
                    let fd = (ap[r] - am[r]) / (2.0 * h);
                    let an = jac[r * len + q];
                    assert!(close(fd, an, 1e-6, scale), "dim {dim} x {wrt_x} [{r},{q}]: {fd} vs {an}");
                }
            }
        }
    }
}

#[test]
fn jacobian_refused_for_nbody_and_rod() {
    let w = world(2, 2, 1);
    let mut dadx = vec![0.0; 16];
    let mut dadv = vec![0.0; 16];
    for f in
        [Force::NBody { g: 1.0, softening: 0.0 }, Force::Rod { i: 0, j: Endpoint::Particle(1), length: 1.0 }]
    {
        let fs = set(&[f, Force::Drag { linear: 1.0, quadratic: 0.0 }], 2, 2);
        assert!(!fs.jacobian(2, 0.0, &w.x, &w.v, &w.inv(), &mut dadx, &mut dadv));
        assert!(dadv.iter().all(|&d| d == 0.0));
    }
}

#[test]
fn rod_gives_centripetal_acceleration() {
    let (l, s) = (2.5, 3.7);
    for (dim, theta) in [(2, 0.3), (3, 1.9), (2, -2.2)] {
        let (c, sn) = (f64::cos(theta), f64::sin(theta));
        let anchor = [1.0, -2.0, 0.5];
        let mut x = vec![anchor[0] + l * c, anchor[1] + l * sn];
        let mut v = vec![-s * sn, s * c];
        if dim == 3 {
            x.push(anchor[2]);
            v.push(0.0);
        }
        let w = W { dim, x, v, m: vec![2.0] };
        let fs = set(
            &[
                Force::Gravity { g: [0.0, -9.81, 0.0] },
                Force::Rod { i: 0, j: Endpoint::Anchor(anchor), length: l },
            ],
            1,
            dim,
        );
        let a = w.accel(&fs);
        let radial = (a[0] * c + a[1] * sn) / 1.0;
        let want = -s * s / l;
        assert!(close(radial, want, 1e-12, 0.0), "{radial} vs {want}");
    }
}

#[test]
fn rod_between_particles_keeps_length() {
    let w = world(2, 3, 5);
    let fs = set(
        &[
            Force::Gravity { g: [0.0, 0.0, -9.81] },
            Force::Rod { i: 1, j: Endpoint::Particle(0), length: 1.0 },
        ],
        2,
        3,
    );
    let a = w.accel(&fs);
    // d^2 |d|^2 / dt^2 / 2 = w.w + d.a_rel = 0
    let (mut ww, mut da, mut dd) = (0.0, 0.0, 0.0);
    for k in 0..3 {
        let d = w.x[k] - w.x[3 + k];
        ww += (w.v[k] - w.v[3 + k]).powi(2);
        da += d * (a[k] - a[3 + k]);
        dd += d * d;
    }
    assert!(close(ww + da, 0.0, 1e-12, ww + dd));
    // momentum: the rod is internal
    let p: f64 = (0..3).map(|k| w.m[0] * a[k] + w.m[1] * a[3 + k]).sum();
    assert!((p - (w.m[0] + w.m[1]) * -9.81).abs() < 1e-12 * 10.0 * (w.m[0] + w.m[1]));
}

#[test]
fn static_particles_stay_put() {
    let mut w = world(3, 2, 9);
    w.m[1] = f64::INFINITY;
    let fs = set(
        &[
            Force::Gravity { g: [0.0, -9.81, 0.0] },
            spring(0, Endpoint::Particle(1), 3.0, 0.5, 0.5),
            Force::Drag { linear: 0.3, quadratic: 0.2 },
            Force::CentralGravity { center: [0.0; 3], gm: 1.0 },
            Force::Rod { i: 1, j: Endpoint::Particle(2), length: 1.0 },
        ],
        3,
        2,
    );
    let a = w.accel(&fs);
    assert_eq!(&a[2..4], &[0.0, 0.0]);
    assert!(a.iter().all(|a| a.is_finite()));
}

#[test]
fn validation_names_field_and_value() {
    let mut fs = ForceSet::new();
    fn msg<T: std::fmt::Debug>(r: Result<T>) -> String {
        r.unwrap_err().to_string()
    }
    let a0 = Endpoint::Anchor([0.0; 3]);
    assert_eq!(
        msg(fs.add(spring(1, Endpoint::Particle(7), 1.0, 0.0, 0.0), 3, 2)),
        "invalid j = 7: must be a particle index < 3 other than i"
    );
    assert_eq!(
        msg(fs.add(spring(1, Endpoint::Particle(1), 1.0, 0.0, 0.0), 3, 2)),
        "invalid j = 1: must be a particle index < 3 other than i"
    );
    assert_eq!(
        msg(fs.add(spring(3, a0, 1.0, 0.0, 0.0), 3, 2)),
        "invalid i = 3: must be a particle index < 3"
    );
    assert_eq!(
        msg(fs.add(spring(0, a0, -1.0, 0.0, 0.0), 3, 2)),
        "invalid stiffness = -1: must be a finite number >= 0"
    );
    assert!(msg(fs.add(spring(0, a0, 1.0, f64::NAN, 0.0), 3, 2)).starts_with("invalid rest_length = NaN"));
    assert!(msg(fs.add(spring(0, a0, 1.0, 0.0, f64::INFINITY), 3, 2)).starts_with("invalid damping = inf"));
    assert!(msg(fs.add(spring(0, Endpoint::Anchor([0.0, f64::NAN, 0.0]), 1.0, 0.0, 0.0), 3, 2))
        .starts_with("invalid anchor = [0.0, NaN, 0.0]"));
    // beyond dim: ignored
    fs.add(spring(0, Endpoint::Anchor([0.0, f64::NAN, 0.0]), 1.0, 0.0, 0.0), 3, 1).unwrap();
    assert_eq!(fs.iter().next(), Some(&spring(0, a0, 1.0, 0.0, 0.0)));
    assert!(
        msg(fs.add(Force::Drag { linear: -0.1, quadratic: 0.0 }, 3, 2)).starts_with("invalid linear = -0.1")
    );
    assert!(
        msg(fs.add(Force::Drag { linear: 0.0, quadratic: -2.0 }, 3, 2)).starts_with("invalid quadratic = -2")
    );
    assert!(msg(fs.add(Force::CentralGravity { center: [0.0; 3], gm: f64::NAN }, 3, 2))
        .starts_with("invalid gm = NaN"));
    assert!(msg(fs.add(Force::CentralGravity { center: [f64::INFINITY, 0.0, 0.0], gm: 1.0 }, 3, 2))
        .starts_with("invalid center = [inf"));
    assert!(
        msg(fs.add(Force::Gravity { g: [0.0, f64::NAN, 0.0] }, 3, 3)).starts_with("invalid g = [0.0, NaN")
    );
    assert!(msg(fs.add(Force::NBody { g: f64::NAN, softening: 0.0 }, 3, 2)).starts_with("invalid g = NaN"));
    assert!(msg(fs.add(Force::NBody { g: 1.0, softening: -1.0 }, 3, 2)).starts_with("invalid softening = -1"));
    assert_eq!(
        msg(fs.add(Force::Rod { i: 0, j: a0, length: 0.0 }, 3, 2)),
        "invalid length = 0: must be a finite number > 0"
    );
    assert!(msg(fs.add(Force::Rod { i: 0, j: Endpoint::Particle(0), length: 1.0 }, 3, 2))
        .starts_with("invalid j = 0"));
    assert!(msg(fs.add(Force::Gravity { g: [0.0; 3] }, 3, 4)).starts_with("invalid dim = 4"));
    assert_eq!(fs.len(), 1);

    fs.add(Force::NBody { g: 1.0, softening: 0.1 }, 3, 2).unwrap();
    assert_eq!(
        msg(fs.validate_masses(&[1.0, 2.0, f64::INFINITY])),
        "invalid mass[2] = inf: must be finite when n-body gravity is on"
    );
    fs.validate_masses(&[1.0, 2.0, 3.0]).unwrap();
    let no_nbody = set(&[Force::Gravity { g: [0.0; 3] }], 3, 2);
    no_nbody.validate_masses(&[1.0, f64::INFINITY, 3.0]).unwrap();
}

#[test]
fn basics() {
    let mut fs = ForceSet::default();
    assert!(fs.is_empty());
    assert!(!fs.velocity_dependent());
    fs.add(Force::Gravity { g: [0.0, -1.0, 0.0] }, 1, 2).unwrap();
    fs.add(spring(0, Endpoint::Anchor([0.0; 3]), 1.0, 0.0, 0.0), 1, 2).unwrap();
    assert!(!fs.velocity_dependent());
    fs.add(Force::Drag { linear: 0.0, quadratic: 1.0 }, 1, 2).unwrap();
    assert!(fs.velocity_dependent());
    assert_eq!(fs.len(), 3);
    assert!(matches!(fs.iter().nth(1), Some(Force::Spring { .. })));
}

#[test]
fn springs_to_anchors_in_any_order_give_the_same_set() {
    // Anchored springs are placed as they come (not rebuilt per addition): the order they
    // were added in must not show, several on one particle included.
    let w = world(4, 2, 11);
    let forces = [
        spring(1, Endpoint::Anchor([1.0, 0.0, 0.0]), 2.0, 0.5, 0.1),
        spring(1, Endpoint::Anchor([0.0, 1.0, 0.0]), 3.0, 0.0, 0.2),
        spring(0, Endpoint::Anchor([0.5, 0.5, 0.0]), 1.0, 0.3, 0.0),
        Force::Gravity { g: [0.0, -9.81, 0.0] },
        spring(3, Endpoint::Anchor([2.0, 2.0, 0.0]), 5.0, 0.0, 0.0),
        spring(1, Endpoint::Anchor([1.0, 0.0, 0.0]), 2.0, 0.25, 0.1),
        Force::Drag { linear: 0.2, quadratic: 0.0 },
    ];
    let reversed: Vec<Force> = forces.iter().rev().copied().collect();
    let (s1, s2) = (set(&forces, 4, 2), set(&reversed, 4, 2));
    assert_eq!(s1, s2);
    let bits = |a: Vec<f64>| a.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(w.accel(&s1)), bits(w.accel(&s2)));
}
