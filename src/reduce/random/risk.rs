//! Capacities, fragility and annual risk per design (model.md §13, docs/scenes.md): what a
//! study with an intensity measure and a threshold adds to the random reduction.
//!
//! # Per design
//! * Its motions' **capacities** (g) by incremental dynamic analysis, from the design stripe's
//!   rows ([`crate::sim::random::ida`]).
//! * The **fragility** from them ([`crate::stats::capacity`]): the empirical curve and the
//!   lognormal fit (`theta`, `beta` per ln IM, censored maximum likelihood), each with 95 %
//!   bootstrap intervals over the motions.
//! * **Stripes** (the `im` axis): each stripe's Monte Carlo `p_f` and Clopper–Pearson interval
//!   beside the empirical curve's value and bootstrap interval and the lognormal's value at its
//!   intensity.
//! * **Whether the lognormal holds** (`fit_ok`): its Kolmogorov–Smirnov distance to the
//!   capacities within Lilliefors' 5 % value, its value at every stripe inside that stripe's
//!   interval, and, with a hazard, its `lambda_f` inside the empirical curve's bootstrap
//!   interval of `lambda_f` (the tail that the hazard weighs). When it does not hold, risk and
//!   ranking use the empirical curve, and the report says so.
//! * With a **hazard** ([`crate::stats::hazard`]): `lambda_f` over both curves of the
//!   capacities and over the stripes' own fragility ([`super::stripes`]), the curve used,
//!   `P_f` over the study's years, and the intensities that contribute 10, 50 and 90 % of
//!   `lambda_f`. **The curve used**: where motions fall back (a motion passed the limit at one
//!   scale and not at a larger one tried), a capacity is the crossing its search met, not
//!   always the first, and the curve used is the stripes' fitted lognormal: `P(f | IM)` measured
//!   at each stripe is what the risk integral asks for, and it needs no capacity. Where no
//!   motion fell back, every capacity is a first passage, and the capacities' curve that holds
//!   is used; so too where the stripes have no fit (their counts separated, too few stripes).
//!   Against a truth measured at 40 stripes of 20,000 motions (results/risk_validation.md, 40
//!   seeds a design): at two damped designs whose motions fall back the stripes' `lambda_f`
//!   reads 0.994 and 1.002 of the truth, its interval covering at 38 and 39 of 40 seeds, the
//!   capacities' at 25 and 32; at the structure without a damper the capacities' covers at 38
//!   and the stripes' at 34 (its lognormal over six stripes reads 1.1 % low). The stripes' fit
//!   is not tested stripe by stripe for this: at a 4-cm design it lies outside some stripe's
//!   interval at most seeds, and its `lambda_f` still reads the truth (the integral over the
//!   hazard averages the misfit). The designs are then ranked by `lambda_f` (rank 1 the lowest;
//!   ties as the core's ranking breaks them: the lower mean amplitude, then the lower design;
//!   [`rank_by_risk`]).

use crate::numeric::mix64;
use crate::stats::capacity::{Capacities, LognormalFit, lilliefors_5};
use crate::stats::hazard::{
    self, SiteHazard, deaggregation, lambda_f_empirical, lambda_f_lognormal, lognormal_p, p_years,
};

use super::point::PointPf;
use crate::reduce::common::PointStats;
use crate::store::table::{Column, Table};

/// One stripe of a design: its intensity (g), the Monte Carlo estimate at it, and both curves
/// there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stripe {
    pub im: f64,
    /// The stripe's Monte Carlo `p_f` and its Clopper–Pearson 95 % interval.
    pub p_f: f64,
    pub p_f_lo: f64,
    pub p_f_hi: f64,
    /// The empirical fragility from the capacities at `im`, and its bootstrap interval.
    pub empirical: f64,
    pub empirical_lo: f64,
    pub empirical_hi: f64,
    /// The lognormal fit at `im` (NaN without a fit).
    pub lognormal: f64,
}

impl Stripe {
    /// The lognormal lies inside the stripe's interval.
    pub fn lognormal_ok(&self) -> bool {
        self.lognormal >= self.p_f_lo && self.lognormal <= self.p_f_hi
    }
}

/// Which fragility curve the risk and the ranking use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Curve {
    /// The lognormal fitted to the stripes' counts ([`super::stripes`]).
    Stripes,
    /// The capacities' lognormal fit.
    Lognormal,
    /// The capacities' empirical curve.
    Empirical,
}

impl Curve {
    pub fn name(self) -> &'static str {
        match self {
            Curve::Stripes => "stripes",
            Curve::Lognormal => "lognormal",
            Curve::Empirical => "empirical",
        }
    }

    /// The curve in words, for the report.
    pub fn text(self) -> &'static str {
        match self {
            Curve::Stripes => "the stripes' fitted fragility",
            Curve::Lognormal => "the capacities' lognormal fragility",
            Curve::Empirical => "the capacities' empirical fragility",
        }
    }
}

/// A design's own fragility from its stripes: the lognormal fitted to the share of motions that
/// pass the limit at each stripe, and with a hazard its `lambda_f` with the bootstrap interval
/// over the motions ([`super::stripes`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripesFit {
    pub theta: f64,
    pub beta: f64,
    pub lambda_f: Option<Interval>,
}

/// A value and its 95 % interval.
pub type Interval = (f64, f64, f64);

/// The annual risk of one design over the study's hazard.
#[derive(Clone, Debug, PartialEq)]
pub struct Risk {
    /// `lambda_f` (per year) over the empirical curve and over the lognormal, each with its
    /// bootstrap interval.
    pub empirical: Interval,
    pub lognormal: Interval,
    /// The capacities' curve that holds (the lognormal where `fit_ok`, else the empirical
    /// curve) and its `lambda_f` with its interval.
    pub capacities_curve: Curve,
    pub capacities: Interval,
    /// The curve used (the stripes' fit where motions fall back, else the capacities' curve that
    /// holds; module doc), and its `lambda_f`, `P_f` over the years, with intervals.
    pub curve: Curve,
    pub lambda_f: Interval,
    pub p_f_years: Interval,
    /// The intensities (g) where `lambda_f` reaches 10, 50 and 90 % of itself, over the curve
    /// used.
    pub deaggregation: [f64; 3],
}

/// What the capacities say of one design (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct DesignRisk {
    pub design: u64,
    /// Motions with a capacity, those censored at `ida_max`, those whose response fell back
    /// above a passing gain, and the mean runs a search took.
    pub n: usize,
    pub censored: usize,
    pub resurrected: usize,
    pub runs_mean: f64,
    pub fit: Option<LognormalFit>,
    pub theta: Interval,
    pub beta: Interval,
    /// The Kolmogorov–Smirnov distance and Lilliefors' 5 % value.
    pub ks: f64,
    pub ks_critical: f64,
    pub stripes: Vec<Stripe>,
    pub fit_ok: bool,
    pub risk: Option<Risk>,
    /// Rank by `lambda_f` (1 the lowest), with a hazard.
    pub risk_rank: Option<u64>,
}

/// The capacities of one design's motions: `(capacity, censored, resurrected, runs)`.
pub type MotionCapacity = (f64, bool, bool, u32);

/// The risk of design `design` from its motions' capacities, its stripes `(im, Monte Carlo)`,
/// the stripes' own fit `own` and the study's hazard. The bootstrap is seeded by the study's
/// `seed` alone, the same at every design (common random numbers, as subset simulation's):
/// every design resamples the same ground motions, and a design's intervals do not depend on
/// its index in the grid, so a study of that design alone reproduces them.
pub fn design_risk(
    design: u64,
    motions: &[MotionCapacity],
    stripes: &[(f64, PointPf)],
    own: Option<StripesFit>,
    hazard: Option<&SiteHazard>,
    ida_max: f64,
    seed: u64,
) -> DesignRisk {
    let caps = Capacities::new(motions.iter().map(|m| (m.0, m.1)).collect());
    let fit = caps.lognormal();
    let ims: Vec<f64> = stripes.iter().map(|s| s.0).collect();
    let stat = |c: &Capacities| statistic(c, &ims, hazard, ida_max);
    let boot = caps.bootstrap(mix64(seed ^ 0xCA9A_C17E), stat);
    let at = |k: usize| boot.get(k).copied().unwrap_or((f64::NAN, f64::NAN));
    let whole = stat(&caps);
    let stripes: Vec<Stripe> = stripes
        .iter()
        .enumerate()
        .map(|(j, (im, p))| Stripe {
            im: *im,
            p_f: p.p_f,
            p_f_lo: p.p_f_lo,
            p_f_hi: p.p_f_hi,
            empirical: whole[4 + j],
            empirical_lo: at(4 + j).0,
            empirical_hi: at(4 + j).1,
            lognormal: fit.map_or(f64::NAN, |f| f.p(*im)),
        })
        .collect();
    let (ks, ks_critical) = match &fit {
        Some(f) => (caps.ks_distance(f), lilliefors_5(caps.n())),
        None => (f64::NAN, f64::NAN),
    };
    let risk = hazard.map(|h| {
        let empirical = (whole[2], at(2).0, at(2).1);
        let lognormal = (whole[3], at(3).0, at(3).1);
        (h, empirical, lognormal)
    });
    let tail_ok = risk
        .as_ref()
        .is_none_or(|(_, e, l)| l.0 >= e.1 && l.0 <= e.2);
    let fit_ok = fit.is_some()
        && ks <= ks_critical
        && stripes.iter().all(|s| s.p_f.is_nan() || s.lognormal_ok())
        && tail_ok;
    // Where no motion fell back, every capacity is its motion's first passage (the response
    // monotone in the scale over every run tried), and the capacities' curve is the decision's.
    let resurrected = motions.iter().filter(|m| m.2).count();
    let own = own.filter(|_| resurrected > 0);
    let risk = risk.map(|(h, empirical, lognormal)| {
        annual_risk(h, &caps, fit, fit_ok, (empirical, lognormal), own)
    });
    DesignRisk {
        design,
        n: caps.n(),
        censored: caps.censored(),
        resurrected,
        runs_mean: motions.iter().map(|m| f64::from(m.3)).sum::<f64>() / motions.len() as f64,
        fit,
        theta: (whole[0], at(0).0, at(0).1),
        beta: (whole[1], at(1).0, at(1).1),
        ks,
        ks_critical,
        stripes,
        fit_ok,
        risk,
        risk_rank: None,
    }
}

/// The bootstrap's statistic of a set of capacities: the lognormal fit's `theta` and `beta`,
/// with a hazard the annual rates of failure over the empirical curve (a censored capacity at
/// `ida_max`) and over the fit, then the empirical curve at each stripe's intensity `ims`.
fn statistic(c: &Capacities, ims: &[f64], hazard: Option<&SiteHazard>, ida_max: f64) -> Vec<f64> {
    let f = c.lognormal();
    let (le, ll) = match hazard {
        None => (f64::NAN, f64::NAN),
        Some(h) => {
            let values: Vec<f64> = c
                .values
                .iter()
                .map(|v| if v.1 { ida_max } else { v.0 })
                .collect();
            let logn = f.map_or(f64::NAN, |f| lambda_f_lognormal(&h.curve, f.theta, f.beta));
            (lambda_f_empirical(&h.curve, &values), logn)
        }
    };
    let mut v = vec![
        f.map_or(f64::NAN, |f| f.theta),
        f.map_or(f64::NAN, |f| f.beta),
        le,
        ll,
    ];
    v.extend(ims.iter().map(|&x| c.p(x)));
    v
}

/// A design's annual risk over the hazard `h`: `lambda_f` and its interval over the curve used
/// (the stripes' own fit `own` where given, else the capacities' curve that holds: the
/// lognormal fit where `fit_ok`, else the empirical curve), the probability of a failure in the
/// hazard's years and the deaggregation over the intensity.
fn annual_risk(
    h: &SiteHazard,
    caps: &Capacities,
    fit: Option<LognormalFit>,
    fit_ok: bool,
    (empirical, lognormal): (Interval, Interval),
    own: Option<StripesFit>,
) -> Risk {
    let (capacities_curve, capacities) = if fit_ok {
        (Curve::Lognormal, lognormal)
    } else {
        (Curve::Empirical, empirical)
    };
    let (curve, lambda_f) = match own.and_then(|o| o.lambda_f) {
        Some(l) => (Curve::Stripes, l),
        None => (capacities_curve, capacities),
    };
    let py = |l: f64| p_years(l, h.years);
    let (lo, hi) = caps
        .values
        .first()
        .zip(caps.values.last())
        .map_or((1e-3, 10.0), |(a, b)| (a.0 / 100.0, b.0 * 100.0));
    let deagg = match (curve, fit, own) {
        (Curve::Stripes, _, Some(o)) => {
            deaggregation(&h.curve, |x| lognormal_p(x, o.theta, o.beta), lo, hi)
        }
        (Curve::Lognormal, Some(f), _) => deaggregation(&h.curve, |x| f.p(x), lo, hi),
        _ => deaggregation(&h.curve, |x| caps.p(x), lo, hi),
    };
    Risk {
        empirical,
        lognormal,
        capacities_curve,
        capacities,
        curve,
        lambda_f,
        p_f_years: (py(lambda_f.0), py(lambda_f.1), py(lambda_f.2)),
        deaggregation: deagg,
    }
}

/// Ranks the designs that have a `lambda_f` (1 the lowest) in the order of the core's ranking
/// `points` (by `p_s = exp(-years lambda_f)`, ties to the lower mean amplitude, then to the
/// lower design: [`crate::reduce::common`]), so that `risk_rank` is `rank` wherever every
/// design has a risk, exact ties included.
pub fn rank_by_risk(designs: &mut [DesignRisk], points: &[PointStats]) {
    let mut order: Vec<(u64, u64)> = points
        .iter()
        .filter_map(|p| Some((p.rank?, p.point)))
        .collect();
    order.sort_unstable();
    let mut next = 1;
    for (_, point) in order {
        if let Ok(i) = designs.binary_search_by_key(&point, |d| d.design)
            && designs[i]
                .risk
                .as_ref()
                .is_some_and(|r| r.lambda_f.0.is_finite())
        {
            designs[i].risk_rank = Some(next);
            next += 1;
        }
    }
}

/// Cornell's closed form for a design's lognormal under a power-law hazard, where both exist
/// (the check of [`lambda_f_lognormal`]).
pub fn cornell_of(d: &DesignRisk, h: &SiteHazard) -> Option<f64> {
    match (&h.curve, d.fit) {
        (hazard::Hazard::Power { k0, k }, Some(f)) => {
            Some(hazard::cornell(*k0, *k, f.theta, f.beta))
        }
        _ => None,
    }
}

/// The capacities' fragility and risk of design `design` among `designs` (in design order), if
/// it has capacities.
pub fn risk_of(designs: &[DesignRisk], design: u64) -> Option<&DesignRisk> {
    designs
        .binary_search_by_key(&design, |f| f.design)
        .ok()
        .map(|i| &designs[i])
}

/// The summary columns of the capacities and the risk (docs/schema.md): `theta`, `beta_im` and
/// their bootstrap intervals, `ks`, `ks_critical`, `fit_ok`, `capacities`,
/// `capacities_censored`, `capacities_resurrected`, `ida_runs_mean`; with a hazard `lambda_f`
/// (the curve used, `lambda_f_curve`) and its interval, the capacities' curve that holds
/// (`lambda_f_capacities` and its interval), `lambda_f_empirical`, `lambda_f_lognormal`,
/// `lambda_f_cornell` (a power law), `p_f_years` and its interval,
/// `deagg_im_10`, `deagg_im_50`, `deagg_im_90`, `risk_rank`.
pub fn summary_columns(
    t: &mut Table,
    designs: &[DesignRisk],
    hazard: Option<&SiteHazard>,
    rows: &[&PointStats],
) {
    let risks: Vec<Option<&DesignRisk>> = rows.iter().map(|d| risk_of(designs, d.point)).collect();
    let col = |g: &dyn Fn(&DesignRisk) -> f64| {
        Column::F64(risks.iter().map(|r| r.map_or(f64::NAN, g)).collect())
    };
    let count =
        |g: &dyn Fn(&DesignRisk) -> u64| Column::U64(risks.iter().map(|r| r.map(g)).collect());
    t.push("theta", col(&|r| r.theta.0));
    t.push("theta_lo", col(&|r| r.theta.1));
    t.push("theta_hi", col(&|r| r.theta.2));
    t.push("beta_im", col(&|r| r.beta.0));
    t.push("beta_im_lo", col(&|r| r.beta.1));
    t.push("beta_im_hi", col(&|r| r.beta.2));
    t.push("ks", col(&|r| r.ks));
    t.push("ks_critical", col(&|r| r.ks_critical));
    t.push(
        "fit_ok",
        Column::Bool(risks.iter().map(|r| r.is_some_and(|r| r.fit_ok)).collect()),
    );
    t.push("capacities", count(&|r| r.n as u64));
    t.push("capacities_censored", count(&|r| r.censored as u64));
    t.push("capacities_resurrected", count(&|r| r.resurrected as u64));
    t.push("ida_runs_mean", col(&|r| r.runs_mean));
    let Some(h) = hazard else {
        return;
    };
    let k = |g: &dyn Fn(&Risk) -> f64| col(&|r| r.risk.as_ref().map_or(f64::NAN, g));
    t.push("lambda_f", k(&|k| k.lambda_f.0));
    t.push("lambda_f_lo", k(&|k| k.lambda_f.1));
    t.push("lambda_f_hi", k(&|k| k.lambda_f.2));
    t.push(
        "lambda_f_curve",
        Column::Str(
            risks
                .iter()
                .map(|r| {
                    r.and_then(|r| r.risk.as_ref())
                        .map_or("", |k| k.curve.name())
                        .to_string()
                })
                .collect(),
        ),
    );
    t.push("lambda_f_capacities", k(&|k| k.capacities.0));
    t.push("lambda_f_capacities_lo", k(&|k| k.capacities.1));
    t.push("lambda_f_capacities_hi", k(&|k| k.capacities.2));
    t.push("lambda_f_empirical", k(&|k| k.empirical.0));
    t.push("lambda_f_lognormal", k(&|k| k.lognormal.0));
    t.push(
        "lambda_f_cornell",
        col(&|r| cornell_of(r, h).unwrap_or(f64::NAN)),
    );
    t.push("p_f_years", k(&|k| k.p_f_years.0));
    t.push("p_f_years_lo", k(&|k| k.p_f_years.1));
    t.push("p_f_years_hi", k(&|k| k.p_f_years.2));
    t.push("deagg_im_10", k(&|k| k.deaggregation[0]));
    t.push("deagg_im_50", k(&|k| k.deaggregation[1]));
    t.push("deagg_im_90", k(&|k| k.deaggregation[2]));
    t.push(
        "risk_rank",
        Column::U64(risks.iter().map(|r| r.and_then(|r| r.risk_rank)).collect()),
    );
}

/// The `capacities` table: one row per motion of the design stripe, with the design's axis
/// values (`grid`), `point` (the design), `case` (the realization or record), with a suite
/// `record` (the record's file name, from `suite`), `capacity` (g), `censored`, `resurrected`,
/// `runs`.
pub fn capacities_table(
    grid: &crate::reduce::common::Grid,
    c: &[(u64, u32, MotionCapacity)],
    suite: &[&str],
) -> Table {
    let mut t = Table::default();
    t.push("point", Column::U64(c.iter().map(|x| Some(x.0)).collect()));
    for a in 0..grid.n_axes() {
        t.push(
            crate::store::schema::column_name(grid.key(a)),
            Column::F64(c.iter().map(|x| grid.value(x.0, a)).collect()),
        );
    }
    t.push(
        "case",
        Column::U64(c.iter().map(|x| Some(u64::from(x.1))).collect()),
    );
    if !suite.is_empty() {
        let name = |case: u32| {
            suite
                .get(case as usize)
                .copied()
                .unwrap_or_default()
                .to_string()
        };
        t.push("record", Column::Str(c.iter().map(|x| name(x.1)).collect()));
    }
    t.push("capacity", Column::F64(c.iter().map(|x| x.2.0).collect()));
    let flag =
        |g: &dyn Fn(&MotionCapacity) -> bool| Column::Bool(c.iter().map(|x| g(&x.2)).collect());
    t.push("censored", flag(&|m| m.1));
    t.push("resurrected", flag(&|m| m.2));
    t.push(
        "runs",
        Column::U64(c.iter().map(|x| Some(u64::from(x.2.3))).collect()),
    );
    t
}
