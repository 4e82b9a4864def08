// A force of your own in a Rust world: wind that pushes harder on faster-moving air.
//
// `cargo run -p physstep --example custom_force`

use physstep::forces::ForceGenerator;
use physstep::prelude::*;
use std::sync::Arc;

/// Drag towards a wind velocity: `F = -c (v - wind)`, on every particle.
struct Wind {
    c: f64,
    wind: [f64; 2],
}

impl ForceGenerator for Wind {
    fn name(&self) -> &str {
        "wind"
    }

    fn add_forces(&self, _t: f64, _x: &[f64], v: &[f64], f: &mut [f64]) -> Result<(), String> {
        for (k, (fk, vk)) in f.iter_mut().zip(v).enumerate() {
            *fk -= self.c * (vk - self.wind[k % 2]);
        }
        Ok(())
    }

    // Linear in v: the implicit methods can use the exact Jacobian dF/dv = -c I.
    fn jacobian(&self, _t: f64, x: &[f64], _v: &[f64], _dfdx: &mut [f64], dfdv: &mut [f64]) -> bool {
        let n = x.len();
        for i in 0..n {
            dfdv[i * n + i] -= self.c;
        }
        true
    }
}

fn main() -> physstep::Result<()> {
    let mut w =
        World::new(WorldParams { dim: 2, method: "rk4".into(), dt: 1.0 / 120.0, ..Default::default() })?;
    w.add_particle(&[0.0, 10.0], &[0.0, 0.0], 1.0, false)?;
    w.add_force(Force::Gravity { g: [0.0, -9.81, 0.0] })?;
    w.add_force_generator(Arc::new(Wind { c: 0.5, wind: [3.0, 0.0] }))?;
    w.step(120)?;
    let (x, v) = (w.positions(), w.velocities());
    println!("after 1 s: x = ({:.4}, {:.4}) m, v = ({:.4}, {:.4}) m/s", x[0], x[1], v[0], v[1]);
    // The horizontal motion has a closed form: vx = 3 (1 - exp(-c t / m)).
    let exact = 3.0 * (1.0 - (-0.5f64).exp());
    assert!((v[0] - exact).abs() < 1e-9, "vx = {} vs {exact}", v[0]);
    // Without a potential for the wind the energy is unknown, not wrong.
    assert!(w.energy().is_none());
    println!("vx matches 3 (1 - e^-0.5) = {exact:.6} m/s; energy unknown (the wind has no potential)");
    Ok(())
}
