//! Issue 69: a random study's reduce streams its realizations. A design point whose
//! realizations pass the reducer's exact budget is reduced from counts, running moments and a
//! quantile sketch; on a study that crosses a low budget on purpose (a test hook), the streamed
//! reduce ranks the designs as the exact one does, gives the same `p_f` bits, and its quantiles
//! stay within the sketch's stated error; the streamed figures are the same bits however the
//! rows come (one part file at a time, all at once, a row at a time).

use std::path::Path;

use impactsweep::reduce::Summary;
use impactsweep::reduce::random::sketch::ALPHA;
use impactsweep::reduce::random::{self, RandomReducer, RandomSummary};
use impactsweep::sim::random::RealizationRecord;
use impactsweep::store::{self, RunRow};
use impactsweep::study::Study;
use impactsweep::sweep::{self, SweepOptions};

/// A structure in a Kanai–Tajimi ground motion's band (as tests/random_sweep.rs), with and
/// without a damper, two clearances and two intensities: 8 design points × 240 realizations of
/// 2 s, in blocks of 50 (each point spans five part files).
fn study(dir: &Path) -> Study {
    let path = dir.join("stream.toml");
    std::fs::write(
        &path,
        "[study]\nname = \"stream\"\nseed = 69\n[system]\nM = 1.0\nK = 246.7\nC = 0.628\n\
         e = 0.6\n[scene]\nkind = \"random\"\nspectrum = \"kanai-tajimi\"\nomega_g = 15.708\n\
         zeta_g = 0.6\nduration = 2\nthreshold = 0.011\nrealizations = 240\n\
         [sweep]\nm = [0.0, 0.05]\nd = [0.01, 0.03]\nS0 = [0.003, 0.004]\n\
         [run]\nchunk_realizations = 50\n",
    )
    .unwrap();
    Study::load(&path).unwrap()
}

/// Reduces `batches` of rows with the exact budget `budget`.
fn reduce(
    s: &Study,
    batches: &[Vec<RunRow<RealizationRecord>>],
    budget: usize,
) -> (Summary, RandomSummary) {
    let design = random::design_study(s);
    let mut r = RandomReducer::new(s, &design, random::options(&design)).with_budget(budget);
    for b in batches {
        r.push(b.clone());
    }
    r.finish(None)
}

fn ranks(s: &Summary) -> Vec<(u64, Option<u64>)> {
    s.points.iter().map(|p| (p.point, p.rank)).collect()
}

#[test]
fn the_streamed_reduce_ranks_as_the_exact_one() {
    let tmp = tempfile::tempdir().unwrap();
    let s = study(tmp.path());
    let out = tmp.path().join("out");
    sweep::run_study(&s, &out, &SweepOptions::default()).unwrap();
    let parts: Vec<Vec<RunRow<RealizationRecord>>> = store::part_files(&out.join("stream"))
        .unwrap()
        .iter()
        .map(|p| store::read_rows(p).unwrap())
        .collect();
    assert_eq!(parts.len(), 8 * 5);
    let (exact, exact_rs) = reduce(&s, &parts, usize::MAX);
    // 240 realizations a point against a budget of 64: every design streams.
    let (streamed, streamed_rs) = reduce(&s, &parts, 64);
    assert_eq!(ranks(&streamed), ranks(&exact));
    assert!(exact.points.iter().all(|p| p.rank.is_some()));
    let pfs: Vec<f64> = exact_rs.points.iter().map(|p| p.p_f).collect();
    assert!(
        pfs.iter().any(|&p| p != pfs[0]),
        "the designs must differ for the ranking to mean something: {pfs:?}"
    );
    // p_f, its interval and rms_x_mean: exact counts and sums, the same bits.
    assert_eq!(format!("{exact_rs:?}"), format!("{streamed_rs:?}"));
    for (e, x) in exact.points.iter().zip(&streamed.points) {
        let (a, b) = (&e.response, &x.response);
        assert_eq!(
            (e.n_ok, e.n_cases, e.outcomes),
            (x.n_ok, x.n_cases, x.outcomes)
        );
        assert_eq!((a.min, a.max), (b.min, b.max));
        assert_eq!(e.di.to_bits(), x.di.to_bits(), "p_s is a count over n");
        assert_eq!(a.mean.to_bits(), b.mean.to_bits(), "a running sum over n");
        assert!((a.sd / b.sd - 1.0).abs() < 1e-9);
        assert!((e.di_sd - x.di_sd).abs() < 1e-12);
        for (q, r) in [(a.q1, b.q1), (a.median, b.median), (a.q3, b.q3)] {
            assert!(((r - q) / q).abs() <= ALPHA, "{r} against {q}");
        }
    }
    // However the rows come, the streamed reduce is the same bits.
    let all: Vec<RunRow<RealizationRecord>> = parts.concat();
    let one_by_one: Vec<Vec<RunRow<RealizationRecord>>> =
        all.iter().map(|r| vec![r.clone()]).collect();
    for batches in [vec![all.clone()], one_by_one] {
        let (again, again_rs) = reduce(&s, &batches, 64);
        assert_eq!(
            format!("{:?}", again.points),
            format!("{:?}", streamed.points)
        );
        assert_eq!(format!("{again_rs:?}"), format!("{streamed_rs:?}"));
    }
}
