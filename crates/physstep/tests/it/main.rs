//! The engine's integration tests: each module is one concern (the names say what they hold);
//! `common` has the helpers they share. They are compiled into the library's own test harness
//! (`src/lib.rs` includes this file; `physstep::` names the crate there), with the unit tests
//! and the runs of the examples (`examples`), so `cargo test` builds the engine once. The test
//! that requests a stop (`interrupt`) runs in a process of its own: the request is
//! process-wide, and a test stepping a world at that moment would be interrupted with it.

mod bodies;
mod breaking_scenes;
mod ccd;
mod collisions;
mod common;
mod constraints;
mod contact;
mod contact_scenes;
mod contact_stage;
mod convergence;
mod determinism;
mod energy;
mod entity_state;
mod examples;
mod flows;
mod golden_tables;
mod handles;
mod implicit_solves;
mod integrators;
mod interrupt;
mod joints;
mod kepler_solution;
mod kernels;
mod parts;
mod refused_inputs;
mod registry;
mod removal;
mod restore_and_rollback;
mod scene_files;
mod scene_fuzz;
mod scenes;
mod sleeping;
mod solid_forces;
mod solid_handles;
mod spring_at_zero_length;
mod stiff;
mod stored_derivative;
mod user_forces;
mod vector_paths;
mod world;
mod xpbd_solver;
