//! Render interpolation of the solids: their poses before a frame's last step of
//! [`World::advance`], kept beside the particles' (`prev_x`) and the bodies' (`prev_q`), and
//! the poses between those and the current ones at the clock's `alpha`.

use super::World;
use crate::rigid::orientation;
use glam::DQuat;

impl World {
    /// Keeps the solids' poses (positions, then orientations) before a frame's last step.
    pub(super) fn keep_solid_poses(&mut self) {
        let mut kept = std::mem::take(&mut self.prev_solids);
        kept.clear();
        kept.extend(self.solid_positions());
        kept.extend(self.solid_orientations());
        self.prev_solids = kept;
    }

    /// The kept poses, split into positions and orientations, when they are of the solids
    /// there are now (none after a step outside `advance`, or once a solid was added).
    fn kept_solid_poses(&self) -> Option<(&[f64], &[f64])> {
        let n = self.solid_count();
        let (d, r) = if self.dim() == 3 { (3, 4) } else { (2, 1) };
        (n > 0 && self.prev_solids.len() == n * (d + r)).then(|| self.prev_solids.split_at(n * d))
    }

    /// Solid positions to draw (flat, `n * dim`, m): `previous + alpha (current - previous)`
    /// between the poses before the last step of the latest [`World::advance`] and the
    /// current ones; the current ones outside a frame.
    #[must_use]
    pub fn interpolated_solid_positions(&self) -> Vec<f64> {
        let now = self.solid_positions();
        let Some((before, _)) = self.kept_solid_poses() else { return now };
        let alpha = self.alpha();
        before.iter().zip(&now).map(|(p, c)| p + alpha * (c - p)).collect()
    }

    /// Solid orientations to draw, as [`World::solid_orientations`]: the angle moved by
    /// `alpha` of its change over the last step (2D), the quaternion slerped (3D).
    #[must_use]
    pub fn interpolated_solid_orientations(&self) -> Vec<f64> {
        let now = self.solid_orientations();
        let Some((_, before)) = self.kept_solid_poses() else { return now };
        let alpha = self.alpha();
        if self.dim() != 3 {
            return before.iter().zip(&now).map(|(p, c)| p + alpha * (c - p)).collect();
        }
        let q = |c: &[f64]| DQuat::from_xyzw(c[1], c[2], c[3], c[0]);
        before
            .chunks_exact(4)
            .zip(now.chunks_exact(4))
            .flat_map(|(a, b)| {
                let s = orientation::slerp(q(a), q(b), alpha);
                [s.w, s.x, s.y, s.z]
            })
            .collect()
    }
}
