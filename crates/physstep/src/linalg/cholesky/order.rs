//! The order and the pattern of the complete Cholesky factor (its symbolic analysis): the
//! minimum-degree elimination of the springs' graph within the stages of its nested
//! dissection ([`super::dissect`]), which writes the factor's pattern as it goes, and the
//! split of its elimination tree into two subtrees factored at once and their common
//! ancestors. Both depend on the springs alone; the numeric factorisation
//! ([`super`]) reads them.

use super::{SparseCholesky, FILL_LIMIT, NONE, SPLIT_MIN};
use crate::linalg::Block;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

impl SparseCholesky {
    /// Whether the pattern kept is that of the springs `pairs` with the particles `free`
    /// moving.
    pub(in crate::linalg) fn same_pattern(&self, pairs: &[(usize, usize, Block)], free: &[bool]) -> bool {
        self.moving == free
            && self.key.len() == pairs.len()
            && pairs.iter().zip(&self.key).all(|(&(i, j, _), k)| *k == crate::linalg::ic::key(i, j, free))
    }

    /// Makes the order and pattern of the springs `pairs` on `n` particles (those whose ends
    /// both move), unless it is the one kept.
    pub(super) fn pattern(&mut self, n: usize, pairs: &[(usize, usize, Block)], free: &[bool]) {
        if self.same_pattern(pairs, free) {
            return;
        }
        self.moving.clear();
        self.moving.extend_from_slice(free);
        self.key.clear();
        self.key.extend(pairs.iter().map(|&(i, j, _)| crate::linalg::ic::key(i, j, free)));
        // The elimination graph: each moving particle's neighbours, ascending, no repeats.
        let mut adj: Vec<Vec<u32>> = vec![Vec::new(); n];
        for &(a, b) in self.key.iter().flatten() {
            adj[a].push(b as u32);
            adj[b].push(a as u32);
        }
        for list in &mut adj {
            list.sort_unstable();
            list.dedup();
        }
        // By stage of the nested dissection first (the halves before the separators that
        // join them), then by degree; ties go to the particle whose neighbours changed longest
        // ago (then the lowest index): on a 100 x 100 cloth a quarter fewer block products than
        // the lowest index first.
        let stage = super::dissect::stages(&adj, free);
        let mut heap: BinaryHeap<Reverse<(u32, usize, u64, u32)>> =
            (0..n).filter(|&p| free[p]).map(|p| Reverse((stage[p], adj[p].len(), 0, p as u32))).collect();
        let mut changed = vec![0u64; n];
        let mut clock = 0u64;
        let mut done = vec![false; n];
        let mut column = vec![NONE; n];
        self.perm.clear();
        let mut start = vec![0];
        // Rows as particles until the order is known.
        self.dest.clear();
        let budget = FILL_LIMIT.saturating_mul(heap.len());
        let mut merged = Vec::new();
        while let Some(Reverse((_, _, stamp, p))) = heap.pop() {
            let p = p as usize;
            if done[p] || changed[p] != stamp {
                continue;
            }
            done[p] = true;
            column[p] = self.perm.len() as u32;
            self.perm.push(p as u32);
            let nb = std::mem::take(&mut adj[p]);
            self.dest.extend_from_slice(&nb);
            start.push(self.dest.len());
            if self.dest.len() > budget {
                break;
            }
            // Each neighbour joins the others (and forgets p).
            for &u in &nb {
                let u = u as usize;
                merged.clear();
                let (a, b) = (&adj[u], &nb);
                let (mut i, mut k) = (0, 0);
                while i < a.len() || k < b.len() {
                    let next = match (a.get(i), b.get(k)) {
                        (Some(&x), Some(&y)) if x == y => {
                            i += 1;
                            k += 1;
                            x
                        }
                        (Some(&x), Some(&y)) if x < y => {
                            i += 1;
                            x
                        }
                        (Some(&x), None) => {
                            i += 1;
                            x
                        }
                        (_, Some(&y)) => {
                            k += 1;
                            y
                        }
                        (None, None) => break,
                    };
                    if next as usize != u && next as usize != p {
                        merged.push(next);
                    }
                }
                std::mem::swap(&mut adj[u], &mut merged);
                clock += 1;
                changed[u] = clock;
                heap.push(Reverse((stage[u], adj[u].len(), clock, u as u32)));
            }
        }
        self.fits = self.dest.len() <= budget;
        if !self.fits {
            return;
        }
        self.products = start.windows(2).map(|w| (w[1] - w[0]) * (w[1] - w[0] + 1) / 2 + 1).sum();
        // Rows as columns, ascending within each column.
        let mut row: Vec<u32> = self.dest.iter().map(|&p| column[p as usize]).collect();
        for j in 0..self.perm.len() {
            row[start[j]..start[j + 1]].sort_unstable();
        }
        self.split(&start, &row);
        self.supernodes(&start, &row);
        // The matrix's blocks by column (the lower of the two ends).
        let mut by_col: Vec<Vec<(u32, u32)>> = vec![Vec::new(); self.perm.len()];
        for (s, k) in self.key.iter().enumerate() {
            if let Some((a, b)) = *k {
                let (ca, cb) = (column[a], column[b]);
                by_col[ca.min(cb) as usize].push((ca.max(cb), s as u32));
            }
        }
        self.a_start.clear();
        self.a_entry.clear();
        self.a_start.push(0);
        for list in &by_col {
            self.a_entry.extend_from_slice(list);
            self.a_start.push(self.a_entry.len());
        }
    }

    /// Splits the columns (their patterns `row[start[j]..start[j + 1]]`) into two independent
    /// subtrees of the elimination tree of about equal work and the rest: from the roots down,
    /// the largest subtree is replaced by its children while it holds more than half of the
    /// work in reach; the subtrees left go, largest first, to the lighter part (ties to the
    /// lower index). Below [`SPLIT_MIN`] block products, one part.
    fn split(&mut self, start: &[usize], row: &[u32]) {
        let m = self.perm.len();
        for part in &mut self.parts {
            part.clear();
        }
        let mut part = vec![2u8; m];
        if self.products >= SPLIT_MIN {
            let own = |j: usize| (start[j + 1] - start[j]) * (start[j + 1] - start[j] + 1) / 2 + 1;
            let parent = |j: usize| if start[j] < start[j + 1] { row[start[j]] } else { NONE };
            let mut work: Vec<usize> = (0..m).map(own).collect();
            let mut children: Vec<Vec<u32>> = vec![Vec::new(); m];
            for j in 0..m {
                let p = parent(j);
                if p != NONE {
                    work[p as usize] += work[j];
                    children[p as usize].push(j as u32);
                }
            }
            let mut reach: BinaryHeap<(usize, Reverse<u32>)> =
                (0..m).filter(|&j| parent(j) == NONE).map(|j| (work[j], Reverse(j as u32))).collect();
            let mut total: usize = reach.iter().map(|e| e.0).sum();
            while let Some(&(big, Reverse(j))) = reach.peek() {
                if 2 * big <= total || children[j as usize].is_empty() {
                    break;
                }
                reach.pop();
                total -= big;
                for &c in &children[j as usize] {
                    total += work[c as usize];
                    reach.push((work[c as usize], Reverse(c)));
                }
            }
            let mut load = [0usize; 2];
            let mut root_part = vec![NONE; m];
            for (w, Reverse(j)) in reach.into_sorted_vec().into_iter().rev() {
                let q = usize::from(load[1] < load[0]);
                load[q] += w;
                root_part[j as usize] = q as u32;
            }
            for j in (0..m).rev() {
                let p = parent(j);
                part[j] = if root_part[j] != NONE {
                    root_part[j] as u8
                } else if p != NONE {
                    part[p as usize]
                } else {
                    2
                };
            }
        }
        for (j, &q) in part.iter().enumerate() {
            self.parts[q as usize].push(j as u32);
        }
    }

    /// Groups the columns of each part into supernodes: runs of consecutive columns each of
    /// whose pattern is the next column and that column's pattern (so that they share their
    /// rows below the run), stored part by part.
    /// (Relaxed supernodes, a column taken where its pattern is only part of the next
    /// column's, were tried: on a 32 x 32 cloth 539 supernodes instead of 548, no faster; the
    /// many leaves of the elimination tree stay supernodes of one particle.)
    fn supernodes(&mut self, start: &[usize], row: &[u32]) {
        let rows = |j: usize| &row[start[j]..start[j + 1]];
        let nests = |j: usize| {
            let r = rows(j);
            r.first() == Some(&(j as u32 + 1)) && r[1..] == *rows(j + 1)
        };
        self.sn.clear();
        self.row.clear();
        self.dest.clear();
        self.sn_of.clear();
        self.sn_of.resize(self.perm.len(), NONE);
        self.max_rows = 0;
        self.laid = 0;
        for (q, part) in self.parts.iter().enumerate() {
            if q > 0 {
                self.sn_split[q - 1] = self.sn.len();
            }
            let mut i = 0;
            while i < part.len() {
                let mut k = i;
                while k + 1 < part.len() && part[k + 1] == part[k] + 1 && nests(part[k] as usize) {
                    k += 1;
                }
                let (first, last) = (part[i] as usize, part[k] as usize);
                let b = self.row.len();
                self.row.extend_from_slice(rows(last));
                self.dest.extend(rows(last).iter().map(|&r| self.perm[r as usize]));
                let id = self.sn.len() as u32;
                self.sn_of[first..=last].fill(id);
                self.sn.push(super::Super {
                    first: first as u32,
                    width: (k - i + 1) as u32,
                    below: (b, self.row.len()),
                });
                self.max_rows = self.max_rows.max(k - i + 1 + self.row.len() - b);
                i = k + 1;
            }
        }
        self.blocks = start[self.perm.len()] + self.perm.len();
    }
}
