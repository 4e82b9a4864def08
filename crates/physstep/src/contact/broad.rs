//! The broad phase: sweep and prune on the x axis. Boxes are sorted by their low x (ties by
//! index, so the order never depends on anything but the boxes), each scanned against the
//! boxes that start before it ends; the pairs come out sorted by `(a, b)`, one thread, the
//! same every run.

/// The pairs `(a, b)`, `a < b`, whose boxes overlap and of which at least one can move
/// (`moves[i]`), sorted; `order` is scratch (kept between calls: the order of the last call
/// is nearly sorted for the next, which insertion sort finishes in close to linear time).
pub fn pairs(
    lo: &[[f64; 3]],
    hi: &[[f64; 3]],
    moves: &[bool],
    order: &mut Vec<u32>,
    out: &mut Vec<(u32, u32)>,
) {
    let n = lo.len();
    out.clear();
    if !moves.contains(&true) {
        // Nothing moves (every solid static or asleep): no pair (`order` is sorted again
        // by the next call that needs it).
        return;
    }
    if order.len() != n {
        order.clear();
        order.extend(0..n as u32);
    }
    let key = |i: u32| (lo[i as usize][0], i);
    // Insertion sort: stable for the keys (x, index), fast on last step's order.
    for k in 1..n {
        let cur = order[k];
        let mut j = k;
        while j > 0 && less(key(cur), key(order[j - 1])) {
            order[j] = order[j - 1];
            j -= 1;
        }
        order[j] = cur;
    }
    for (k, &i) in order.iter().enumerate() {
        let (li, hi_i) = (&lo[i as usize], &hi[i as usize]);
        for &j in &order[k + 1..] {
            let lj = &lo[j as usize];
            if lj[0] > hi_i[0] {
                break;
            }
            if !(moves[i as usize] || moves[j as usize]) {
                continue;
            }
            let hj = &hi[j as usize];
            if li[1] <= hj[1] && lj[1] <= hi_i[1] && li[2] <= hj[2] && lj[2] <= hi_i[2] {
                out.push((i.min(j), i.max(j)));
            }
        }
    }
    out.sort_unstable();
}

/// `a < b` for keys whose x may be infinite (a plane's box): by x with `total_cmp`, then
/// index.
fn less(a: (f64, u32), b: (f64, u32)) -> bool {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).is_lt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_exactly_the_overlapping_moving_pairs_in_order() {
        // Three unit boxes on a line, the first two overlapping, and a static floor under all.
        let lo = [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [3.0, 0.0, 0.0], [f64::NEG_INFINITY, -1.0, 0.0]];
        let hi = [[1.0, 1.0, 0.0], [1.5, 1.0, 0.0], [4.0, 1.0, 0.0], [f64::INFINITY, 0.0, 0.0]];
        let mut order = Vec::new();
        let mut out = Vec::new();
        pairs(&lo, &hi, &[true, true, true, false], &mut order, &mut out);
        assert_eq!(out, vec![(0, 1), (0, 3), (1, 3), (2, 3)]);
        // The floor alone never pairs with another static box.
        pairs(&lo, &hi, &[false, false, true, false], &mut order, &mut out);
        assert_eq!(out, vec![(2, 3)]);
    }
}
