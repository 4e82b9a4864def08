//! The catalogue of built-in scenes: their names, parameters with their rules and defaults,
//! default step and run length, and the resolution of a user's parameter overrides.

use super::{balls, bodies, breaking, constrained, flows, jointed, particles, solids, stiff, Build};
use crate::error::{Error, Result};

pub use crate::limits::{PARAM_MAX, PARAM_MIN};

/// The most particles (or balls) a built-in scene may have: a count parameter is at most this,
/// and a grid of two (`cloth`'s w x h, `stiff-cloth`'s n x n) is refused past it before
/// anything is built (a million particles, their springs and a step's buffers fit in a few
/// hundred MB).
pub const MAX_PARTICLES: usize = 1_000_000;

/// What a parameter may be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// A number in [-1e12, 1e12].
    Any,
    /// A number in [1e-12, 1e12].
    Positive,
    /// 0, or a number in [1e-12, 1e12].
    NonNegative,
    /// A whole number >= 1.
    Count,
    /// A number in [0, 1).
    Fraction,
}

/// Where a scene loses energy by design (damping, drag, inelastic contacts): a run that
/// loses energy there reports the energy lost, not an error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Loss {
    /// The scene conserves energy (what a method loses or gains is its error).
    None,
    /// Always, for the reason given.
    Always(&'static str),
    /// When the parameter named is not 0 (damping, drag), for the reason given.
    Nonzero(&'static str, &'static str),
    /// When the parameter named is below 1 (restitution), for the reason given.
    BelowOne(&'static str, &'static str),
}

/// One named parameter of a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamSpec {
    /// Name, as given to `--param NAME=VALUE`.
    pub name: &'static str,
    /// Default value.
    pub default: f64,
    /// What it is, with units.
    pub doc: &'static str,
    /// What it may be.
    pub rule: Rule,
}

/// A scene in the registry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneSpec {
    /// Registry name.
    pub name: &'static str,
    /// One line on what it is.
    pub doc: &'static str,
    /// Spatial dimensions.
    pub dim: usize,
    /// Its parameters.
    pub params: &'static [ParamSpec],
    /// The method that runs the scene well at its `dt` (the default of the command line,
    /// `simulate` and `World.from_scene`): RK4 for the flows (the split methods do not apply
    /// to them), backward Euler for the stiff scenes (explicit methods diverge at their dt),
    /// symplectic Euler (the notes' default) elsewhere.
    pub method: &'static str,
    /// Where it loses energy by design.
    pub loss: Loss,
    /// A step that shows the scene well, s (the command line's default).
    pub dt: f64,
    /// A run length that shows the scene well, s (the command line's default).
    pub until: f64,
    /// How it is built: the one place a scene's name meets its builder.
    pub(super) build: Build,
}

const fn p(name: &'static str, default: f64, doc: &'static str, rule: Rule) -> ParamSpec {
    ParamSpec { name, default, doc, rule }
}

/// Every built-in scene, in registry order: the scenes' one table (name, parameters, defaults
/// and builder, whose file gives the exact solution where one is known).
pub const SCENES: &[SceneSpec] = &[
    SceneSpec {
        name: "spring",
        doc: "1D mass on a spring to the origin, F = -k x - c v (the notes' m = 10, k = 5, x0 = 20)",
        dim: 1,
        params: &[
            p("m", 10.0, "mass, kg", Rule::Positive),
            p("k", 5.0, "stiffness, N/m", Rule::NonNegative),
            p("c", 0.0, "damping, N s/m", Rule::NonNegative),
            p("x0", 20.0, "initial position, m", Rule::Any),
            p("v0", 0.0, "initial velocity, m/s", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Nonzero("c", "damping"),
        dt: 0.1,
        until: 20.0,
        build: Build::Parts(particles::spring),
    },
    SceneSpec {
        name: "projectile",
        doc: "2D throw under uniform gravity (the notes' fetch); exact x0 + v0 t + g t^2/2",
        dim: 2,
        params: &[
            p("g", 9.81, "gravity, m/s^2 (pointing down)", Rule::Any),
            p("vx", 10.0, "initial horizontal velocity, m/s", Rule::Any),
            p("vy", 10.0, "initial vertical velocity, m/s", Rule::Any),
            p("x0", 0.0, "initial x, m", Rule::Any),
            p("y0", 0.0, "initial y, m", Rule::Any),
            p("m", 1.0, "mass, kg", Rule::Positive),
        ],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 0.01,
        until: 2.0,
        build: Build::Parts(particles::projectile),
    },
    SceneSpec {
        name: "drag",
        doc: "1D particle slowed by linear drag F = -c v; exact v = v0 exp(-c t / m)",
        dim: 1,
        params: &[
            p("m", 1.0, "mass, kg", Rule::Positive),
            p("c", 0.5, "drag coefficient, N s/m", Rule::NonNegative),
            p("x0", 0.0, "initial position, m", Rule::Any),
            p("v0", 10.0, "initial velocity, m/s", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Nonzero("c", "drag"),
        dt: 0.01,
        until: 5.0,
        build: Build::Parts(particles::drag),
    },
    SceneSpec {
        name: "orbit",
        doc: "2D circular orbit around a fixed centre, GM = 1, r = 1, period 2 pi",
        dim: 2,
        params: &[
            p("gm", 1.0, "gravitational parameter GM, m^3/s^2", Rule::Positive),
            p("r", 1.0, "orbit radius, m", Rule::Positive),
        ],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 0.01,
        until: 2.0 * std::f64::consts::TAU,
        build: Build::Parts(particles::orbit),
    },
    SceneSpec {
        name: "kepler",
        doc: "2D Kepler ellipse, GM = 1, a = 1, from the pericentre (1 - e, 0); period 2 pi",
        dim: 2,
        params: &[p("e", 0.6, "eccentricity, in [0, 1)", Rule::Fraction)],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 0.01,
        until: std::f64::consts::TAU,
        build: Build::Parts(particles::kepler),
    },
    SceneSpec {
        name: "pendulum",
        doc: "2D particle on a rigid rod to a fixed point (the notes' dog tied to a tree); exact when g = 0",
        dim: 2,
        params: &[
            p("length", 1.0, "rod length, m", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2", Rule::Any),
            p("theta0", 0.5, "initial angle from straight down, rad", Rule::Any),
            p("omega0", 0.0, "initial angular velocity, rad/s", Rule::Any),
            p("m", 1.0, "mass, kg", Rule::Positive),
            p(
                "rod",
                1.0,
                "the rod: a distance constraint (SHAKE/RATTLE under velocity-verlet), 0 for the notes' rod force",
                Rule::NonNegative,
            ),
        ],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 0.01,
        until: 5.0,
        build: Build::Parts(particles::pendulum),
    },
    SceneSpec {
        name: "nbody",
        doc: "2D softened n-body gravity, G = 1, N bodies of total mass 1 in a unit disc (seeded)",
        dim: 2,
        params: &[
            p("n", 16.0, "number of bodies", Rule::Count),
            p("seed", 1.0, "random seed", Rule::NonNegative),
            p("softening", 0.05, "softening length, m", Rule::NonNegative),
        ],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 0.001,
        until: 1.0,
        build: Build::Parts(particles::nbody),
    },
    SceneSpec {
        name: "chain",
        doc: "2D chain of particles joined by springs, hanging from a fixed point under gravity",
        dim: 2,
        params: &[
            p("n", 10.0, "number of moving particles", Rule::Count),
            p("k", 500.0, "spring stiffness, N/m", Rule::NonNegative),
            p("c", 0.0, "spring damping, N s/m", Rule::NonNegative),
            p("spacing", 0.1, "rest length of each link, m", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2", Rule::Any),
            p("m", 0.1, "mass of each particle, kg", Rule::Positive),
        ],
        method: "symplectic-euler",
        loss: Loss::Nonzero("c", "spring damping"),
        dt: 0.001,
        until: 2.0,
        build: Build::Parts(particles::chain),
    },
    SceneSpec {
        name: "lorenz",
        doc:
            "Lorenz attractor, a first-order flow x' = sigma (y - x), y' = x (rho - z) - y, z' = x y - beta z",
        dim: 3,
        params: &[
            p("sigma", 10.0, "Prandtl number", Rule::Any),
            p("rho", 28.0, "Rayleigh number", Rule::Any),
            p("beta", 8.0 / 3.0, "geometry factor", Rule::Any),
            p("x0", 1.0, "initial x", Rule::Any),
            p("y0", 1.0, "initial y", Rule::Any),
            p("z0", 1.0, "initial z", Rule::Any),
        ],
        method: "rk4",
        loss: Loss::None,
        dt: 0.005,
        until: 40.0,
        build: Build::Flow(flows::lorenz),
    },
    SceneSpec {
        name: "rossler",
        doc: "Rossler attractor, a first-order flow x' = -y - z, y' = x + a y, z' = b + z (x - c)",
        dim: 3,
        params: &[
            p("a", 0.2, "", Rule::Any),
            p("b", 0.2, "", Rule::Any),
            p("c", 5.7, "", Rule::Any),
            p("x0", 1.0, "initial x", Rule::Any),
            p("y0", 1.0, "initial y", Rule::Any),
            p("z0", 0.0, "initial z", Rule::Any),
        ],
        method: "rk4",
        loss: Loss::None,
        dt: 0.01,
        until: 200.0,
        build: Build::Flow(flows::rossler),
    },
    SceneSpec {
        name: "thomas",
        doc: "Thomas' cyclically symmetric attractor, x' = sin y - b x (and cyclic)",
        dim: 3,
        params: &[
            p("b", 0.208_186, "dissipation", Rule::Any),
            p("x0", 0.1, "initial x", Rule::Any),
            p("y0", 0.0, "initial y", Rule::Any),
            p("z0", 0.0, "initial z", Rule::Any),
        ],
        method: "rk4",
        loss: Loss::None,
        dt: 0.05,
        until: 500.0,
        build: Build::Flow(flows::thomas),
    },
    SceneSpec {
        name: "stiff-chain",
        doc: "2D chain 1 m long of n particles joined by stiff springs to a pinned one, swinging down",
        dim: 2,
        params: &[
            p("n", 100.0, "number of moving particles (after the pinned one)", Rule::Count),
            p("k", 1e5, "spring stiffness, N/m", Rule::Positive),
            p("m", 0.01, "mass of each particle, kg", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2", Rule::Any),
        ],
        method: "backward-euler",
        loss: Loss::None,
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(stiff::chain),
    },
    SceneSpec {
        name: "stiff-cloth",
        doc: "3D n x n cloth 1 m square of stiff structural and shear springs, two corners pinned, falling",
        dim: 3,
        params: &[
            p("n", 12.0, "particles along each side (n x n at most 1000000)", Rule::Count),
            p("k", 1e5, "spring stiffness, N/m", Rule::Positive),
            p("m", 0.01, "mass of each particle, kg", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2", Rule::Any),
        ],
        method: "backward-euler",
        loss: Loss::None,
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(stiff::cloth),
    },
    SceneSpec {
        name: "racket",
        doc: "free thin plate, principal inertia 1 : 2 : 3, spun about its intermediate axis: the tennis-racket flip",
        dim: 3,
        params: &[
            p("spin", 2.0, "angular velocity about the intermediate axis, rad/s", Rule::Any),
            p("wobble", 0.01, "angular velocity about the other two axes, rad/s", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 1.0 / 120.0,
        until: 1200.0,
        build: Build::Parts(bodies::racket),
    },
    SceneSpec {
        name: "top",
        doc: "slow top: a cylinder pinned at its tip under gravity, tilted 0.3 rad and spun below the 132 rad/s it needs to stay up, nodding from 17 to 85 degrees as it precesses (spin=1000: a fast top)",
        dim: 3,
        params: &[
            p("radius", 0.1, "cylinder radius, m", Rule::Positive),
            p("height", 0.4, "cylinder height, m", Rule::Positive),
            p("m", 1.0, "mass, kg", Rule::Positive),
            p("tilt", 0.3, "initial tilt from vertical, rad", Rule::Any),
            p("spin", 100.0, "spin about its axis, rad/s", Rule::Any),
            p("g", 9.81, "gravity, m/s^2", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 1.0 / 1200.0,
        until: 5.0,
        build: Build::Parts(bodies::top),
    },
    SceneSpec {
        name: "tumble",
        doc: "a 0.8 x 0.4 x 0.2 m box of 2 kg pushed up at a corner, tumbling as it flies under gravity",
        dim: 3,
        params: &[
            p("impulse", 6.0, "upward impulse at the corner, N s", Rule::Any),
            p("g", 9.81, "gravity, m/s^2", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::None,
        dt: 1.0 / 120.0,
        until: 1.0,
        build: Build::Parts(bodies::tumble),
    },
    SceneSpec {
        name: "cloth",
        doc: "3D cloth: a W x H grid of particles joined by distance constraints (structural and shear), top corners pinned, under gravity",
        dim: 3,
        params: &[
            p("w", 12.0, "particles across", Rule::Count),
            p("h", 12.0, "particles down", Rule::Count),
            p("spacing", 0.1, "rest length of a structural link, m", Rule::Positive),
            p("m", 0.01, "mass of each particle, kg", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
            p("wind", 0.0, "wind, a uniform acceleration along +z, m/s^2", Rule::Any),
            p("drag", 0.0, "linear air drag on each particle, N s/m", Rule::NonNegative),
            p("compliance", 0.0, "compliance of every link, m/N (0: rigid)", Rule::NonNegative),
        ],
        method: "symplectic-euler",
        loss: Loss::Nonzero("drag", "air drag"),
        dt: 1.0 / 120.0,
        until: 5.0,
        build: Build::Parts(constrained::cloth),
    },
    SceneSpec {
        name: "ragdoll",
        doc: "2D stick-figure ragdoll: 11 particles, rigid bones, joint limits as min/max distances, falling onto the ground y = 0",
        dim: 2,
        params: &[
            p("height", 1.0, "height of the lowest point above the ground at the start, m", Rule::NonNegative),
            p("tilt", 0.4, "initial tilt from upright, rad", Rule::Any),
            p("spin", 1.0, "initial angular velocity, rad/s", Rule::Any),
            p("m", 1.0, "mass of each particle, kg", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("inelastic ground contact and joint limits"),
        dt: 1.0 / 120.0,
        until: 3.0,
        build: Build::Parts(constrained::ragdoll),
    },
    SceneSpec {
        name: "balls",
        doc: "N balls in a box (seeded, no overlap, random velocities), colliding elastically at their time of impact",
        dim: 2,
        params: &[
            p("n", 100.0, "number of balls", Rule::Count),
            p("radius", 0.05, "ball radius, m", Rule::Positive),
            p("dim", 2.0, "spatial dimensions, 1 to 3", Rule::Count),
            p("seed", 1.0, "random seed", Rule::NonNegative),
            p("restitution", 1.0, "coefficient of restitution, 0 to 1 (1: elastic)", Rule::NonNegative),
            p("fraction", 0.1, "fraction of the box's length, area or volume the balls fill", Rule::Fraction),
            p("speed", 1.0, "each velocity component uniform in [-speed, speed], m/s", Rule::Positive),
        ],
        method: "symplectic-euler",
        loss: Loss::BelowOne("restitution", "inelastic collisions"),
        dt: 1.0 / 120.0,
        until: 10.0,
        build: Build::Parts(balls::scene),
    },
    SceneSpec {
        name: "pile",
        doc: "N balls dropped under gravity into a box, where they come to rest (resting contacts below restitution 1)",
        dim: 2,
        params: &[
            p("n", 1000.0, "number of balls", Rule::Count),
            p("restitution", 0.5, "coefficient of restitution, 0 to 1 (1: elastic)", Rule::NonNegative),
            p("radius", 0.05, "ball radius, m", Rule::Positive),
            p("seed", 1.0, "random seed", Rule::NonNegative),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::BelowOne("restitution", "inelastic collisions"),
        dt: 1.0 / 120.0,
        until: 10.0,
        build: Build::Parts(balls::pile),
    },
    SceneSpec {
        name: "bridge",
        doc: "n planks 1 m long hinged end to end between two fixed points span n apart, sagging into a catenary (joints)",
        dim: 2,
        params: &[
            p("n", 40.0, "number of planks", Rule::Count),
            p("span", 0.75, "distance between the fixed ends over the planks' length (0 to 1)", Rule::Fraction),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the joints' softness"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(jointed::bridge),
    },
    SceneSpec {
        name: "ball-chain",
        doc: "a chain of n hinged capsules with a heavy ball on its end, falling from level and swinging (joints)",
        dim: 2,
        params: &[
            p("n", 30.0, "number of links, 1 m each", Rule::Count),
            p("radius", 2.0, "radius of the ball, m", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the joints' softness and the ground"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(jointed::ball_chain),
    },
    SceneSpec {
        name: "ragdoll-bodies",
        doc: "a ragdoll of 12 solids joined by hinges with angle limits and joint friction, pushed over: it falls and rests",
        dim: 2,
        params: &[
            p("height", 0.0, "height of its feet above the ground, m", Rule::NonNegative),
            p("push", 1.0, "horizontal speed given to the torso, m/s", Rule::Any),
            p("spin", 1.0, "angular velocity given to the torso, rad/s", Rule::Any),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the landing, friction and joint friction"),
        dt: 1.0 / 60.0,
        until: 5.0,
        build: Build::Parts(jointed::ragdoll_bodies),
    },
    SceneSpec {
        name: "single-box",
        doc: "a unit box dropped onto the ground, where it comes to rest (solids: the contact solver)",
        dim: 2,
        params: &[
            p("height", 1.0, "drop height of the box's bottom, m", Rule::NonNegative),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the landing and friction"),
        dt: 1.0 / 60.0,
        until: 3.0,
        build: Build::Parts(solids::single_box),
    },
    SceneSpec {
        name: "stack",
        doc: "n unit boxes stacked on the ground, standing",
        dim: 2,
        params: &[
            p("n", 10.0, "number of boxes", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::stack),
    },
    SceneSpec {
        name: "pyramid",
        doc: "a pyramid of unit boxes, rows (rows + 1) / 2 of them, standing on the ground",
        dim: 2,
        params: &[
            p("rows", 20.0, "rows of boxes", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::pyramid),
    },
    SceneSpec {
        name: "ramp",
        doc: "a box on a plank tilted by angle: it sticks where friction > tan(angle), else slides at g (sin a - mu cos a)",
        dim: 2,
        params: &[
            p("angle", 0.5, "tilt of the plank, rad", Rule::Any),
            p("friction", 0.6, "friction coefficient of box and plank", Rule::NonNegative),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("friction"),
        dt: 1.0 / 60.0,
        until: 5.0,
        build: Build::Parts(solids::ramp),
    },
    SceneSpec {
        name: "dice",
        doc: "n dice (20 cm cubes) thrown spinning onto a plane, where they come to rest (3D)",
        dim: 3,
        params: &[
            p("n", 16.0, "number of dice", Rule::Count),
            p("seed", 1.0, "random seed", Rule::NonNegative),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("bounces and friction"),
        dt: 1.0 / 60.0,
        until: 5.0,
        build: Build::Parts(solids::dice),
    },
    SceneSpec {
        name: "box-stack",
        doc: "n unit cubes stacked on a plane, standing (3D)",
        dim: 3,
        params: &[
            p("n", 10.0, "number of cubes", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::stack),
    },
    // The rest of Solver2D's contact scenes (scenes/solids.rs), and the top on the floor.
    SceneSpec {
        name: "card-house",
        doc: "Box2D's card house: rows of 40 cm cards leaning in pairs, flat cards across them, standing",
        dim: 2,
        params: &[
            p("levels", 5.0, "rows of card pairs (at most 100)", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::card_house),
    },
    SceneSpec {
        name: "mass-ratio",
        doc: "a 20 m box resting on two unit boxes, ratio times as heavy as each, standing",
        dim: 2,
        params: &[
            p("ratio", 100.0, "mass of the big box over a small one's, 0.001 to 10000", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::mass_ratio),
    },
    SceneSpec {
        name: "arch",
        doc: "Solver2D's arch of 17 convex stones with 4 boxes on its keystone, standing by friction",
        dim: 2,
        params: &[
            p("friction", 0.6, "friction coefficient of the stones, boxes and ground", Rule::NonNegative),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::arch),
    },
    SceneSpec {
        name: "domino",
        doc: "n dominos 1 m apart, the first pushed at its top: each knocks over the next",
        dim: 2,
        params: &[
            p("n", 15.0, "number of dominos", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("impacts and friction"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::domino),
    },
    SceneSpec {
        name: "confined",
        doc: "n x n circles started overlapping in a closed box, no gravity: they push apart and jam",
        dim: 2,
        params: &[p("n", 25.0, "circles a row and a column (at most 30)", Rule::Count)],
        method: "symplectic-euler",
        loss: Loss::Always("contacts pushing apart"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::confined),
    },
    SceneSpec {
        name: "overlap-recovery",
        doc: "a pyramid of unit boxes started overlapping: pushed apart at most at the push speed, they rest",
        dim: 2,
        params: &[
            p("base", 4.0, "boxes in the bottom row", Rule::Count),
            p("overlap", 0.25, "overlap of neighbours, a fraction of a side, 0 to 0.5", Rule::Fraction),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts pushing apart"),
        dt: 1.0 / 60.0,
        until: 5.0,
        build: Build::Parts(solids::overlap_recovery),
    },
    SceneSpec {
        name: "top-on-floor",
        doc: "a spinning top (a convex hull) on its flat foot on a plane, spun until friction stops it (3D)",
        dim: 3,
        params: &[
            p("spin", 60.0, "spin about its axis, rad/s", Rule::Any),
            p("foot", 0.02, "half side of its square foot, m, 0 (a tip) to 0.05", Rule::NonNegative),
            p("tilt", 0.0, "tilt of its axis from the vertical, rad, 0 to 1.2", Rule::NonNegative),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("friction"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(solids::top_on_floor),
    },
    // Solver2D's scenes that break contact and joint solvers (scenes/breaking.rs).
    SceneSpec {
        name: "far-pyramid",
        doc: "the pyramid of unit boxes (rows 10) built offset m (30 km) from the origin: does precision hold far out?",
        dim: 2,
        params: &[
            p("rows", 10.0, "rows of boxes", Rule::Count),
            p("offset", 30000.0, "distance of the scene from the origin along x and along -y, m (at most 1e9)", Rule::Any),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::far_pyramid),
    },
    SceneSpec {
        name: "far-ragdoll-pile",
        doc: "six ragdolls of 12 solids piling into a V of two boards, offset m (30 km) from the origin",
        dim: 2,
        params: &[
            p("offset", 30000.0, "distance of the scene from the origin along x and along -y, m (at most 1e9)", Rule::Any),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the landing, friction and joint friction"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::far_ragdoll_pile),
    },
    SceneSpec {
        name: "high-mass-ratio",
        doc: "Solver2D's high mass ratio 1 (three pyramids topped by a box 100-300x as dense), 2 or 3 (a 20 m box dropped on two unit boxes, thin or thick ground)",
        dim: 2,
        params: &[
            p("variant", 1.0, "Solver2D's sample: 1, 2 or 3", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("impacts and contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::high_mass_ratio),
    },
    SceneSpec {
        name: "friction-ramp",
        doc: "five boxes of friction 0.75 to 0 dropped on zigzag boards tilted 0.25 rad: those above tan 0.25 (mixed) slow down, the rest speed up",
        dim: 2,
        params: &[
            p("ramp_friction", 0.2, "friction coefficient of the boards and the ground", Rule::NonNegative),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("impacts and friction"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::friction_ramp),
    },
    SceneSpec {
        name: "warm-start-energy",
        doc: "three balls stacked, the top one ratio (100) times as dense: remove it (solid 3) and the light ones must not jump",
        dim: 2,
        params: &[
            p("ratio", 100.0, "density of the top ball over the others', 0.001 to 10000", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts settling"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::warm_start_energy),
    },
    SceneSpec {
        name: "rush",
        doc: "n (400) circles on a spiral pulled by springs to a static circle at the origin, no gravity: they crowd in and jam",
        dim: 2,
        params: &[
            p("n", 400.0, "number of circles (at most 10000)", Rule::Count),
            p("k", 100.0, "stiffness of each circle's spring to the origin, N/m", Rule::NonNegative),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("contacts and friction"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::rush),
    },
    SceneSpec {
        name: "double-domino",
        doc: "the domino row (n 15) pushed at both ends: two waves fall inward and meet in the middle",
        dim: 2,
        params: &[
            p("n", 15.0, "number of dominos", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("impacts and friction"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::double_domino),
    },
    SceneSpec {
        name: "joint-grid",
        doc: "an n x n (30 x 30) grid of circles hinged to their neighbours, hanging from 7 pinned in the top row's middle",
        dim: 2,
        params: &[
            p("n", 30.0, "circles a row and a column (at most 300)", Rule::Count),
            p("g", 19.62, "gravity, m/s^2 (along -y; Solver2D's gravity scale 2)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the joints' softness"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::joint_grid),
    },
    SceneSpec {
        name: "stretched-chain",
        doc: "n (40) hinged circles hanging from a point, started with every joint 1 m open (twice its length); the last ratio times as dense",
        dim: 2,
        params: &[
            p("n", 40.0, "number of circles (at most 10000)", Rule::Count),
            p("ratio", 1.0, "density of the last circle over the others', 0.001 to 10000", Rule::Positive),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the joints' softness"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::stretched_chain),
    },
    SceneSpec {
        name: "far-chain",
        doc: "n (40) hinged capsules 20 cm long falling from level and swinging, offset m (30 km) from the origin",
        dim: 2,
        params: &[
            p("n", 40.0, "number of links", Rule::Count),
            p("offset", 30000.0, "distance of the scene from the origin along x and along -y, m (at most 1e9)", Rule::Any),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("the joints' softness"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::far_chain),
    },
    SceneSpec {
        name: "ragdoll-stress",
        doc: "n (32) ragdolls of 12 solids falling through a container of shelves and three motor-driven paddles",
        dim: 2,
        params: &[
            p("n", 32.0, "number of ragdolls (at most 32)", Rule::Count),
            p("g", 9.81, "gravity, m/s^2 (along -y)", Rule::Any),
        ],
        method: "symplectic-euler",
        loss: Loss::Always("impacts, friction and joint friction"),
        dt: 1.0 / 60.0,
        until: 10.0,
        build: Build::Parts(breaking::ragdoll_stress),
    },
];

/// The spec of a scene by name.
///
/// # Errors
/// [`Error::UnknownName`] listing the valid scenes.
pub fn spec(name: &str) -> Result<&'static SceneSpec> {
    SCENES
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| Error::unknown("scene", name, SCENES.iter().map(|s| s.name)))
}

/// Resolves `overrides` against a scene's defaults, validating each.
///
/// # Errors
/// [`Error::UnknownName`] for a parameter the scene does not have (listing those it has);
/// [`Error::InvalidValue`] for a value that breaks its rule.
pub fn resolve(spec: &SceneSpec, overrides: &[(&str, f64)]) -> Result<Vec<f64>> {
    let mut values: Vec<f64> = spec.params.iter().map(|p| p.default).collect();
    for (name, value) in overrides {
        let i = spec
            .params
            .iter()
            .position(|p| p.name == *name)
            .ok_or_else(|| Error::unknown("param", name, spec.params.iter().map(|p| p.name)))?;
        let rule = spec.params[i].rule;
        let size = (PARAM_MIN..=PARAM_MAX).contains(value);
        let ok = match rule {
            Rule::Any => value.abs() <= PARAM_MAX,
            Rule::Positive => size,
            Rule::NonNegative => *value == 0.0 || size,
            Rule::Count => *value >= 1.0 && value.fract() == 0.0 && *value <= 1e6,
            Rule::Fraction => (0.0..1.0).contains(value),
        };
        if !ok {
            let expected = match rule {
                Rule::Any => "a number in [-1e12, 1e12]",
                Rule::Positive => "a number in [1e-12, 1e12]",
                Rule::NonNegative => "0 or a number in [1e-12, 1e12]",
                Rule::Count => "a whole number from 1 to 1000000",
                Rule::Fraction => "in [0, 1)",
            };
            return Err(Error::invalid(*name, crate::error::num(*value), expected));
        }
        values[i] = *value;
    }
    Ok(values)
}
