//! Stable ids of the solids, joints, solid springs and user forces on solids, shaped like
//! [`crate::forces::ForceId`]: a number given when the thing is added, from a counter of its
//! kind that its world never gives again, so it stays the thing's while others of its kind
//! come and go.
//!
//! The things stay in dense arrays, in the order they were added; a removal deletes the row
//! and keeps the order of the rest (never a swap). So the ids are kept beside the rows in
//! increasing order, an id's row is a binary search, and the array order after removals is
//! the add order with the removed rows taken out. Until something of a kind is removed its
//! ids are `0..n`, the rows' own indices: such ids are implicit (not in a snapshot or a
//! state hash), so a world where nothing was ever removed snapshots and hashes as before ids.

use crate::error::{Error, Result};

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u64);

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, "{}", self.0)
            }
        }
    };
}

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

/// The ids of one kind's rows, increasing, and the id the next one gets.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Ids {
    pub(crate) ids: Vec<u64>,
    pub(crate) next: u64,
}

impl Ids {
    /// A new row's id.
    pub(crate) fn push(&mut self) -> u64 {
        let id = self.next;
        self.ids.push(id);
        self.next += 1;
        id
    }

    /// The row of `id`, if it is one of these.
    pub(crate) fn row(&self, id: u64) -> Option<usize> {
        self.ids.binary_search(&id).ok()
    }

    /// Whether the ids are the rows' indices (nothing was ever removed).
    pub(crate) fn implicit(&self) -> bool {
        self.next == self.ids.len() as u64
    }

    /// Deletes the rows where `gone` is true, keeping the order of the rest.
    pub(crate) fn retain_rows(&mut self, gone: &[bool]) {
        let mut k = 0;
        self.ids.retain(|_| {
            k += 1;
            !gone[k - 1]
        });
    }

    /// Replaces the ids (a copy or pickle of a world), checked: one per row, increasing, each
    /// below `next`.
    pub(crate) fn set(&mut self, field: &str, ids: &[u64], next: u64) -> Result<()> {
        if ids.len() != self.ids.len() {
            return Err(Error::invalid(format!("len({field})"), ids.len(), format!("{}", self.ids.len())));
        }
        if let Some(w) = ids.windows(2).find(|w| w[0] >= w[1]) {
            return Err(Error::invalid(field, w[1], "increasing ids (the rows' order is the add order)"));
        }
        if let Some(last) = ids.last().filter(|l| **l >= next) {
            return Err(Error::invalid(field, last, format!("ids below next = {next}")));
        }
        self.ids = ids.to_vec();
        self.next = next;
        Ok(())
    }

    /// Appends the ids and the counter (a snapshot's and a state hash's, when not implicit).
    pub(crate) fn write(&self, out: &mut Vec<f64>) {
        out.push(self.next as f64);
        out.extend(self.ids.iter().map(|i| *i as f64));
    }
}

/// The rows where `keep` is false taken out of `v`, the order of the rest kept.
pub(crate) fn retain_by<T>(v: &mut Vec<T>, gone: &[bool]) {
    let mut k = 0;
    v.retain(|_| {
        k += 1;
        !gone[k - 1]
    });
}

/// Solid index `i` after solid `removed` was taken out (`i != removed`).
pub(crate) fn shift(i: usize, removed: usize) -> usize {
    if i > removed {
        i - 1
    } else {
        i
    }
}
