//! The reducer end to end: statistics on synthetic and simulated runs, zones, flags, the
//! output files (Parquet, CSV, report, charts) and the `plot waveform` command.

use std::path::Path;

use crate::common;

use impactsweep::api::reduce::{WaveformArgs, waveform_files, write_outputs};
use impactsweep::reduce::common::regions::NO_REGION;
use impactsweep::reduce::free::{self, reduce};
use impactsweep::reduce::testing::{FnIdeal, paper_study, row, simulate_chunks, study};
use impactsweep::reduce::{Class, JumpKind, Options, Quantity, Reducer, Run, Summary};
use impactsweep::sim::Outcome;
use impactsweep::study::Study;

/// Reduces simulated chunks (jumps located with the study's own simulator).
fn run(study: &Study, chunks: Vec<Vec<Run>>) -> Summary {
    reduce::<_, std::convert::Infallible>(study, free::options(study), chunks.into_iter().map(Ok))
        .unwrap()
}

/// Reduces synthetic chunks whose ideal case is `ideal(axis values) -> [xmax, DI]` (`None`:
/// there is none to simulate between the grid points).
fn run_synthetic(
    study: &Study,
    chunks: Vec<Vec<Run>>,
    ideal: impl Fn(&[f64]) -> Option<[f64; 2]> + Sync,
) -> Summary {
    let mut r = Reducer::new(study, free::options(study));
    for c in chunks {
        r.push(c);
    }
    r.finish_with(&FnIdeal(ideal))
}

fn no_ideal(_: &[f64]) -> Option<[f64; 2]> {
    None
}

/// The paper study as configs/paper.toml states it.
fn paper() -> Study {
    paper_study()
}

/// The ideal case of [`synthetic`]: xmax smooth (quadratic), `jump` added above e = 0.7043.
fn synthetic_ideal(e: f64, jump: f64) -> [f64; 2] {
    let smooth = 0.027 + 0.004 * (e - 0.5) * (e - 0.5);
    [
        smooth + if e > 0.7043 { jump } else { 0.0 },
        0.04 - 0.03 * (e - 0.5),
    ]
}

/// 41 points along e, 5 cases each (case c adds 1e-4 c to xmax: a spread of 1.6e-4 m), the
/// ideal case [`synthetic_ideal`].
fn synthetic(jump: f64) -> (Study, Summary) {
    let e: Vec<f64> = (0..41).map(|i| 0.5 + i as f64 * 0.01).collect();
    let s = study(vec![("e", e.clone())], 5);
    let mut rows = Vec::new();
    for (p, &ev) in e.iter().enumerate() {
        let [x, di] = synthetic_ideal(ev, jump);
        for c in 0..5u32 {
            rows.push(row(
                &s,
                p as u64,
                c,
                Outcome::Ok,
                x + 1e-4 * f64::from(c),
                di,
            ));
        }
    }
    let chunks: Vec<Vec<_>> = rows.chunks(5 * 7).map(|c| c.to_vec()).collect();
    let sum = run_synthetic(&s, chunks, |v| Some(synthetic_ideal(v[0], jump)));
    (s, sum)
}

#[test]
fn planted_step_is_located_within_its_tolerance() {
    let (_, sum) = synthetic(0.002);
    // The step, and no kink: a step is not a change of slope.
    assert_eq!(sum.jumps.len(), 1, "{:?}", sum.jumps);
    let j = &sum.jumps[0];
    assert_eq!((j.kind, j.quantity), (JumpKind::Step, Quantity::Response));
    assert!((j.location - 0.7043).abs() <= j.location_tol, "{j:?}");
    assert!(j.location_tol <= 0.01 / 200.0 + 1e-15, "{j:?}");
    assert!((j.size - 0.002).abs() < 1e-5, "{j:?}");
    assert_eq!((j.below, j.above), (20, 21));
    assert!(
        sum.jump_stats.sims > 0 && sum.jump_stats.sims <= 20,
        "{:?}",
        sum.jump_stats
    );
    // The points either side are around the jump: one zone.
    let jz: Vec<_> = sum
        .zones
        .iter()
        .filter(|z| z.class == Some(Class::AroundJump))
        .collect();
    assert_eq!(jz.len(), 1);
    assert_eq!(jz[0].ranges[0], (0.70, 0.71));
}

#[test]
fn planted_kink_is_located_at_the_apex() {
    // xmax rises gently (slightly curved) to e = 0.7031, then falls steeply: a kink, no step.
    let ideal = |e: f64| {
        let up = 0.027 + 0.01 * (e - 0.5) - 0.002 * (e - 0.5) * (e - 0.5);
        let x = if e <= 0.7031 {
            up
        } else {
            up - 0.05 * (e - 0.7031)
        };
        [x, 0.03 - 0.02 * (e - 0.5)]
    };
    let e: Vec<f64> = (0..41).map(|i| 0.5 + i as f64 * 0.01).collect();
    let s = study(vec![("e", e.clone())], 1);
    let rows: Vec<_> = e
        .iter()
        .enumerate()
        .map(|(p, &ev)| {
            let [x, di] = ideal(ev);
            row(&s, p as u64, 0, Outcome::Ok, x, di)
        })
        .collect();
    let sum = run_synthetic(&s, vec![rows], |v| Some(ideal(v[0])));
    assert_eq!(sum.jumps.len(), 1, "{:?}", sum.jumps);
    let j = &sum.jumps[0];
    assert_eq!((j.kind, j.quantity), (JumpKind::Kink, Quantity::Response));
    assert!((j.location - 0.7031).abs() <= j.location_tol, "{j:?}");
    assert!((j.size + 0.05).abs() < 1e-3, "{j:?}");
    assert_eq!((j.below, j.above), (20, 21));
}

#[test]
fn smooth_data_has_no_jump() {
    let (_, sum) = synthetic(0.0);
    assert!(sum.jumps.is_empty(), "{:?}", sum.jumps);
    assert!(sum.zones.iter().all(|z| z.class != Some(Class::AroundJump)));
}

#[test]
fn failed_outcomes_are_flagged_and_left_out() {
    let s = study(vec![("e", vec![0.6, 0.7, 0.8])], 4);
    let mut rows = Vec::new();
    for p in 0..3u64 {
        for c in 0..4u32 {
            let bad = p == 1 && c == 2;
            let (o, x) = if bad {
                (Outcome::EventCap, 1.0) // a wild xmax that must not be averaged in
            } else {
                (Outcome::Ok, 0.028 + 1e-4 * f64::from(c))
            };
            rows.push(row(&s, p, c, o, x, 0.02));
        }
    }
    let sum = run_synthetic(&s, vec![rows], no_ideal);
    let p1 = &sum.points[1];
    assert!(!p1.all_ok);
    assert_eq!((p1.n_cases, p1.n_ok), (4, 3));
    assert_eq!(p1.outcomes[3], 1, "event_cap counted");
    assert!(
        p1.response.mean < 0.03,
        "the failed run was averaged in: {}",
        p1.response.mean
    );
    assert!(sum.points[0].all_ok && sum.points[2].all_ok);
    assert_eq!(sum.outcome_totals[0], 11);
    assert_eq!(sum.outcome_totals[3], 1);
    // The flag reaches the CSV and the report.
    let dir = tempfile::tempdir().unwrap();
    write_outputs(&s, &sum, dir.path(), None).unwrap();
    let csv = std::fs::read_to_string(dir.path().join("summary.csv")).unwrap();
    let line = csv.lines().nth(2).unwrap();
    assert!(
        line.contains("false") && line.contains("event_cap:1"),
        "{line}"
    );
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(
        md.contains("1 design points have runs that did not end `ok`"),
        "{md}"
    );
}

#[test]
fn bootstrap_and_summary_are_deterministic_across_chunkings() {
    let s = paper();
    let chunks = simulate_chunks(&s);
    let a = run(&s, chunks.clone());
    // Same rows, one point per chunk, pushed in reverse order.
    let mut single: Vec<Vec<_>> = chunks
        .concat()
        .chunk_by(|x, y| x.point == y.point)
        .map(|c| c.to_vec())
        .collect();
    single.reverse();
    let b = run(&s, single);
    assert_eq!(a.points.len(), b.points.len());
    for (x, y) in a.points.iter().zip(&b.points) {
        assert_eq!(x.reliability_lo.to_bits(), y.reliability_lo.to_bits());
        assert_eq!(x.reliability_hi.to_bits(), y.reliability_hi.to_bits());
        assert_eq!(x.perfectibility.to_bits(), y.perfectibility.to_bits());
        assert_eq!(x.zone, y.zone);
    }
}

/// Decodes a PNG fully and returns its size; panics unless it decodes and has real content
/// (at least 2 % of its pixels not white).
fn png_size(path: &Path) -> (u32, u32) {
    let file = std::fs::File::open(path).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let px = info.color_type.samples();
    let pixels = &buf[..info.buffer_size()];
    let inked = pixels
        .chunks(px)
        .filter(|p| p.iter().take(3).any(|&c| c < 250))
        .count();
    let total = (info.width * info.height) as usize;
    assert!(
        inked * 50 > total,
        "{}: only {inked} of {total} pixels are not white",
        path.display()
    );
    (info.width, info.height)
}

#[test]
fn paper_study_reduces_to_zones_report_and_charts() {
    let s = paper();
    let sum = run(&s, simulate_chunks(&s));
    assert_eq!(sum.points.len(), 51);
    assert!(sum.points.iter().all(|p| p.all_ok && p.n_ok == 12));
    // Nominal design: e = 0.9 (the base system), 12 cases.
    let (np, rows) = sum.nominal.as_ref().unwrap();
    assert_eq!(*np, 45);
    assert_eq!(rows.len(), 12);
    // Ranks are a permutation of 1..=51; P of the best is the maximum.
    let mut ranks: Vec<u64> = sum.points.iter().map(|p| p.rank.unwrap()).collect();
    ranks.sort_unstable();
    assert_eq!(ranks, (1..=51).collect::<Vec<_>>());
    assert!(sum.points.iter().any(|p| p.pareto));
    // Three or more zones along e, and the two kinks of the first peak located near e = 0.74
    // (model.md §7: a non-smooth change near 0.74; the paper: a jump between 0.73 and 0.77)
    // and near e = 0.80 (issue 10).
    assert!(sum.zones.len() >= 3, "{:?}", sum.zones);
    let kinks: Vec<_> = sum
        .jumps
        .iter()
        .filter(|j| j.quantity == Quantity::Response && j.kind == JumpKind::Kink)
        .collect();
    assert_eq!(kinks.len(), 2, "{:?}", sum.jumps);
    assert!((kinks[0].location - 0.7457).abs() < 1e-3, "{:?}", kinks[0]);
    assert!((kinks[1].location - 0.7985).abs() < 1e-3, "{:?}", kinks[1]);
    assert!(kinks.iter().all(|j| j.location_tol <= 0.01 / 200.0 + 1e-12));
    let out = std::env::var_os("IMPACTSWEEP_KEEP_CHARTS").map(std::path::PathBuf::from);
    let tmp = tempfile::tempdir().unwrap();
    let dir = out.as_deref().unwrap_or(tmp.path());
    write_outputs(&s, &sum, dir, None).unwrap();
    for stem in ["di", "design_chart", "xmax_spread"] {
        // The chart's data beside it: the summary rows it draws.
        let points = common::chart_rows_are_summary_rows(
            &dir.join(format!("{stem}.csv")),
            &dir.join("summary.csv"),
        );
        assert_eq!(points, (0..51).collect::<Vec<u64>>(), "{stem}.csv");
        let svg = dir.join(format!("{stem}.svg"));
        let png = dir.join(format!("{stem}.png"));
        let svg_len = std::fs::metadata(&svg).unwrap().len();
        let png_len = std::fs::metadata(&png).unwrap().len();
        assert!(svg_len > 5_000, "{stem}.svg is {svg_len} bytes");
        assert!(png_len > 20_000, "{stem}.png is {png_len} bytes");
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.starts_with("<svg") && text.contains("</svg>"));
    }
    assert_eq!(png_size(&dir.join("design_chart.png")), (1000, 820));
    // The design chart gives R its own panel and axis, with the r_min threshold, apart from
    // mu_n and DI.
    let svg = std::fs::read_to_string(dir.join("design_chart.svg")).unwrap();
    for needle in [
        "reliability R (–)",
        "r_min = 0.98 (reliable: interval at or above)",
        "95 % bootstrap interval of R",
        "safety factor μn (–)",
        "DI (m/s)",
        "zone: strong damping, reliable",
    ] {
        assert!(svg.contains(needle), "design_chart.svg lacks {needle}");
    }
    assert_eq!(png_size(&dir.join("di.png")), (900, 560));
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for needle in [
        "## Zones (Table III)",
        "## Top 10",
        "## Pareto set",
        "Table II",
        "## Recommended design",
        "| e | kink | xmax | 0.745",
        "| e | kink | xmax | 0.798",
    ] {
        assert!(md.contains(needle), "report lacks {needle}");
    }
    // Parquet files start and end with the magic.
    for f in ["summary.parquet", "zones.parquet"] {
        let b = std::fs::read(dir.join(f)).unwrap();
        assert!(b.starts_with(b"PAR1") && b.ends_with(b"PAR1"), "{f}");
    }
    // The outputs are deterministic: a second write gives the same bytes.
    let again = tempfile::tempdir().unwrap();
    write_outputs(&s, &sum, again.path(), None).unwrap();
    for f in [
        "summary.parquet",
        "summary.csv",
        "zones.parquet",
        "report.md",
        "design_chart.svg",
        "design_chart.png",
    ] {
        assert_eq!(
            std::fs::read(dir.join(f)).unwrap(),
            std::fs::read(again.path().join(f)).unwrap(),
            "{f} differs between two writes"
        );
    }
}

#[test]
fn two_axes_give_a_map() {
    let mut s = paper();
    s.axes = vec![
        impactsweep::study::Axis {
            key: "m".into(),
            values: vec![0.015, 0.02, 0.025],
        },
        impactsweep::study::Axis {
            key: "e".into(),
            values: (0..8).map(|i| 0.5 + 0.05 * i as f64).collect(),
        },
    ];
    let sum = run(&s, simulate_chunks(&s));
    assert_eq!(sum.points.len(), 24);
    assert!(sum.points.iter().all(|p| p.zone != NO_REGION));
    let tmp = tempfile::tempdir().unwrap();
    let keep = std::env::var_os("IMPACTSWEEP_KEEP_CHARTS").map(|d| Path::new(&d).join("map"));
    let dir = keep.as_deref().unwrap_or(tmp.path());
    let files = write_outputs(&s, &sum, dir, None).unwrap();
    for stem in [
        "perfectibility_map_mass_inner_e",
        "zone_map_mass_inner_e",
        "design_chart_mass_inner",
        "design_chart_e",
    ] {
        assert!(
            files.iter().any(|f| f.ends_with(format!("{stem}.png"))),
            "{stem}"
        );
        assert!(
            std::fs::metadata(dir.join(format!("{stem}.png")))
                .unwrap()
                .len()
                > 10_000
        );
    }
}

#[test]
fn declared_zones_override() {
    let mut s = paper();
    s.zones.declared = vec![
        impactsweep::study::DeclaredZone {
            name: "I".into(),
            axis: "e".into(),
            from: 0.45,
            to: 0.70,
        },
        impactsweep::study::DeclaredZone {
            name: "II".into(),
            axis: "e".into(),
            from: 0.70,
            to: 0.77,
        },
        impactsweep::study::DeclaredZone {
            name: "III".into(),
            axis: "e".into(),
            from: 0.77,
            to: 0.90,
        },
    ];
    let sum = run(&s, simulate_chunks(&s));
    let names: Vec<&str> = sum.zones.iter().map(|z| z.name.as_str()).collect();
    assert_eq!(names, ["I", "II", "III"]);
    assert_eq!(sum.zones[0].n_points, 26); // 0.45..=0.70, 0.70 goes to the first zone
    assert_eq!(sum.zones[1].n_points, 7); // 0.71..=0.77
    assert_eq!(sum.zones[2].n_points, 13); // 0.78..=0.90
    let best = sum
        .zones
        .iter()
        .map(|z| z.perfectibility)
        .fold(f64::MIN, f64::max);
    assert!(best <= 100.0 + 1e-9);
    assert!(
        sum.points
            .iter()
            .filter(|p| sum.values(p)[0] > 0.905)
            .all(|p| p.zone == NO_REGION)
    );
}

#[test]
fn waveform_command_draws_both_figures() {
    let dir = tempfile::tempdir().unwrap();
    let files = waveform_files(&WaveformArgs {
        sets: vec![],
        out: dir.path().to_path_buf(),
        e: vec![0.45, 0.9],
        t_end: 0.3,
    })
    .unwrap();
    assert_eq!(files.len(), 6);
    assert_eq!(png_size(&dir.path().join("waveform_e.png")), (1000, 820));
    // Its data: trace, t, x; the two traces over the whole time.
    let csv = std::fs::read_to_string(dir.path().join("waveform_e.csv")).unwrap();
    assert!(csv.starts_with("trace,t,x\n0,0,0\n"), "{}", &csv[..40]);
    assert!(csv.lines().any(|l| l.starts_with("1,")));
    assert_eq!(
        png_size(&dir.path().join("waveform_damper.png")),
        (1000, 520)
    );
    assert!(
        std::fs::metadata(dir.path().join("waveform_e.svg"))
            .unwrap()
            .len()
            > 20_000
    );
    let bad = waveform_files(&WaveformArgs {
        sets: vec![],
        out: dir.path().to_path_buf(),
        e: vec![0.45, 1.3],
        t_end: 0.3,
    });
    assert!(format!("{:#}", bad.unwrap_err()).contains("e = 1.3"));
}

/// Throughput of the reducer alone on 10^6 synthetic runs (83,334 points × 12 cases) pushed in
/// chunks of 65,532 runs, as the store's part files would deliver them. Not a timed assert:
/// run with `cargo test --release --test integration -- --ignored --nocapture reduce::million`
/// and read the figure (BENCHMARKS.md).
#[test]
#[ignore]
fn million_runs_throughput() {
    let n_points = 83_334u64;
    let e: Vec<f64> = (0..n_points)
        .map(|i| 0.45 + 0.5 * i as f64 / n_points as f64)
        .collect();
    let mut s = study(vec![("e", e.clone())], 12);
    if let Some(b) = std::env::var("IMPACTSWEEP_BOOTSTRAP")
        .ok()
        .and_then(|b| b.parse().ok())
    {
        s.reliability.bootstrap = b;
    }
    let start = std::time::Instant::now();
    let mut r = impactsweep::reduce::Reducer::new(&s, free::options(&s));
    let per_chunk = 5_461u64;
    let mut p0 = 0;
    while p0 < n_points {
        let p1 = (p0 + per_chunk).min(n_points);
        let mut rows = Vec::with_capacity(((p1 - p0) * 12) as usize);
        for p in p0..p1 {
            for c in 0..12u32 {
                let x = 0.028 + 1e-4 * f64::from(c) + 1e-3 * e[p as usize];
                rows.push(row(&s, p, c, Outcome::Ok, x, 0.02 - 0.01 * e[p as usize]));
            }
        }
        r.push(rows);
        p0 = p1;
    }
    let sum = free::finish(r);
    let dir = tempfile::tempdir().unwrap();
    let reduced = start.elapsed();
    write_outputs(&s, &sum, dir.path(), None).unwrap();
    eprintln!(
        "reduced {} points from 10^6 runs in {:.2?} (incl. building the rows); outputs in {:.2?} more",
        sum.points.len(),
        reduced,
        start.elapsed() - reduced
    );
}

#[test]
fn cli_plot_waveform_writes_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .args(["plot", "waveform", "--out"])
        .arg(dir.path())
        .args(["--e", "0.5", "0.8", "--t-end", "0.2"])
        .assert()
        .success()
        .stdout(predicates::str::contains("waveform_e.png"));
    for f in [
        "waveform_damper.svg",
        "waveform_damper.png",
        "waveform_e.svg",
        "waveform_e.png",
    ] {
        assert!(
            std::fs::metadata(dir.path().join(f)).unwrap().len() > 10_000,
            "{f}"
        );
    }
}

#[test]
fn cli_reduce_names_the_missing_study_file() {
    let dir = tempfile::tempdir().unwrap();
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("reduce")
        .arg(dir.path().join("nothing"))
        .assert()
        .code(2)
        .stderr(predicates::str::contains("study.toml"));
}

#[test]
fn paper_safety_form_and_mean_di_are_options() {
    use impactsweep::reduce::common::stats;
    use impactsweep::study::{DiSource, SafetyForm};
    let s = paper();
    let chunks = simulate_chunks(&s);
    let exact = run(&s, chunks.clone());
    let opts = Options {
        safety_form: SafetyForm::Paper,
        di_source: DiSource::Mean,
        ..free::options(&s)
    };
    let paper = reduce::<_, std::convert::Infallible>(&s, opts, chunks.clone().into_iter().map(Ok))
        .unwrap();
    for (a, b) in exact.points.iter().zip(&paper.points) {
        assert_eq!(a.reliability.to_bits(), b.reliability.to_bits());
        let want = stats::safety_factor_paper(a.reliability_index, a.cn);
        assert!((b.safety_factor - want).abs() < 1e-12);
        assert!((a.safety_factor - b.safety_factor).abs() > 1e-6);
    }
    // Mean DI over the cases at the nominal point, from the runs themselves.
    let rows: Vec<_> = chunks
        .concat()
        .into_iter()
        .filter(|r| r.point == 45)
        .collect();
    let mean = rows.iter().map(|r| r.di).sum::<f64>() / rows.len() as f64;
    assert!((paper.points[45].di - mean).abs() < 1e-15);
    let ideal = rows.iter().find(|r| r.ideal).unwrap().di;
    assert_eq!(exact.points[45].di, ideal);
}

#[test]
fn audit_reaches_the_report_as_a_typed_value() {
    use impactsweep::accuracy::{Audit, ErrorStats};
    use impactsweep::api::reduce::read_audit;
    let dir = tempfile::tempdir().unwrap();
    assert!(read_audit(dir.path()).unwrap().is_none());
    let e = |max: f64| ErrorStats {
        n: 4,
        max,
        median: max / 10.0,
    };
    let audit = Audit {
        points: vec![3, 17, 29, 40],
        solver: "exact".into(),
        knob: "tol".into(),
        knob_value: 1e-12,
        tol: 1e-12,
        reference: "exact, tol = 1e-14".into(),
        xmax: e(1.5e-13),
        t1: e(2.5e-13),
        di: e(7.5e-12),
        outcome_changed: 0,
        impacts_changed: 1,
    };
    let s = paper();
    let sum = run(&s, simulate_chunks(&s));
    write_outputs(&s, &sum, dir.path(), Some(&audit)).unwrap();
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    for needle in [
        "## Accuracy audit",
        "4 design points (their ideal case) re-run against the reference (exact, tol = 1e-14)",
        "| xmax | 1.50e-13 | 1.50e-14 | 4 |",
        "| DI | 7.50e-12 | 7.50e-13 | 4 |",
        "impact count in 1",
    ] {
        assert!(md.contains(needle), "report lacks {needle}");
    }
}

#[test]
fn the_confidence_level_in_the_text_follows_the_study() {
    let mut s = paper();
    s.reliability.confidence = 0.9;
    s.reliability.bootstrap = 200;
    let sum = run(&s, simulate_chunks(&s));
    let md = impactsweep::report::markdown::report(&s, &sum, &[], None);
    assert!(
        md.contains("90 % interval") && md.contains("90 % confidence"),
        "{md}"
    );
    for stale in ["95 % interval", "95 % confidence", "(95 %)"] {
        assert!(!md.contains(stale), "{stale} in {md}");
    }
}

#[test]
fn many_points_draw_bands_and_stay_small() {
    // 2000 design points: lines and bands instead of markers and boxes, at most 30 jump lines.
    // A saw tooth of 39 steps (more than the chart marks) halfway between grid points.
    let saw = |e: f64| {
        let k = ((e - 0.45) * 3998.0 + 0.5) / 50.0;
        0.028 + 2e-3 * (k.floor() as i64 % 2) as f64 + 1e-3 * e
    };
    let e: Vec<f64> = (0..2000).map(|i| 0.45 + 0.5 * i as f64 / 1999.0).collect();
    let s = study(vec![("e", e.clone())], 4);
    let mut rows = Vec::new();
    for (p, &ev) in e.iter().enumerate() {
        for c in 0..4u32 {
            let x = saw(ev) + 1e-4 * f64::from(c);
            rows.push(row(&s, p as u64, c, Outcome::Ok, x, 0.03 - 0.02 * ev));
        }
    }
    let sum = run_synthetic(&s, vec![rows], |v| Some([saw(v[0]), 0.03 - 0.02 * v[0]]));
    assert!(sum.jumps.len() > 30, "{}", sum.jumps.len());
    let tmp = tempfile::tempdir().unwrap();
    let keep = std::env::var_os("IMPACTSWEEP_KEEP_CHARTS").map(|d| Path::new(&d).join("many"));
    let dir = keep.as_deref().unwrap_or(tmp.path());
    write_outputs(&s, &sum, dir, None).unwrap();
    for stem in ["di", "design_chart", "xmax_spread"] {
        let svg = std::fs::metadata(dir.join(format!("{stem}.svg")))
            .unwrap()
            .len();
        assert!(svg < 1_500_000, "{stem}.svg is {svg} bytes");
        assert!(png_size(&dir.join(format!("{stem}.png"))).0 >= 900);
    }
}

#[test]
fn command_line_flags_override_the_study() {
    use impactsweep::api::reduce::{ReduceArgs, options};
    use impactsweep::study::{DiSource, SafetyForm};
    let s = paper();
    let o = options(&s, &ReduceArgs::default());
    assert_eq!(
        (o.safety_form, o.di_source, o.bootstrap),
        (SafetyForm::Exact, DiSource::Ideal, 2000)
    );
    let o = options(
        &s,
        &ReduceArgs {
            paper_safety: true,
            di_mean: true,
            bootstrap: Some(1),
            ..Default::default()
        },
    );
    assert_eq!(
        (o.safety_form, o.di_source, o.bootstrap),
        (SafetyForm::Paper, DiSource::Mean, 1)
    );
}

#[test]
fn a_study_without_axes_reduces_to_one_point() {
    let s = study(vec![], 3);
    let rows: Vec<_> = (0..3u32)
        .map(|c| row(&s, 0, c, Outcome::Ok, 0.028 + 1e-4 * f64::from(c), 0.02))
        .collect();
    let sum = run_synthetic(&s, vec![rows], no_ideal);
    assert_eq!(sum.points.len(), 1);
    assert_eq!(sum.points[0].rank, Some(1));
    assert_eq!(sum.zones.len(), 1);
    let dir = tempfile::tempdir().unwrap();
    write_outputs(&s, &sum, dir.path(), None).unwrap();
    assert!(dir.path().join("report.md").exists());
}

#[test]
fn summary_parquet_reads_back_with_the_summary_values() {
    use arrow_array::{Array, BooleanArray, Float64Array, StringArray, UInt64Array};
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    let s = paper();
    let sum = run(&s, simulate_chunks(&s));
    let dir = tempfile::tempdir().unwrap();
    write_outputs(&s, &sum, dir.path(), None).unwrap();
    let file = std::fs::File::open(dir.path().join("summary.parquet")).unwrap();
    let reader = ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap()
        .build()
        .unwrap();
    let batches: Vec<_> = reader.map(|b| b.unwrap()).collect();
    assert_eq!(batches.len(), 1);
    let b = &batches[0];
    assert_eq!(b.num_rows(), 51);
    let names: Vec<String> = b
        .schema()
        .fields()
        .iter()
        .map(|f| f.name().clone())
        .collect();
    for col in [
        "e",
        "n",
        "xmax_mean",
        "xmax_sd",
        "stress_mean",
        "stress_sd",
        "reliability",
        "reliability_lo",
        "reliability_hi",
        "safety_factor",
        "di",
        "perfectibility",
        "rank",
        "pareto",
        "zone",
        "ad_stat",
        "ad_p",
        "n_ok",
        "all_ok",
    ] {
        assert!(
            names.iter().any(|n| n == col),
            "summary.parquet lacks {col}: {names:?}"
        );
    }
    let col = |name: &str| {
        b.column(names.iter().position(|n| n == name).unwrap())
            .clone()
    };
    let f64s = |name: &str| {
        col(name)
            .as_any()
            .downcast_ref::<Float64Array>()
            .unwrap()
            .values()
            .to_vec()
    };
    let e = f64s("e");
    let r = f64s("reliability");
    let rank = col("rank");
    let rank = rank.as_any().downcast_ref::<UInt64Array>().unwrap();
    let pareto = col("pareto");
    let pareto = pareto.as_any().downcast_ref::<BooleanArray>().unwrap();
    let zone = col("zone");
    let zone = zone.as_any().downcast_ref::<StringArray>().unwrap();
    for (i, p) in sum.points.iter().enumerate() {
        assert_eq!(e[i].to_bits(), sum.values(p)[0].to_bits());
        assert_eq!(r[i].to_bits(), p.reliability.to_bits());
        assert_eq!(Some(rank.value(i)), p.rank);
        assert_eq!(pareto.value(i), p.pareto);
        assert_eq!(zone.value(i), sum.zone_name(p));
    }
    let zfile = std::fs::File::open(dir.path().join("zones.parquet")).unwrap();
    let zrows: usize = ParquetRecordBatchReaderBuilder::try_new(zfile)
        .unwrap()
        .build()
        .unwrap()
        .map(|b| b.unwrap().num_rows())
        .sum();
    assert_eq!(zrows, sum.zones.len());
}

#[test]
fn a_point_whose_ideal_run_failed_has_no_di_and_no_rank() {
    let s = study(vec![("e", vec![0.5, 0.6, 0.7, 0.8])], 3);
    let mut rows = Vec::new();
    for p in 0..4u64 {
        for c in 0..3u32 {
            let o = if p == 2 && c == 0 {
                Outcome::NoSecondPeak
            } else {
                Outcome::Ok
            };
            rows.push(row(
                &s,
                p,
                c,
                o,
                0.028 + 1e-4 * f64::from(c),
                0.02 + 1e-3 * p as f64,
            ));
        }
    }
    let sum = run_synthetic(&s, vec![rows], no_ideal);
    let p2 = &sum.points[2];
    assert!(!p2.all_ok && p2.di.is_nan() && p2.rank.is_none() && !p2.pareto);
    assert!(
        p2.reliability.is_finite(),
        "R still comes from the two ok cases"
    );
    assert_eq!(p2.outcomes[1], 1);
    let ranks: Vec<Option<u64>> = sum.points.iter().map(|p| p.rank).collect();
    assert_eq!(ranks, vec![Some(3), Some(2), None, Some(1)]);
    assert_eq!(sum.zone_of(p2).unwrap().class, Some(Class::NoData));
}

/// The real pipeline through the binary: `run` a small study to Parquet, `reduce` it, and the
/// outputs appear in the run directory, the audit of the manifest in the report.
#[test]
fn cli_run_then_reduce() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("tiny.toml");
    let text = std::fs::read_to_string("configs/paper.toml")
        .unwrap()
        .replace("name = \"paper\"", "name = \"tiny\"")
        .replace(
            "e = { start = 0.45, stop = 0.95, step = 0.01 }",
            "e = { start = 0.6, stop = 0.9, step = 0.05 }",
        );
    assert!(text.contains("name = \"tiny\"") && text.contains("stop = 0.9, step = 0.05"));
    std::fs::write(&study, text).unwrap();
    let out = dir.path().join("out");
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("run")
        .arg(&study)
        .arg("--out")
        .arg(&out)
        .args(["--quiet", "--audit", "2", "--chunk-points", "3"])
        .assert()
        .success();
    let run_dir = out.join("tiny");
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("reduce")
        .arg(&run_dir)
        .assert()
        .success()
        .stdout(predicates::str::contains("reduced 7 design points"));
    for f in [
        "summary.parquet",
        "summary.csv",
        "zones.parquet",
        "zones.csv",
        "jumps.csv",
        "report.md",
        "design_chart.svg",
        "design_chart.png",
    ] {
        assert!(run_dir.join(f).exists(), "{f} missing");
    }
    let csv = std::fs::read_to_string(run_dir.join("summary.csv")).unwrap();
    assert_eq!(csv.lines().count(), 8, "{csv}");
    let md = std::fs::read_to_string(run_dir.join("report.md")).unwrap();
    assert!(md.contains("7 of 7 design points reduced (84 runs"), "{md}");
    assert!(md.contains("## Accuracy audit"), "{md}");
    png_size(&run_dir.join("design_chart.png"));
}

/// pyarrow and polars read `summary.parquet` and `zones.parquet` and agree with `summary.csv`.
/// The interpreter is `$IMPACTSWEEP_PYTHON`, else the repository's `.venv/bin/python`
/// (`scripts/setup-python.sh`).
#[test]
fn pyarrow_and_polars_read_the_summary() {
    let python = std::env::var_os("IMPACTSWEEP_PYTHON")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join(".venv/bin/python"));
    assert!(
        python.exists(),
        "no Python: set IMPACTSWEEP_PYTHON or run scripts/setup-python.sh ({})",
        python.display()
    );
    let s = paper();
    let sum = run(&s, simulate_chunks(&s));
    let dir = tempfile::tempdir().unwrap();
    write_outputs(&s, &sum, dir.path(), None).unwrap();
    let script = r#"
import sys, csv, math
import pyarrow.parquet as pq, polars as pl
d = sys.argv[1]
t = pq.read_table(f"{d}/summary.parquet")
assert t.num_rows == 51, t.num_rows
meta = pq.read_metadata(f"{d}/summary.parquet").metadata
assert meta[b"impactsweep.table"] == b"summary", meta
rows = list(csv.DictReader(open(f"{d}/summary.csv")))
assert [f.name for f in t.schema] == list(rows[0].keys())
p = pl.read_parquet(f"{d}/summary.parquet")
for col in ["e", "reliability", "reliability_lo", "reliability_hi", "safety_factor", "di", "perfectibility"]:
    a = t.column(col).to_pylist()
    b = p[col].to_list()
    c = [float(r[col]) for r in rows]
    assert a == b == c, col
assert t.column("rank").to_pylist() == [int(r["rank"]) for r in rows]
assert str(t.schema.field("rank").type) == "uint64" and str(t.schema.field("pareto").type) == "bool"
z = pq.read_table(f"{d}/zones.parquet")
assert z.num_rows == len(list(csv.DictReader(open(f"{d}/zones.csv"))))
print("ok", t.num_rows, z.num_rows)
"#;
    let out = std::process::Command::new(&python)
        .arg("-c")
        .arg(script)
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.starts_with("ok 51 "), "{stdout}");
}

/// Issue 25: the smallest study a newcomer writes (a name and one swept axis, no strength) runs
/// and reduces to a report that says at its top what R needs, zones and a ranking by DI, and no
/// `NaN` or `inf` in any text file it writes.
#[test]
fn issue_25_a_study_without_strength_reduces_by_di_without_nan() {
    let dir = tempfile::tempdir().unwrap();
    let study = dir.path().join("tiny.toml");
    std::fs::write(
        &study,
        "[study]\nname = \"tiny\"\n[sweep]\ne = {start = 0.5, stop = 0.9, step = 0.1}\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    for args in [
        vec![
            "run".into(),
            study.display().to_string(),
            "--out".into(),
            out.display().to_string(),
        ],
        vec!["reduce".into(), out.join("tiny").display().to_string()],
    ] {
        assert_cmd::Command::cargo_bin("impactsweep")
            .unwrap()
            .args(&args)
            .assert()
            .success();
    }
    let run = out.join("tiny");
    let md = std::fs::read_to_string(run.join("report.md")).unwrap();
    assert!(
        md.contains("Reliability not computed: the study gives no strength")
            && md.contains("strength_mean = ")
            && md.contains("strength_sd = "),
        "{md}"
    );
    assert!(md.contains("reliability not computed"), "class names");
    assert!(!md.contains("| no data |"), "{md}");
    // The ranking by DI: every design ranked, perfectibility 100 at the best.
    let top: Vec<&str> = md
        .split("## Top 10 by perfectibility")
        .nth(1)
        .unwrap()
        .split("\n## ")
        .next()
        .unwrap()
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| rank"))
        .collect();
    assert_eq!(top.len(), 5, "{md}");
    assert!(top[0].contains("| 100.00 |"), "{}", top[0]);
    let word = |text: &str, w: &str| {
        text.match_indices(w).any(|(i, _)| {
            let before = text[..i].chars().next_back();
            let after = text[i + w.len()..].chars().next();
            !before.is_some_and(char::is_alphanumeric) && !after.is_some_and(char::is_alphanumeric)
        })
    };
    let mut checked = 0;
    for e in std::fs::read_dir(&run).unwrap() {
        let p = e.unwrap().path();
        let ext = p.extension().and_then(|x| x.to_str()).unwrap_or("");
        if !["md", "html", "csv", "svg", "json", "toml"].contains(&ext) {
            continue;
        }
        let text = std::fs::read_to_string(&p).unwrap();
        for w in ["NaN", "inf", "-inf"] {
            assert!(!word(&text, w), "{} contains {w}", p.display());
        }
        checked += 1;
    }
    assert!(checked >= 8, "{checked} text files");
}
