//! Stable ids, one counter per kind of thing in a world (particles, bodies, constraints, body
//! springs and forces; solids, joints, solid springs and forces on solids), shaped like
//! [`crate::forces::ForceId`]: a number given when the thing is added and never given again by
//! that world, so it stays the thing's while others of its kind come and go.
//!
//! Storage stays dense arrays in add order; a removal deletes the row and keeps the order of
//! the rest (never a swap). So the ids are kept beside the rows in increasing order, an id's
//! row is a binary search, and the array order after removals is the add order with the
//! removed rows taken out. Until something of a kind is removed its ids are `0..n`, the rows'
//! own indices: such ids are left out of snapshots and state hashes, so a world where nothing
//! was ever removed snapshots and hashes as it did before ids.

use crate::error::{Error, Result};

/// A public id type: a `u64` newtype with `Display`.
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
pub(crate) use id_type;

/// The ids of one kind's rows, increasing, and the id the next one gets.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Ids {
    ids: Vec<u64>,
    next: u64,
}

impl Ids {
    /// Gives `k` new rows ids; returns the first.
    pub(crate) fn push(&mut self, k: usize) -> u64 {
        let first = self.next;
        self.ids.extend(first..first + k as u64);
        self.next += k as u64;
        first
    }

    /// The row of `id`, if it is one of these.
    pub(crate) fn row(&self, id: u64) -> Option<usize> {
        self.ids.binary_search(&id).ok()
    }

    /// The id of `row`.
    pub(crate) fn id(&self, row: usize) -> Option<u64> {
        self.ids.get(row).copied()
    }

    /// Deletes `row`, keeping the order of the others.
    pub(crate) fn remove(&mut self, row: usize) {
        self.ids.remove(row);
    }

    /// Deletes the rows where `gone` is true, keeping the order of the rest.
    pub(crate) fn retain_rows(&mut self, gone: &[bool]) {
        retain_by(&mut self.ids, gone);
    }

    /// [`Ids::retain_rows`], returning the ids of the rows deleted (in row order).
    pub(crate) fn take_rows(&mut self, gone: &[bool]) -> Vec<u64> {
        let taken = self.ids.iter().zip(gone).filter(|(_, &g)| g).map(|(&id, _)| id).collect();
        self.retain_rows(gone);
        taken
    }

    /// Whether the ids are `0..len` (nothing was ever removed).
    pub(crate) fn dense(&self) -> bool {
        self.next == self.ids.len() as u64
    }

    /// The ids, row by row.
    pub(crate) fn all(&self) -> &[u64] {
        &self.ids
    }

    /// The id the next row gets.
    pub(crate) fn next(&self) -> u64 {
        self.next
    }

    /// Replaces the ids (a copy or pickle of a world), checked: one per row (`per` names the
    /// row's kind), increasing, each below `next`; `field` names them in an error.
    pub(crate) fn set(&mut self, field: &str, per: &str, ids: &[u64], next: u64) -> Result<()> {
        if ids.len() != self.ids.len() {
            return Err(Error::invalid(
                format!("len({field})"),
                ids.len(),
                format!("{}, one per {per}", self.ids.len()),
            ));
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

    /// The ids then the counter, as words (for a fingerprint).
    pub(crate) fn words(&self) -> impl Iterator<Item = u64> + '_ {
        self.ids.iter().copied().chain([self.next])
    }

    /// Appends the counter and the ids (a snapshot's and a state hash's, when not dense).
    pub(crate) fn write(&self, out: &mut Vec<f64>) {
        out.push(self.next as f64);
        out.extend(self.ids.iter().map(|i| *i as f64));
    }
}

/// The rows where `gone` is true taken out of `v`, the order of the rest kept.
pub(crate) fn retain_by<T>(v: &mut Vec<T>, gone: &[bool]) {
    let mut k = 0;
    v.retain(|_| {
        k += 1;
        !gone[k - 1]
    });
}

/// Index `i` after row `removed` was taken out (`i != removed`).
pub(crate) fn shift(i: usize, removed: usize) -> usize {
    if i > removed {
        i - 1
    } else {
        i
    }
}
