//! The racket (a free body with principal inertia 1 : 2 : 3 spun about its intermediate
//! axis) for 144,000 steps of 1/120 s under every method that applies, every orientation
//! rule and every angular form: the energy and |L| drift of each choice, as a Markdown table.
//!
//! `cargo run --release -p physstep --example racket_table` (docs/bodies.md holds its output).

use physstep::prelude::*;
use physstep::rigid::body::{AngularForm, FORMS};
use physstep::rigid::orientation::{Rule, RULES};

fn norm(v: [f64; 3]) -> f64 {
    v.iter().map(|c| c * c).sum::<f64>().sqrt()
}

/// Max relative energy error, relative |L| error at the end, flips of the intermediate axis,
/// ns per step.
fn run(method: &str, rule: Rule, form: AngularForm, steps: u64) -> Result<(f64, f64, usize, f64)> {
    let mut scene = scenes::build("racket", &[], method, 1.0 / 120.0)?;
    let w = &mut scene.world;
    w.set_orientation_rule(rule);
    w.set_angular_form(form);
    let (e0, l0) = (w.energy().unwrap_or(f64::NAN), norm(w.angular_momentum()));
    let (mut de, mut flips, mut last) = (0.0f64, 0, w.body_spin(0)?[1]);
    let start = std::time::Instant::now();
    let chunk = 100;
    for _ in 0..steps / chunk {
        w.step(chunk)?;
        de = de.max((w.energy().unwrap_or(f64::NAN) - e0).abs() / e0);
        let now = w.body_spin(0)?[1];
        if now * last < 0.0 {
            flips += 1;
        }
        last = now;
    }
    let ns = start.elapsed().as_secs_f64() * 1e9 / steps as f64;
    Ok((de, (norm(w.angular_momentum()) - l0).abs() / l0, flips, ns))
}

fn main() -> Result<()> {
    let steps = 144_000;
    println!("| method | orientation rule | angular form | max energy error | final \\|L\\| error | flips | ns/step |");
    println!("|---|---|---|---|---|---|---|");
    for info in INFOS.iter().filter(|i| !i.vector_positions) {
        // Flow methods integrate q' = (0, omega) q / 2 and renormalise: no rule applies.
        let rules: &[Rule] = if info.split { &RULES } else { &[Rule::Splitting] };
        for &rule in rules {
            for form in FORMS {
                let rule_name = if info.split { rule.name() } else { "(q' = w q / 2)" };
                match run(info.name, rule, form, steps) {
                    Ok((de, dl, flips, ns)) => println!(
                        "| {} | {rule_name} | {} | {de:.1e} | {dl:.1e} | {flips} | {ns:.0} |",
                        info.name,
                        form.name()
                    ),
                    Err(e) => {
                        println!("| {} | {rule_name} | {} | failed: {e} | | | |", info.name, form.name())
                    }
                }
            }
        }
    }
    Ok(())
}
