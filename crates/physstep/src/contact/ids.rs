//! Stable ids of the solids, joints, solid springs and user forces on solids (what they are
//! and how they are kept: [`crate::ids`]).

use crate::ids::id_type;

id_type!(
    /// A solid's id in its world ([`crate::world::World::add_solid`]).
    SolidId
);
id_type!(
    /// A joint's id in its world ([`crate::world::World::add_joint`]).
    JointId
);
id_type!(
    /// A solid spring's id in its world ([`crate::world::World::add_solid_spring`]).
    SolidSpringId
);
id_type!(
    /// A user force on a solid: its id in its world ([`crate::world::World::add_solid_force`]).
    SolidForceId
);
