//! The Collide stage's own guarantees, beyond the contacts' physics (`collisions.rs`): the
//! overlap measure covers every step's end whatever the calls, the hit balls' accelerations
//! evaluated alone are the whole evaluation's, and a ball sped up past what the grid's cells
//! were sized for still meets every ball it can reach.

use super::common::{close, max_pair_overlap, world};
use physstep::prelude::*;

/// `w`'s positions set to `x` through the phase vector, which is not checked for balls
/// (`set_positions` refuses an overlap deeper than the state has, as `add_ball` does).
fn force_positions(w: &mut World, x: &[f64]) {
    let mut z = w.phase();
    z[..x.len()].copy_from_slice(x);
    w.set_phase(&z).unwrap();
}

/// An overlap left in the state (set here by hand: two balls 0.01 m into each other, and one
/// 0.02 m past a wall, all moving apart so that no contact happens) is measured by the next
/// step's scan of the grid, whether the steps come one per call or many in one call (the
/// end of a call's last step is measured by the stage itself).
#[test]
fn an_overlap_left_in_the_state_is_measured() {
    for per_call in [1, 4] {
        let mut w = world(2, "symplectic-euler", 0.01);
        w.add_walls(&[0.0, 0.0], &[2.0, 2.0]).unwrap();
        w.add_ball(&[0.5, 1.0], &[-1.0, 0.0], 0.1, 1.0).unwrap();
        w.add_ball(&[0.8, 1.0], &[1.0, 0.0], 0.1, 1.0).unwrap();
        w.add_ball(&[1.5, 0.5], &[0.0, 1.0], 0.1, 1.0).unwrap();
        // (set_positions refuses this now: issue 25, item 10)
        assert!(w.set_positions(&[0.5, 1.0, 0.69, 1.0, 1.5, 0.08]).is_err());
        force_positions(&mut w, &[0.5, 1.0, 0.69, 1.0, 1.5, 0.08]);
        assert_eq!(w.collisions().max_overlap, 0.0);
        for _ in 0..8 / per_call {
            w.step(per_call).unwrap();
        }
        assert_eq!(w.collisions().count, 0, "per call {per_call}");
        let deepest = w.collisions().max_overlap;
        assert!((deepest - 0.02).abs() < 1e-15, "per call {per_call}: {deepest}");
        // The wall's overlap gone, the pair's alone left: 0.01.
        let mut w2 = world(2, "symplectic-euler", 0.01);
        w2.add_walls(&[0.0, 0.0], &[2.0, 2.0]).unwrap();
        w2.add_ball(&[0.5, 1.0], &[-1.0, 0.0], 0.1, 1.0).unwrap();
        w2.add_ball(&[0.8, 1.0], &[1.0, 0.0], 0.1, 1.0).unwrap();
        force_positions(&mut w2, &[0.5, 1.0, 0.69, 1.0]);
        for _ in 0..8 / per_call {
            w2.step(per_call).unwrap();
        }
        let deepest = w2.collisions().max_overlap;
        assert!((deepest - 0.01).abs() < 1e-15, "per call {per_call}: {deepest}");
    }
}

/// After the contacts of a step only the hit balls' accelerations are evaluated again when
/// every force is per particle (gravity, drag, a spring to an anchor): they are the whole
/// evaluation's, bit for bit, and the steps after go on as from a whole evaluation.
#[test]
fn the_hit_balls_accelerations_are_the_whole_evaluations() {
    let build = || {
        let mut w = world(2, "symplectic-euler", 1.0 / 120.0);
        w.add_walls(&[0.0, 0.0], &[2.0, 2.0]).unwrap();
        for i in 0..40 {
            let (x, y) = (0.1 + 0.2 * (i % 9) as f64, 0.1 + 0.2 * (i / 9) as f64);
            w.add_ball(
                &[x, y],
                &[(i as f64 * 0.7).sin(), (i as f64 * 1.3).cos()],
                0.08,
                1.0 + 0.1 * i as f64,
            )
            .unwrap();
        }
        w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] }).unwrap();
        w.add_force(Force::Drag { linear: 0.1, quadratic: 0.05 }).unwrap();
        w.add_force(Force::Spring {
            i: 3,
            j: Endpoint::Anchor([1.0, 1.5, 0.0]),
            stiffness: 20.0,
            rest_length: 0.3,
            damping: 0.2,
        })
        .unwrap();
        w
    };
    let (mut a, mut b) = (build(), build());
    for _ in 0..120 {
        a.step(1).unwrap();
        b.step(1).unwrap();
        let partial = a.accelerations().unwrap().to_vec();
        // Touching the state makes the next read evaluate every particle.
        let v = b.velocities().to_vec();
        b.set_velocities(&v).unwrap();
        let whole = b.accelerations().unwrap().to_vec();
        assert!(partial.iter().zip(&whole).all(|(p, q)| p.to_bits() == q.to_bits()));
        assert_eq!(a.positions(), b.positions());
    }
    assert!(a.collisions().count > 20, "{} contacts", a.collisions().count);
}

/// Heavy balls striking light ones send the light ones off far faster than any ball was going
/// at the step's start (paths up to the bound of 1.5 times the longest, past what the grid's
/// cells were sized for): those contacts are still all found. Balls of masses 1 and 40 on a
/// lattice in 2D and 3D (and in two clusters far apart in 2D: the hashed table), steps one per
/// call and ten per call: no pair overlaps after any step, no ball leaves the box, energy
/// kept.
#[test]
fn balls_sped_up_past_the_grids_cells_are_still_met() {
    // (dim, box side, lattice points per side over 3 m, steps per call)
    for (dim, side, per_side, per_call) in
        [(2, 3.0, 18_usize, 1), (2, 3.0, 18, 10), (3, 1.5, 9, 1), (2, 64.0, 18, 10)]
    {
        let mut w = world(dim, "symplectic-euler", 1.0 / 60.0);
        w.add_walls(&vec![0.0; dim], &vec![side; dim]).unwrap();
        let spacing = side.min(3.0) / per_side as f64;
        let count = per_side.pow(dim as u32);
        for i in 0..count {
            // In the 64 m box, every other ball in a second cluster 61 m away.
            let shift = if side > 3.0 && i % 2 == 1 { 61.0 } else { 0.0 };
            let at = |k: usize| (((i / per_side.pow(k as u32)) % per_side) as f64 + 0.5) * spacing;
            let x: Vec<f64> =
                (0..dim).map(|k| if side > 3.0 { at(k) / 2.0 + shift } else { at(k) }).collect();
            let heavy = i % 7 == 0;
            let v: Vec<f64> =
                (0..dim).map(|k| ((i * 3 + k * 5) as f64).sin() * if heavy { 3.0 } else { 0.5 }).collect();
            w.add_ball(&x, &v, 0.04, if heavy { 40.0 } else { 1.0 }).unwrap();
        }
        let k0 = w.kinetic();
        for _ in 0..240 / per_call {
            w.step(per_call as u64).unwrap();
            let deepest = max_pair_overlap(&w);
            assert!(deepest <= 1e-9, "dim {dim}, side {side}: overlap {deepest}");
            let x = w.positions();
            assert!(x.iter().all(|c| *c >= 0.04 - 1e-12 && *c <= side - 0.04 + 1e-12), "dim {dim}: outside");
        }
        let drift = (w.kinetic() - k0).abs() / k0;
        assert!(drift < 1e-12, "dim {dim}, side {side}: drift {drift}");
        assert!(w.collisions().count > 200, "dim {dim}, side {side}: {:?}", w.collisions());
        assert!(w.collisions().max_overlap <= 1e-9);
    }
}

/// The two ways a ball sped up within a step is met past the grid's cells, built by hand in
/// 1D (dt = 0.06 s, radius 0.05 m, the longest path 0.06 m: cells of 0.22 m from x = 0):
/// A (2 kg) strikes B (1 kg) at s = 0.05 and sends it off at 4/3 m/s, its reach now past the
/// cells'; C, two cells from B, then meets B within the step: coming at it from the start (B's
/// re-query must look two cells out), or set moving only later, by D (C's re-query must check
/// the sped-up balls).
#[test]
fn a_ball_sped_up_in_a_step_meets_one_two_cells_away() {
    for later in [false, true] {
        let mut w = world(1, "symplectic-euler", 0.06);
        w.add_ball(&[0.0], &[0.0], 0.05, 1.0).unwrap(); // Z: where the cells count from
        w.add_ball(&[0.1165], &[1.0], 0.05, 2.0).unwrap(); // A
        w.add_ball(&[0.2195], &[0.0], 0.05, 1.0).unwrap(); // B, in the first cell
        if later {
            w.add_ball(&[0.4402], &[0.0], 0.05, 1.0).unwrap(); // C, in the third cell
            w.add_ball(&[0.5442], &[-1.0], 0.05, 1.0).unwrap(); // D strikes C at s = 1/15
        } else {
            w.add_ball(&[0.4402], &[-1.0], 0.05, 1.0).unwrap(); // C
        }
        let (k0, p0) = (w.kinetic(), w.momentum());
        w.step(1).unwrap();
        let deepest = max_pair_overlap(&w);
        assert!(deepest <= 1e-12, "later {later}: B and C overlap by {deepest}");
        let want = if later { 3 } else { 2 };
        assert_eq!(w.collisions().count, want, "later {later}: {:?}", w.collisions());
        assert!((w.kinetic() - k0).abs() <= 1e-15 * k0);
        close(&w.momentum(), &p0, 1e-15);
    }
}
