//! The examples run as tests (clippy checks them as the example programs they are, `cargo run
//! --example NAME` runs them on their own): the crate's quick start (`src/lib.rs` shows it) and
//! a force of one's own (the README's Rust section).

mod quick_start {
    include!("../../examples/quick_start.rs");

    #[test]
    fn the_quick_start_steps_the_notes_spring() {
        main();
    }
}

mod custom_force {
    include!("../../examples/custom_force.rs");

    #[test]
    fn a_wind_of_ones_own_gives_the_closed_form_velocity() {
        main().unwrap();
    }
}
