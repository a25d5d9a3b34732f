//! The path of C kept as polyline pieces, one per path topic, so that what Foxglove shows
//! after a seek stays within 1 cm of the path travelled.
//!
//! **Why the path is three topics.** On a seek, Foxglove clears the 3D scene and reads
//! back only the latest message of each topic. So the latest messages of `scene`, `path`
//! and `path_tip` together carry the whole path up to that time: `scene` from the start to
//! checkpoint A, `path` from A to checkpoint B, `path_tip` from B to C. The path is kept
//! as the vertices of a polyline within [`PATH_TOLERANCE_M`] of every sample, and C is
//! never more than [`PATH_PUBLISH_STEP_M`] from the drawn end, so what Foxglove shows after
//! a seek lies within 1 cm of the path travelled. `path_tip` holds at most
//! [`TIP_VERTICES`] vertices and `path` at most [`RECENT_VERTICES`], so the bytes written
//! grow linearly with the path (the `scene` message, which repeats the oldest piece, is
//! written once every [`RECENT_VERTICES`] vertices).

/// Largest distance (m) of a logged position from the drawn path polyline, before C moves on.
pub const PATH_TOLERANCE_M: f64 = 0.003;
/// C moves at most this far (m) from the end of the drawn path before `path_tip` is sent again.
pub const PATH_PUBLISH_STEP_M: f64 = 0.007;
/// Vertices `path_tip` holds before they move to `path`.
pub const TIP_VERTICES: usize = 8;
/// Vertices `path` holds before they move to `scene`.
pub const RECENT_VERTICES: usize = 64 * TIP_VERTICES;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct P2 {
    pub(super) x: f64,
    pub(super) y: f64,
}

impl P2 {
    fn dist(self, o: P2) -> f64 {
        (self.x - o.x).hypot(self.y - o.y)
    }
}

/// The path of C as a polyline in three pieces (see the module doc).
///
/// Vertices are logged positions. Between the last vertex (the anchor) and the newest
/// position (the end) every logged position lies within [`PATH_TOLERANCE_M`] of the
/// segment anchor-end: the end's direction from the anchor stays inside the cone of
/// directions that keeps every position since the anchor within the tolerance, and C
/// does not come back towards the anchor by more than the tolerance. When a new
/// position breaks this, the previous one becomes a vertex. O(1) per sample.
pub(super) struct PathPieces {
    /// Oldest piece: the start, then vertices up to checkpoint A.
    pub(super) old: Vec<P2>,
    /// Vertices after A up to checkpoint B.
    pub(super) recent: Vec<P2>,
    /// Vertices after B.
    pub(super) tip: Vec<P2>,
    anchor: P2,
    pub(super) end: P2,
    /// Unit direction the cone's angles are measured from.
    reference: P2,
    /// The cone of directions (rad from `reference`), once a position is farther than the
    /// tolerance from the anchor.
    cone: Option<(f64, f64)>,
    /// Largest distance from the anchor of a position since the anchor, m.
    reach: f64,
    /// End of the path as last sent on `path_tip`.
    pub(super) sent_end: Option<P2>,
    pub(super) old_changed: bool,
    pub(super) recent_changed: bool,
}

impl PathPieces {
    pub(super) fn new(start: P2) -> Self {
        Self {
            old: vec![start],
            recent: Vec::with_capacity(RECENT_VERTICES),
            tip: Vec::with_capacity(TIP_VERTICES),
            anchor: start,
            end: start,
            reference: P2 { x: 1.0, y: 0.0 },
            cone: None,
            reach: 0.0,
            sent_end: None,
            old_changed: false,
            recent_changed: false,
        }
    }

    /// Angle of `p` seen from the anchor, rad from `reference`, and its distance, m.
    fn polar(&self, p: P2) -> (f64, f64) {
        let (dx, dy) = (p.x - self.anchor.x, p.y - self.anchor.y);
        let r = self.reference;
        ((r.x * dy - r.y * dx).atan2(r.x * dx + r.y * dy), dx.hypot(dy))
    }

    fn fits(&self, p: P2) -> bool {
        let (phi, d) = self.polar(p);
        if d + PATH_TOLERANCE_M < self.reach {
            return false;
        }
        match self.cone {
            None => true,
            Some((lo, hi)) => d <= PATH_TOLERANCE_M && self.reach <= PATH_TOLERANCE_M || (lo..=hi).contains(&phi),
        }
    }

    /// Takes `p` as the new end, narrowing the cone.
    fn extend(&mut self, p: P2) {
        let (_, d) = self.polar(p);
        if d > PATH_TOLERANCE_M {
            if self.cone.is_none() {
                self.reference = P2 { x: (p.x - self.anchor.x) / d, y: (p.y - self.anchor.y) / d };
            }
            let (phi, _) = self.polar(p);
            let w = (PATH_TOLERANCE_M / d).asin();
            let (lo, hi) = self.cone.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
            self.cone = Some((lo.max(phi - w), hi.min(phi + w)));
        }
        self.reach = self.reach.max(d);
        self.end = p;
    }

    fn commit(&mut self, v: P2) {
        self.tip.push(v);
        self.anchor = v;
        self.cone = None;
        self.reach = 0.0;
        if self.tip.len() >= TIP_VERTICES {
            self.recent.append(&mut self.tip);
            self.recent_changed = true;
            if self.recent.len() >= RECENT_VERTICES {
                self.old.append(&mut self.recent);
                self.old_changed = true;
            }
        }
    }

    /// Adds the position `p` (m, world frame).
    pub(super) fn push(&mut self, p: P2) {
        if !self.fits(p) {
            let v = self.end;
            self.commit(v);
        }
        self.extend(p);
    }

    /// `path_tip` must be sent: a piece changed, or C moved far enough.
    pub(super) fn tip_due(&self) -> bool {
        self.old_changed
            || self.recent_changed
            || match self.sent_end {
                None => self.end.dist(self.old[0]) >= PATH_PUBLISH_STEP_M,
                Some(e) => self.end.dist(e) >= PATH_PUBLISH_STEP_M,
            }
    }

    pub(super) fn last_old(&self) -> P2 {
        self.old[self.old.len() - 1]
    }

    pub(super) fn last_recent(&self) -> P2 {
        self.recent.last().copied().unwrap_or_else(|| self.last_old())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance from `p` to segment a-b.
    fn seg_dist(p: P2, a: P2, b: P2) -> f64 {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let l2 = dx * dx + dy * dy;
        let t = if l2 == 0.0 { 0.0 } else { (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0) };
        p.dist(P2 { x: a.x + t * dx, y: a.y + t * dy })
    }

    fn drawn(p: &PathPieces) -> Vec<P2> {
        let mut v = p.old.clone();
        v.extend(&p.recent);
        v.extend(&p.tip);
        v.push(p.end);
        v
    }

    fn max_gap(points: &[P2], line: &[P2]) -> f64 {
        points
            .iter()
            .map(|&q| line.windows(2).map(|w| seg_dist(q, w[0], w[1])).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_straight_line_needs_no_vertex_and_a_circle_few() {
        let mut p = PathPieces::new(P2 { x: 0.0, y: 0.0 });
        for k in 1..=1000 {
            p.push(P2 { x: k as f64 * 1e-3, y: 0.0 });
        }
        assert_eq!(p.old.len() + p.recent.len() + p.tip.len(), 1);

        // Circle of radius 1 m: a chord 2 sqrt(2 r e) long stays within e of the arc.
        let mut p = PathPieces::new(P2 { x: 1.0, y: 0.0 });
        let mut all = vec![P2 { x: 1.0, y: 0.0 }];
        for k in 1..=6283 {
            let a = k as f64 * 1e-3;
            let q = P2 { x: a.cos(), y: a.sin() };
            all.push(q);
            p.push(q);
        }
        let vertices = p.old.len() + p.recent.len() + p.tip.len();
        let chord = 2.0 * (2.0 * PATH_TOLERANCE_M).sqrt();
        let least = (std::f64::consts::TAU / chord).floor() as usize;
        assert!((least..=2 * least).contains(&vertices), "{vertices} vertices, at least {least}");
        assert!(max_gap(&all, &drawn(&p)) <= PATH_TOLERANCE_M * 1.0001);
    }

    #[test]
    fn back_and_forth_and_jitter_stay_within_tolerance() {
        let mut p = PathPieces::new(P2 { x: 0.0, y: 0.0 });
        let mut all = vec![P2 { x: 0.0, y: 0.0 }];
        // Forward 0.5 m, back 0.3 m, sideways, then jitter of 0.1 mm in place.
        let mut q = P2 { x: 0.0, y: 0.0 };
        let mut go = |dx: f64, dy: f64, n: usize, p: &mut PathPieces, all: &mut Vec<P2>| {
            for _ in 0..n {
                q = P2 { x: q.x + dx, y: q.y + dy };
                all.push(q);
                p.push(q);
            }
        };
        go(1e-3, 0.0, 500, &mut p, &mut all);
        go(-1e-3, 0.0, 300, &mut p, &mut all);
        go(0.0, 1e-3, 200, &mut p, &mut all);
        for k in 0..2000 {
            let s = if k % 2 == 0 { 1e-4 } else { -1e-4 };
            go(s, s, 1, &mut p, &mut all);
        }
        let line = drawn(&p);
        assert!(max_gap(&all, &line) <= PATH_TOLERANCE_M * 1.5, "{}", max_gap(&all, &line));
        assert!(line.len() <= 6, "{} vertices for three legs and jitter", line.len());
    }
}
