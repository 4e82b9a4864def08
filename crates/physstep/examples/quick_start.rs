use physstep::prelude::*;

fn main() {
    // The notes' spring: m = 10, k = 5, x0 = 20, symplectic Euler at dt = 1.
    let mut scene = scenes::build("spring", &[], "symplectic-euler", 1.0).unwrap();
    scene.world.step(1).unwrap();
    assert_eq!(scene.world.positions(), &[10.0]);
    assert_eq!(scene.world.velocities(), &[-10.0]);
}
