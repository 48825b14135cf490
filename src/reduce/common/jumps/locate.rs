//! Locating one candidate span by bisection and classing what the brackets hold (steps 2 and 3
//! of the module doc of [`super`]): each side of the span judges whether the midpoint follows
//! its trend, and the finest bracket, the ones up to ten tolerances wide and, last, the whole
//! span cut by its largest changes tell a step, a kink or a smooth stretch.

/// Step or kink.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum JumpKind {
    /// The value changes abruptly.
    Step,
    /// Only the slope does.
    Kink,
}

impl JumpKind {
    pub fn name(self) -> &'static str {
        match self {
            JumpKind::Step => "step",
            JumpKind::Kink => "kink",
        }
    }
}

/// What [`super::IdealCase::at`] returns for a quantity that is not known exactly at that design
/// but only as a statistical estimate (a forced probe whose peak may be carried by a chaotic
/// motion whose amplitude over the design life was not measured there): a bisection stops at it
/// ([`locate()`]).
pub const UNRESOLVED: f64 = f64::INFINITY;

/// The result of locating one candidate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    Jump {
        kind: JumpKind,
        location: f64,
        tol: f64,
        size: f64,
    },
    /// A steep but smooth stretch: neither the value nor the slope changes abruptly.
    Smooth,
    /// A simulation inside the span did not end ok.
    Failed,
}

/// The known points of one side of a bracket, nearest last: where that side's trend comes
/// from.
struct Side {
    pts: Vec<(f64, f64)>,
}

impl Side {
    fn last(&self) -> (f64, f64) {
        self.pts[self.pts.len() - 1]
    }

    /// The secant through the two nearest points (NaN with one).
    fn slope(&self) -> f64 {
        match self.pts.len() {
            0 | 1 => f64::NAN,
            n => {
                let (p, q) = (self.pts[n - 2], self.pts[n - 1]);
                (q.1 - p.1) / (q.0 - p.0)
            }
        }
    }

    /// `|second divided difference|` of the three nearest points: half the side's curvature;
    /// `None` with fewer points (the side cannot say how far it may bend).
    fn curvature(&self) -> Option<f64> {
        let n = self.pts.len();
        if n < 3 {
            return None;
        }
        let (p, q, r) = (self.pts[n - 3], self.pts[n - 2], self.pts[n - 1]);
        let d1 = (q.1 - p.1) / (q.0 - p.0);
        let d2 = (r.1 - q.1) / (r.0 - q.0);
        Some(((d2 - d1) / (r.0 - p.0)).abs())
    }

    /// The side's trend at `x`: the line through its nearest point with `slope`, and the error
    /// a smooth curve of the side's curvature would make there (infinite when unknown).
    fn predict(&self, x: f64, slope: f64) -> (f64, f64) {
        let (x0, y0) = self.last();
        let far = match self.pts.len() {
            0 | 1 => x0,
            n => self.pts[n - 2].0,
        };
        let err = self
            .curvature()
            .map_or(f64::INFINITY, |c| c * ((x - x0) * (x - far)).abs());
        (y0 + slope * (x - x0), err)
    }

    fn push(&mut self, p: (f64, f64)) {
        self.pts.push(p);
        if self.pts.len() > 3 {
            self.pts.remove(0);
        }
    }
}

/// Locates the jump in the span `(i, j)` of a line by bisection to a bracket at most `tol`
/// wide, with `f(x)` the quantity of the ideal case at axis value `x`, and classes it (module
/// doc). Returns the outcome and the number of evaluations of `f`.
///
/// Which side of the midpoint `m` the jump is on: each side predicts `q(m)` with the line
/// through its nearest point along its nearest secant, and knows the error a smooth curve of its
/// own curvature (from its three nearest points; unbounded with fewer) would make there. `m`
/// belongs to a side when the prediction holds within four times that error and only that
/// side's does; when both hold, to the side with the smaller error (the more demanding test it
/// passed); when neither (a side bends near the jump more than its known points show), to the
/// side whose slope is nearer the slope at `m`, from one more simulation just before `m`. The
/// side that gets `m` adds it as its nearest point. A square-root corner (one side's slope
/// unbounded at the jump, as at a grazing impact) is then located as well as a clean kink or a
/// step: the smooth side's tight prediction decides, the corner side's large curvature makes
/// its own test loose. Returns the outcome, the simulations asked for, and whether the
/// bisection stopped at a midpoint known only as an estimate ([`UNRESOLVED`]).
pub fn locate(
    xs: &[f64],
    ys: &[f64],
    (i, j): (usize, usize),
    mut f: impl FnMut(f64) -> Option<f64>,
    step_tol: f64,
    kink: Option<f64>,
    tol: f64,
) -> (Outcome, u32, bool) {
    let finite = |k: &usize| ys[*k].is_finite();
    let mut left = Side {
        pts: (i.saturating_sub(2)..=i)
            .filter(finite)
            .map(|k| (xs[k], ys[k]))
            .collect(),
    };
    let mut right = Side {
        pts: (j..(j + 3).min(xs.len()))
            .rev()
            .filter(finite)
            .map(|k| (xs[k], ys[k]))
            .collect(),
    };
    // Rounding in the simulations: no trend is asked to be closer than this.
    let scale = ys[i].abs().max(ys[j].abs());
    let floor = 1e-9 * scale + f64::MIN_POSITIVE;
    let mut sims = 0;
    let mut brackets = vec![Bracket::of(&left, &right)];
    // Each halving costs one simulation; 64 bound the loop whatever `tol` is.
    while right.last().0 - left.last().0 > tol && sims < 64 {
        let (a, b) = (left.last().0, right.last().0);
        let m = 0.5 * (a + b);
        if !(m > a && m < b) {
            break; // the bracket is down to adjacent doubles
        }
        match halve(&left, &right, m, &mut f, floor, step_tol, &mut sims) {
            Ok((fm, true)) => left.push((m, fm)),
            Ok((fm, false)) => right.push((m, fm)),
            Err((outcome, stopped)) => return (outcome, sims, stopped),
        }
        brackets.push(Bracket::of(&left, &right));
    }
    let outcome = classify(&brackets, &mut f, step_tol, kink, tol, &mut sims);
    (outcome, sims, false)
}

/// One halving of the bracket between `left` and `right` at its midpoint `m`: the value there
/// and whether it belongs to the left side (the side whose trend predicts it; when neither
/// does, the slope at `m` from one more simulation decides). `Err` with the outcome, and
/// whether the quantity stopped being resolved, when a simulation fails or is unresolved.
fn halve(
    left: &Side,
    right: &Side,
    m: f64,
    f: &mut impl FnMut(f64) -> Option<f64>,
    floor: f64,
    step_tol: f64,
    sims: &mut u32,
) -> Result<(f64, bool), (Outcome, bool)> {
    *sims += 1;
    let Some(fm) = f(m).filter(|v| v.is_finite() || *v == UNRESOLVED) else {
        return Err((Outcome::Failed, false));
    };
    let (sl, sr) = (left.slope(), right.slope());
    let either = |s: f64, other: f64| {
        if s.is_finite() {
            s
        } else if other.is_finite() {
            other
        } else {
            0.0
        }
    };
    let (sl, sr) = (either(sl, sr), either(sr, sl));
    if fm == UNRESOLVED {
        return Err((unresolved_stop(left, right, (sl, sr), step_tol), true));
    }
    let (pl, el) = left.predict(m, sl);
    let (pr, er) = right.predict(m, sr);
    let (dl, dr) = ((fm - pl).abs(), (fm - pr).abs());
    let (el, er) = (el + floor, er + floor);
    let to_left = match (dl <= 4.0 * el, dr <= 4.0 * er) {
        (true, false) => true,
        (false, true) => false,
        // Both trends allow it: the one that asked more of it (the smaller error) decides.
        (true, true) if el != er => el < er,
        (true, true) => dl <= dr,
        // Neither does: a side bends near the jump more than its known points show. The
        // slope at m (from one more simulation just before it) tells which side it is on.
        (false, false) => {
            let eps = (right.last().0 - left.last().0) / 64.0;
            *sims += 1;
            let Some(fe) = f(m - eps).filter(|v| v.is_finite() || *v == UNRESOLVED) else {
                return Err((Outcome::Failed, false));
            };
            if fe == UNRESOLVED {
                return Err((unresolved_stop(left, right, (sl, sr), step_tol), true));
            }
            let s = (fm - fe) / eps;
            (s - sl).abs() <= (s - sr).abs()
        }
    };
    Ok((fm, to_left))
}

/// What the brackets of a bisection hold, finest last. A step across the finest bracket is a
/// step. One across a wider bracket (at most ten tolerances) only when it persists inside it
/// ([`persists`]): a steep smooth stretch, or one that curves hard, also changes by `step_tol`
/// across some wider bracket. A kink is the finest bracket across which the slope still changes
/// enough, no wider than ten tolerances: a corner rounded over more than the tolerance (but
/// less than a tenth of the grid step) is a kink at the scale of its rounding, and says so with
/// its wider location_tol. Last, the whole span is searched for a step by its largest changes:
/// a quantity with several steps close together (DI where the second peak changes identity
/// again and again) can lead the bisection, which follows the sides' trends, off its steps. A
/// candidate with none of these was a steep but smooth stretch.
fn classify(
    brackets: &[Bracket],
    f: &mut impl FnMut(f64) -> Option<f64>,
    step_tol: f64,
    kink: Option<f64>,
    tol: f64,
    sims: &mut u32,
) -> Outcome {
    let finest = brackets.last().and_then(|br| br.step(step_tol));
    let coarse = brackets
        .iter()
        .rev()
        .take_while(|br| br.b - br.a <= 10.0 * tol)
        .find(|br| (br.fb - br.fa).abs() >= step_tol);
    let step = match (finest, coarse) {
        (Some(step), _) => Some(step),
        (None, Some(br)) => persists(br, f, step_tol, tol, sims),
        (None, None) => None,
    };
    step.or_else(|| {
        brackets
            .iter()
            .rev()
            .take_while(|br| br.b - br.a <= 10.0 * tol)
            .find_map(|br| br.kink(kink))
    })
    .or_else(|| persists(&brackets[0], f, step_tol, tol, sims))
    .unwrap_or(Outcome::Smooth)
}

/// Interior points a bracket is sampled at by [`persists`].
const PERSIST_SAMPLES: u32 = 7;

/// Whether `br` holds a step: the bracket is cut into `PERSIST_SAMPLES + 1` equal parts
/// (`PERSIST_SAMPLES` simulations) and the part with the largest change is cut again, until a part at most `tol` wide still changes by `step_tol` (a step
/// there) or the largest change of a cut falls below it (a smooth stretch: `None`). Following
/// the largest change, not a side's trend, finds a step among several.
fn persists(
    br: &Bracket,
    f: &mut impl FnMut(f64) -> Option<f64>,
    step_tol: f64,
    tol: f64,
    sims: &mut u32,
) -> Option<Outcome> {
    let n = PERSIST_SAMPLES + 1;
    let (mut a, mut fa, mut b, mut fb) = (br.a, br.fa, br.b, br.fb);
    while b - a > tol {
        let mut pts = vec![(a, fa)];
        for k in 1..n {
            let x = a + (b - a) * f64::from(k) / f64::from(n);
            *sims += 1;
            match f(x) {
                Some(v) if v.is_finite() => pts.push((x, v)),
                // An estimate or a failed run inside: the step is not confirmed.
                _ => return None,
            }
        }
        pts.push((b, fb));
        let k = (0..pts.len() - 1)
            .max_by(|&i, &j| {
                let d = |k: usize| (pts[k + 1].1 - pts[k].1).abs();
                d(i).total_cmp(&d(j))
            })
            .unwrap_or(0);
        if (pts[k + 1].1 - pts[k].1).abs() < step_tol {
            return None;
        }
        ((a, fa), (b, fb)) = (pts[k], pts[k + 1]);
    }
    Some(Outcome::Jump {
        kind: JumpKind::Step,
        location: 0.5 * (a + b),
        tol: 0.5 * (b - a),
        size: fb - fa,
    })
}

/// The bisection stopped at a midpoint known only as an estimate ([`UNRESOLVED`]): it cannot
/// say which side that point is on, so the bracket reached is the location. A step when the
/// change across it is not explained by either side's trend (by `step_tol` or more, as a step
/// candidate is found), else dropped; a kink is not told at an estimate's resolution.
fn unresolved_stop(left: &Side, right: &Side, (sl, sr): (f64, f64), step_tol: f64) -> Outcome {
    let ((a, fa), (b, fb)) = (left.last(), right.last());
    let (pl, _) = left.predict(b, sl);
    let (pr, _) = right.predict(a, sr);
    if (fb - pl).abs().min((fa - pr).abs()) >= step_tol {
        Outcome::Jump {
            kind: JumpKind::Step,
            location: 0.5 * (a + b),
            tol: 0.5 * (b - a),
            size: fb - fa,
        }
    } else {
        Outcome::Smooth
    }
}

/// One bracket of the bisection: its ends and values, and the secants either side.
struct Bracket {
    a: f64,
    b: f64,
    fa: f64,
    fb: f64,
    sl: f64,
    sr: f64,
}

impl Bracket {
    fn of(left: &Side, right: &Side) -> Bracket {
        let ((a, fa), (b, fb)) = (left.last(), right.last());
        Bracket {
            a,
            b,
            fa,
            fb,
            sl: left.slope(),
            sr: right.slope(),
        }
    }

    /// A step when the change across the bracket is not explained by the trend on either side
    /// by `step_tol` or more (`min |Δ - s w|` over the secants `s` either side, `w` the
    /// bracket's width; `|Δ|` when neither side has a secant), as a step candidate is found.
    fn step(&self, step_tol: f64) -> Option<Outcome> {
        let change = self.fb - self.fa;
        let unexplained = [self.sl, self.sr]
            .iter()
            .filter(|s| s.is_finite())
            .map(|s| (change - s * (self.b - self.a)).abs())
            .reduce(f64::min)
            .unwrap_or(change.abs());
        (unexplained >= step_tol).then_some(Outcome::Jump {
            kind: JumpKind::Step,
            location: 0.5 * (self.a + self.b),
            tol: 0.5 * (self.b - self.a),
            size: change,
        })
    }

    /// A kink when the slope changes across the bracket by the threshold or more.
    fn kink(&self, kink: Option<f64>) -> Option<Outcome> {
        kink.is_some_and(|thr| (self.sr - self.sl).abs() >= thr)
            .then_some(Outcome::Jump {
                kind: JumpKind::Kink,
                location: 0.5 * (self.a + self.b),
                tol: 0.5 * (self.b - self.a),
                size: self.sr - self.sl,
            })
    }
}
