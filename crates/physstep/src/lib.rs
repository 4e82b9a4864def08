//! physstep: a game-physics integration engine.
//!
//! Every integrator of the game-physics lecture notes (explicit Euler, symplectic Euler in
//! both orders, Stormer Verlet, velocity Verlet, leapfrog, midpoint, Heun, RK4, backward
//! Euler, predictor-corrector) and more, behind one interface ([`integrators::Method`],
//! chosen by name through [`integrators::registry`]); particles with composable forces in a
//! [`world::World`]; the fixed-timestep game loop ([`clock::Clock`]); built-in
//! [`scenes`] with energies and exact solutions.
//!
//! ```
#![doc = include_str!("../examples/quick_start.rs")]
//! ```
//!
//! # What is public
//!
//! | module | for a Rust user |
//! |---|---|
//! | [`world`] | [`world::World`] (particles, bodies, balls, constraints, the step and the game loop) and its parameters |
//! | [`integrators`] | the methods, one type each, their [`integrators::Info`], and [`integrators::Integrator`] (a method by name; [`integrators::registry`] lists them) |
//! | [`dynamics`] | the systems methods step: [`dynamics::SecondOrder`], [`dynamics::FirstOrder`], and [`dynamics::System`] / [`dynamics::Step`] for a method or a part of your own |
//! | [`forces`], [`flows`] | the built-in forces and flows, and the traits of your own ([`forces::ForceGenerator`], [`flows::FlowGenerator`]) |
//! | [`rigid`] | shapes and their mass properties, orientation rules, the bodies' angular forms |
//! | [`constraints`], [`collide`] | position constraints; the balls' contact statistics and walls |
//! | [`contact`] | solids: shapes, kinds, the contact solver and its settings ([`contact::Solids`] on its own, or [`world::World::add_solid`]) |
//! | [`clock`] | the fixed-timestep loop on its own |
//! | [`record`] | a run recorded row by row |
//! | [`scenes`] | the built-in scenes and scene files |
//! | [`linalg`] | the sparse Newton solve's blocks and conjugate gradients (what [`dynamics::System::blocks`] fills) |
//! | [`error`], [`limits`] | the one error type, and the bounds every input is held to |
//! | [`simd`] | the AVX2 switch (also [`world::set_vector_paths`]) |
//! | [`alloc`] | an allocator that maps large blocks as huge pages (the Python extension's) |
//!
//! The rest is `pub(crate)`: how a step is taken inside (the rollback, the fused kernels, the
//! contact stage's grid and events) may change without notice.
#![warn(missing_docs)]

pub mod alloc;
pub mod clock;
pub mod collide;
pub mod constraints;
pub mod contact;
pub mod dynamics;
pub mod error;
pub mod flows;
pub mod forces;
pub(crate) mod ids;
pub mod integrators;
pub mod interrupt;
pub mod limits;
pub mod linalg;
pub mod record;
pub mod rigid;
pub mod scenes;
pub mod simd;
pub mod world;

pub use error::{Error, Result};

// Every test of the engine is in one harness, the library's own: its unit tests, the tests of
// `tests/it` (their `physstep::` paths name this crate) and the runs of the examples. So
// `cargo test` compiles the engine once, not a second time as the library a test binary links
// (cold, on this project's 2-core VM: 57 s where the library, its harness and an integration-test
// binary took 82).
#[cfg(test)]
extern crate self as physstep;
#[cfg(test)]
#[path = "../tests/it/main.rs"]
mod it;

/// The names most programs need.
pub mod prelude {
    pub use crate::clock::{Clock, ClockParams, LoopMode};
    pub use crate::dynamics::{FirstOrder, SecondOrder};
    pub use crate::error::{Error, Result};
    pub use crate::forces::{Endpoint, Force};
    pub use crate::integrators::registry::State;
    pub use crate::integrators::{Info, Integrator, INFOS};
    pub use crate::scenes::{self, Scene};
    pub use crate::world::{World, WorldParams};
}
