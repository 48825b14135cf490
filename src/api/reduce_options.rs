//! What `impactsweep reduce` (and the Python binding's `reduce`) asks of a reduction, whatever
//! the scene: [`ReduceArgs`], and the study's reducer options with its overrides ([`options`]).

use std::path::PathBuf;

use crate::reduce::harmonic::analysis;
use crate::reduce::random::subset::DEFAULT_SUBSET_N;
use crate::reduce::{Options, free};
use crate::study::{DiSource, SafetyForm, Study};

/// `impactsweep reduce RUN_DIR`. Its default: the study's own settings, subset simulation of
/// [`DEFAULT_SUBSET_N`] samples per level where a random study's Monte Carlo saw few
/// exceedances.
#[derive(Clone, Debug)]
pub struct ReduceArgs {
    pub dir: PathBuf,
    /// Use the paper's small-C_n safety factor instead of Shigley's exact relation.
    pub paper_safety: bool,
    /// DI as the mean over cases instead of the ideal case.
    pub di_mean: bool,
    /// Overrides `[reliability].bootstrap`.
    pub bootstrap: Option<usize>,
    /// `(I, N)`: only shard `I` of `N` of a harmonic study's per-design analysis
    /// ([`crate::reduce::harmonic::analysis`]), written to `RUN_DIR/analysis/`; no report.
    pub shard: Option<(u64, u64)>,
    /// A harmonic study: the lines of the design grid its bifurcation curves are followed along.
    pub bifurcation_curves: analysis::CurveLines,
    /// A random study: subset simulation of this many samples per level for the designs whose
    /// realizations passed the threshold fewer than 10 times
    /// ([`crate::reduce::random::subset`]); `None`: Monte Carlo only.
    pub subset: Option<usize>,
    /// A random study: independent subset simulations per such design (at least 1), their mean
    /// its `p_f` and their spread its interval when more than 1. Default 1.
    pub subset_repeats: usize,
}

impl Default for ReduceArgs {
    fn default() -> Self {
        ReduceArgs {
            dir: PathBuf::new(),
            paper_safety: false,
            di_mean: false,
            bootstrap: None,
            shard: None,
            bifurcation_curves: analysis::CurveLines::default(),
            subset: Some(DEFAULT_SUBSET_N),
            subset_repeats: 1,
        }
    }
}

/// The study's choices with the command-line overrides.
pub fn options(study: &Study, args: &ReduceArgs) -> Options {
    options_over(free::options(study), args)
}

/// `base` (the study's choices, or a scene's) with the command-line overrides.
pub(crate) fn options_over(base: Options, args: &ReduceArgs) -> Options {
    let mut o = base;
    if args.paper_safety {
        o.safety_form = SafetyForm::Paper;
    }
    if args.di_mean {
        o.di_source = DiSource::Mean;
    }
    if let Some(b) = args.bootstrap {
        o.bootstrap = b;
    }
    o
}
