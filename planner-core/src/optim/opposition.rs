//! Opposition: the opposite point `lb + ub - x` (SSA-GWO's initialisation, `Zhu2025Orchard` section
//! 2.3.1) and the TCLHHO opposition mutation (`Lei2024Warehouse` eq. 17-19).

use super::{Bounds, Objective, Population, Tracker};

/// `out = lb + ub - x`, per dimension.
pub fn opposite_point(lower: &[f32], upper: &[f32], x: &[f32], out: &mut [f32]) {
    for (((o, v), l), u) in out.iter_mut().zip(x).zip(lower).zip(upper) {
        *o = l + u - v;
    }
}

/// Replaces `pop` (already evaluated) by the best `size` points among its members and their
/// opposites, evaluating each opposite once.
///
/// Works in place with two index lists: the members sorted by cost and the opposites sorted
/// by cost are merged, taking the `size` smallest (a member wins a tie). Opposites chosen for
/// a member whose own point is dropped overwrite that row; the others go into rows whose
/// member and opposite were both dropped (there are exactly as many such rows).
pub(crate) fn select_best_of_opposites<const N: usize, const D: usize, O: Objective + ?Sized>(
    pop: &mut Population<N, D>,
    bounds: &Bounds<D>,
    tracker: &mut Tracker<D>,
    objective: &mut O,
) {
    let n = pop.size();
    let mut opposite_cost = [f32::INFINITY; N];
    let mut buf = [0.0f32; D];
    for (i, c) in opposite_cost.iter_mut().enumerate().take(n) {
        opposite_point(bounds.lower(), bounds.upper(), pop.position(i), &mut buf);
        bounds.clamp(&mut buf);
        *c = tracker.evaluate(objective, buf.get(..pop.dim()).unwrap_or(&[]));
    }
    let mut members = [0usize; N];
    pop.sort_indices(&mut members);
    let mut opposites = [0usize; N];
    for (k, o) in opposites.iter_mut().enumerate() {
        *o = k;
    }
    for k in 1..n {
        let mut j = k;
        while j > 0 && opposite_cost[opposites[j]] < opposite_cost[opposites[j - 1]] {
            opposites.swap(j, j - 1);
            j -= 1;
        }
    }
    let mut keep_member = [false; N];
    let mut take_opposite = [false; N];
    let (mut a, mut b) = (0usize, 0usize);
    for _ in 0..n {
        let from_member = b >= n || (a < n && pop.cost(members[a]) <= opposite_cost[opposites[b]]);
        if from_member {
            keep_member[members[a]] = true;
            a += 1;
        } else {
            take_opposite[opposites[b]] = true;
            b += 1;
        }
    }
    // Opposites whose own member is dropped replace it in place.
    for i in 0..n {
        if take_opposite[i] && !keep_member[i] {
            opposite_point(bounds.lower(), bounds.upper(), pop.position(i), &mut buf);
            bounds.clamp(&mut buf);
            pop.replace(i, buf.get(..pop.dim()).unwrap_or(&[]), opposite_cost[i]);
            keep_member[i] = true;
            take_opposite[i] = false;
        }
    }
    // The rest need a free row (member and opposite both dropped); the counts match.
    let mut free = 0usize;
    for i in 0..n {
        if take_opposite[i] {
            while free < n && keep_member[free] {
                free += 1;
            }
            if free >= n {
                break;
            }
            opposite_point(bounds.lower(), bounds.upper(), pop.position(i), &mut buf);
            bounds.clamp(&mut buf);
            pop.replace(free, buf.get(..pop.dim()).unwrap_or(&[]), opposite_cost[i]);
            keep_member[free] = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::random::Random;

    #[test]
    fn opposition_init_keeps_the_best_n_of_2n() {
        let b = Bounds::<2>::from_slices(&[-10.0, 0.0], &[10.0, 4.0]).unwrap();
        let mut obj = |x: &[f32]| (x[0] - 7.0).abs() + (x[1] - 3.5).abs();
        for seed in 0..20 {
            let mut rng = Random::new(seed);
            let mut p = Population::<8, 2>::new(8, 2);
            let mut t = Tracker::<2>::unconfigured();
            t.reset(2);
            let mut all = [0.0f32; 16];
            for i in 0..8 {
                let x = [rng.range(-10.0, 10.0), rng.range(0.0, 4.0)];
                let c = t.evaluate(&mut obj, &x);
                p.replace(i, &x, c);
                all[i] = c;
                all[8 + i] = obj(&[-x[0], 4.0 - x[1]]);
            }
            select_best_of_opposites(&mut p, &b, &mut t, &mut obj);
            assert_eq!(t.evaluations, 16);
            all.sort_unstable_by(f32::total_cmp);
            let mut got = [0.0f32; 8];
            for (i, g) in got.iter_mut().enumerate() {
                *g = p.cost(i);
                assert_eq!(obj(p.position(i)), p.cost(i), "cached cost matches the row");
            }
            got.sort_unstable_by(f32::total_cmp);
            assert_eq!(&got[..], &all[..8]);
        }
    }

    #[test]
    fn opposite_reflects_through_the_centre() {
        let mut out = [0.0; 2];
        opposite_point(&[0.0, -1.0], &[4.0, 1.0], &[1.0, 0.5], &mut out);
        assert_eq!(out, [3.0, -0.5]);
    }
}
