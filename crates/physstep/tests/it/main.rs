//! The engine's integration tests, one binary: each module is one concern (the names say what
//! they hold); `common` has the helpers they share. One crate links parry and the engine once,
//! where a binary a file linked them about thirty times. The one test that requests a stop
//! (`tests/interrupt.rs`) is a binary of its own: the request is process-wide, and a test
//! here stepping a world at that moment was interrupted with it (`determinism`, once).

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
mod flows;
mod golden_tables;
mod handles;
mod implicit_solves;
mod integrators;
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
mod user_forces;
mod vector_paths;
mod world;
mod xpbd_solver;
