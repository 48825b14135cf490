//! The census of several units in a harmonic study (issue 68): every run of a study of several
//! units takes the census of several units from the state its run from rest ended in, and
//! stores its attractors.
//!
//! * Through the command line, a two-unit study's attractor rows equal the library's
//!   `census_units` from each run's end state (`simulate_harmonic_ends`), then the race for the
//!   design lives along each case's curve (`race_units`), to `1e-12`.
//!   Each row's whole section state is stored (`section_units`), a periodic orbit's its fixed
//!   point.
//! * The same rows and records, bit for bit, on 1 and 2 threads and with another chunk size.
//! * A one-unit study stores the same bytes whether or not it says `units = 1`.
//! * `impactsweep simulate` of several units takes the same census: its JSON equals the record
//!   a one-point study of study seed 0 stores, bit for bit.

use std::path::{Path, PathBuf};

use impactsweep::orbits::attractors::{AttractorRow, RunId, RunWindow, SteadyKind};
use impactsweep::orbits::continuation::End;
use impactsweep::orbits::map::Forcing;
use impactsweep::orbits::race::{Serves, race_units};
use impactsweep::orbits::several::end_section;
use impactsweep::orbits::units::map::distance;
use impactsweep::orbits::units::{UnitsCensusSettings, census_units, eval};
use impactsweep::plan::Plan;
use impactsweep::sim::harmonic::simulate_harmonic_ends;
use impactsweep::sim::{Harmonic, HarmonicRecord, NoProbe, Scene};
use impactsweep::store::{self, RunRow};
use impactsweep::study::{CensusKind, Study};

/// Two units of 10 g with clearances 8 and 12 mm (the orbits tests' two units,
/// tests/units_orbits.rs) near resonance, 4 starts, and the cases of a clearance tolerance.
const TWO_UNITS: &str = "[study]\nname = \"two\"\nseed = 11\n\
     [system]\nm = 0.02\nd = 0.01\ne = 0.7\nC = 1.0\nv0 = 0.0\nunits = 2\nd_spread = 0.2\n\
     [scene]\nkind = \"harmonic\"\nF0 = 0.5\nstarts = 4\nn_meas = 50\nn_trans_max = 600\n\
     [sweep]\nr = [1.0, 1.1]\n\
     [perturb]\ndd = [0.001]\n";

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

fn run(study: &Path, out: &Path, args: &[&str]) {
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("run")
        .arg(study)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .args(args)
        .assert()
        .success();
}

fn records(dir: &Path) -> Vec<RunRow<HarmonicRecord>> {
    let mut rows: Vec<_> = store::part_files(dir)
        .unwrap()
        .iter()
        .flat_map(|p| store::read_rows::<HarmonicRecord>(p).unwrap())
        .collect();
    rows.sort_by_key(|r| r.point_id);
    rows
}

fn attractors(dir: &Path) -> Vec<AttractorRow> {
    let mut rows = Vec::new();
    for p in store::part_files(dir).unwrap() {
        let side = store::attractors::attractors_part_path(dir, store::part_chunk(&p).unwrap());
        rows.extend(store::attractors::read_part(&side).unwrap());
    }
    rows.sort_by_key(|a| (a.run.point_id, a.attractor));
    rows
}

/// The run of design point `point`, case `case` of a harmonic study of several units from rest,
/// with its scene, the census's forcing and its end state (the census's start 0).
fn run_end(
    study: &Study,
    plan: &Plan,
    point: u64,
    case: u32,
) -> (HarmonicRecord, Harmonic, Forcing, Vec<f64>) {
    let spec = plan.run(point, case);
    let Scene::Harmonic(scene) = spec.scene else {
        panic!("not harmonic")
    };
    let (rec, units) = simulate_harmonic_ends(
        &spec.system,
        &study.solver,
        &study.request,
        &scene,
        None,
        &mut NoProbe,
    );
    let f = Forcing {
        sys: spec.system,
        F0: scene.F0,
        omega: rec.omega,
        settings: study.solver,
    };
    let s0 = end_section(&spec.system, &rec, &units);
    (rec, scene, f, s0)
}

fn close(a: f64, b: f64, what: &str) {
    let ok = (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1e-3);
    assert!(ok, "{what}: {a:e} against {b:e}");
}

#[test]
fn a_two_unit_study_stores_the_census_of_each_runs_end_state() {
    let tmp = tempfile::tempdir().unwrap();
    let path = write(tmp.path(), "two", TWO_UNITS);
    let study = Study::load(&path).unwrap();
    assert_eq!(study.census_kind(), CensusKind::Units);
    run(&path, tmp.path(), &["--threads", "1"]);
    let dir = tmp.path().join("two");
    let (recs, stored) = (records(&dir), attractors(&dir));
    assert_eq!(recs.len(), 4);
    let plan = Plan::new(&study);
    // Each run's census from its end state, as the library makes it.
    let mut runs = Vec::new();
    for row in &recs {
        let (rec, scene, f, s0) = run_end(&study, &plan, row.point, row.case);
        assert_eq!(rec.amplitude.to_bits(), row.record.amplitude.to_bits());
        assert_eq!(s0.len(), 6);
        let c = census_units(
            &f,
            &s0,
            &UnitsCensusSettings {
                starts: 4,
                max_periods: 600,
                seed: 11,
                point: row.point,
                ..UnitsCensusSettings::default()
            },
        );
        runs.push((row, rec, f, s0, scene, c));
    }
    // The race for the design lives along each case's curve (the ideal case's serves the
    // curve, a perturbed case's its peak).
    for case in [0, 1] {
        let curve: Vec<usize> = (0..runs.len())
            .filter(|&i| runs[i].0.case == case)
            .collect();
        assert_eq!(curve.len(), 2);
        let points: Vec<_> = curve
            .iter()
            .map(|&i| Some((runs[i].2.clone(), runs[i].4)))
            .collect();
        let mut censuses: Vec<_> = curve.iter().map(|&i| Some(runs[i].5.clone())).collect();
        let serves = if runs[curve[0]].0.ideal {
            Serves::Curve
        } else {
            Serves::Peak
        };
        race_units(&points, &mut censuses, serves);
        for (&i, c) in curve.iter().zip(censuses) {
            runs[i].5 = c.unwrap();
        }
    }
    for (row, rec, f, s0, _, c) in &runs {
        let id = RunId {
            point_id: row.point_id,
            point: row.point,
            case: row.case,
            ideal: row.ideal,
            r: rec.r,
            omega: rec.omega,
            F0: rec.F0,
        };
        let own = RunWindow {
            amplitude: rec.amplitude,
            n_meas: rec.n_meas,
        };
        let want = AttractorRow::of_units_census(id, f, c, s0, own);
        let got: Vec<&AttractorRow> = stored
            .iter()
            .filter(|a| a.run.point_id == row.point_id)
            .collect();
        assert_eq!(got.len(), want.len(), "run {}", row.point_id);
        assert!(!want.is_empty());
        for (g, w) in got.iter().zip(&want) {
            assert_eq!((g.kind, g.period, g.starts), (w.kind, w.period, w.starts));
            close(g.amplitude, w.amplitude, "amplitude");
            close(g.window_amplitude, w.window_amplitude, "window amplitude");
            close(g.life_lo, w.life_lo, "life_lo");
            close(g.life_hi, w.life_hi, "life_hi");
            assert_eq!(g.measured_periods, w.measured_periods);
            close(g.multiplier_max, w.multiplier_max, "multiplier_max");
            close(g.lyapunov, w.lyapunov, "lyapunov");
            close(g.basin_share, w.basin_share, "basin share");
            for k in 0..4 {
                close(g.section[k], w.section[k], "section");
            }
            // The whole state (`section_units`): stored as the library made it, and a periodic
            // orbit's is its fixed point, so `reduce` can run the motion again from it.
            assert_eq!(g.section_units.len(), 6, "2 + 2N components");
            for (a, b) in g.section_units.iter().zip(&w.section_units) {
                close(*a, *b, "section_units");
            }
            if g.kind == SteadyKind::Periodic {
                let back = eval(f, &g.section_units, u64::from(g.period)).end;
                let off = distance(f, &back, &g.section_units);
                assert!(
                    off <= 1e-9,
                    "a stored orbit is {off:e} m off its fixed point"
                );
            }
        }
        // The record's summary is that of the rows: the worst, never below the run's own.
        let worst = want.iter().map(|a| a.amplitude).fold(f64::NAN, f64::max);
        assert_eq!(row.record.steady.starts, 4);
        close(row.record.steady.amplitude_worst, worst, "worst");
        assert!(row.record.steady.amplitude_worst >= row.record.amplitude * (1.0 - 1e-9));
    }
    // The race measured a motion that is not periodic over the design life here.
    assert!(
        stored
            .iter()
            .any(|a| a.life_lo.is_finite() && !a.kind.periodic()),
        "no design-life estimate among {} rows",
        stored.len()
    );
}

/// Every stored column of the records and the attractors, as text (`{:?}` of an `f64` is the
/// shortest text that reads back to its bits).
fn stored_text(dir: &Path) -> (String, String) {
    let recs: Vec<String> = records(dir).iter().map(|r| format!("{r:?}")).collect();
    let atts: Vec<String> = attractors(dir).iter().map(|a| format!("{a:?}")).collect();
    (recs.join("\n"), atts.join("\n"))
}

#[test]
fn the_census_of_several_units_is_the_same_on_any_thread_count_and_chunk_size() {
    let tmp = tempfile::tempdir().unwrap();
    // Two designs (two curves), so that a chunk of one curve makes two chunks.
    // Its chaotic motions' design lives measured briefly (2,000 periods, not 1,024,000): the
    // race runs and is compared all the same, at a thirtieth of the cost.
    let text = TWO_UNITS
        .replace("e = 0.7\n", "")
        .replace("[sweep]\n", "[sweep]\ne = [0.7, 0.8]\n")
        .replace(
            "n_trans_max = 600\n",
            "n_trans_max = 600\nlife_max_periods = 2000\n",
        );
    let path = write(tmp.path(), "two", &text);
    let one = tmp.path().join("one");
    let two = tmp.path().join("two");
    let chunks = tmp.path().join("chunks");
    run(&path, &one, &["--threads", "1"]);
    run(&path, &two, &["--threads", "2"]);
    run(&path, &chunks, &["--threads", "2", "--chunk-points", "2"]);
    assert_eq!(store::part_files(&chunks.join("two")).unwrap().len(), 2);
    let base = stored_text(&one.join("two"));
    assert!(base.1.contains("Periodic") || base.1.contains("NotSettled"));
    assert!(
        base == stored_text(&two.join("two")),
        "1 and 2 threads differ"
    );
    assert!(
        base == stored_text(&chunks.join("two")),
        "chunk sizes differ"
    );
}

#[test]
fn a_one_unit_study_is_the_same_whether_or_not_it_says_units_1() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "[study]\nname = \"one\"\nseed = 5\n\
         [system]\nm = 0.02\nd = 0.01\ne = 0.7\nC = 1.0\nv0 = 0.0\n\
         [scene]\nkind = \"harmonic\"\nF0 = 0.5\nstarts = 3\nn_meas = 50\n\
         nonperiodic_peak = \"window\"\n\
         [sweep]\nr = [1.0, 1.1]\n";
    let plain = write(tmp.path(), "plain", text);
    let said = write(
        tmp.path(),
        "said",
        &text.replace("v0 = 0.0\n", "v0 = 0.0\nunits = 1\nd_spread = 0.0\n"),
    );
    assert_eq!(
        Study::load(&said).unwrap().census_kind(),
        CensusKind::OneUnit
    );
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    run(&plain, &a, &[]);
    run(&said, &b, &[]);
    let parts = |d: &Path| -> Vec<(String, Vec<u8>)> {
        crate::common::dataset(d)
            .into_iter()
            .filter(|f| f.0 != "manifest.json")
            .collect()
    };
    // The study text is stored in each part's metadata: compare the rows instead of the bytes
    // when the texts differ, and the bytes of the plain study's two runs.
    assert!(stored_text(&a.join("one")) == stored_text(&b.join("one")));
    let c = tmp.path().join("c");
    run(&plain, &c, &[]);
    assert!(parts(&a.join("one")) == parts(&c.join("one")));
}

/// `simulate --set units=2 ...` runs the census of several units with the starts of study seed
/// 0, design point 0: its JSON is the record a one-point study of seed 0 stores, bit for bit
/// (NaN as null).
#[test]
fn simulate_takes_the_census_of_several_units_as_the_sweep_does() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "[study]\nname = \"one\"\nseed = 0\n\
         [system]\nm = 0.02\nd = 0.01\ne = 0.7\nC = 1.0\nv0 = 0.0\nunits = 2\nd_spread = 0.2\n\
         [scene]\nkind = \"harmonic\"\nF0 = 0.5\nr = 1.0\nstarts = 4\nn_meas = 50\n\
         n_trans_max = 600\n";
    let path = write(tmp.path(), "one", text);
    run(&path, tmp.path(), &["--threads", "1"]);
    let recs = records(&tmp.path().join("one"));
    assert_eq!(recs.len(), 1);
    let want = &recs[0].record;
    let out = assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .args(["simulate", "--json"])
        .args(
            [
                "m=0.02",
                "d=0.01",
                "e=0.7",
                "C=1.0",
                "v0=0.0",
                "units=2",
                "d_spread=0.2",
                "scene=harmonic",
                "F0=0.5",
                "r=1.0",
                "starts=4",
                "n_meas=50",
                "n_trans_max=600",
            ]
            .iter()
            .flat_map(|s| ["--set", s]),
        )
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let got: serde_json::Value = serde_json::from_slice(&out).unwrap();
    let num = |k: &str| got[k].as_f64().unwrap_or(f64::NAN);
    let st = &want.steady;
    assert_eq!(got["starts"], 4);
    assert_eq!(got["attractors"], st.attractors);
    assert_eq!(got["worst_period"], st.worst_period);
    assert_eq!(got["census_periods"], st.census_periods);
    assert_eq!(got["worst_kind"], st.worst_kind);
    for (k, v) in [
        ("amplitude", want.amplitude),
        ("amplitude_worst", st.amplitude_worst),
        ("worst_window_amplitude", st.worst_window_amplitude),
        ("rest_amplitude", st.rest_amplitude),
        ("worst_basin_share", st.worst_basin_share),
        ("worst_impacts_per_period", st.worst_impacts_per_period),
    ] {
        let g = num(k);
        assert!(
            g.to_bits() == v.to_bits() || (g.is_nan() && v.is_nan()),
            "{k}: simulate {g:e}, the sweep {v:e}"
        );
    }
}

/// `reduce` verifies the decision of a study of several units (issue 68): the deciding designs'
/// motions that are not periodic are run again from their stored whole state (`section_units`)
/// by the map of several units, over `verify_periods` periods. Two designs of two chaotic units
/// (those of `results/units_life_validation.md`, U2, at two total masses): the verification
/// table has direct measurements on the whole `verify_periods`, and each direct value lies
/// where the race's estimate of the same motion says (its 90 % interval widened by 10 %: the
/// restart measured the motion the race did, not another).
#[test]
fn reduce_verifies_a_study_of_several_units_from_their_stored_states() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "[study]\nname = \"verify\"\nseed = 1\n\
         [system]\nM = 0.1\nK = 400.0\nC = 0.1\nd = 0.01\ne = 0.8\n\
         x0 = 0.0\nv0 = 0.0\ny0 = 0.0\nw0 = 0.0\nunits = 2\nd_spread = 0.5\n\
         [scene]\nkind = \"harmonic\"\nF0 = 0.1\nstarts = 4\nn_meas = 400\nlife_max_periods = 4000\n\
         [sweep]\nm = [0.01, 0.011]\nr = [1.0]\n\
         [ranking]\nverify_periods = 20000\n";
    let path = write(tmp.path(), "verify", text);
    run(&path, tmp.path(), &[]);
    let dir = tmp.path().join("verify");
    assert!(attractors(&dir).iter().all(|a| a.section_units.len() == 6));
    assert_cmd::Command::cargo_bin("impactsweep")
        .unwrap()
        .arg("reduce")
        .arg(&dir)
        .assert()
        .success();
    let table = std::fs::read_to_string(dir.join("verification.csv"))
        .unwrap_or_else(|e| panic!("no verification.csv: {e}"));
    let mut lines = table.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| {
        head.iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("no column {name} in {head:?}"))
    };
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let num = |r: &Vec<&str>, k: &str| -> f64 { r[at(k)].parse().unwrap_or(f64::NAN) };
    let measured: Vec<&Vec<&str>> = rows
        .iter()
        .filter(|r| num(r, "direct_periods") >= 20000.0)
        .collect();
    assert!(
        !measured.is_empty(),
        "no motion measured directly over 20,000 periods:\n{table}"
    );
    for r in measured {
        let (direct, lo, hi) = (
            num(r, "direct"),
            num(r, "estimate_lo"),
            num(r, "estimate_hi"),
        );
        assert!(
            direct >= 0.9 * lo && direct <= 1.1 * hi,
            "direct {direct:e} m outside the race's interval [{lo:e}, {hi:e}]: {r:?}"
        );
    }
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(report.contains("**The decision verified.**"), "{report}");
}

/// The census tells coexisting motions that are not periodic apart (issue 68): on the
/// multi-unit showcase (`configs/multi-unit.toml`, two units, clearances 5 and 15 mm) at
/// r = 0.94, start 0 goes on from the run's end with one unit floating still and the structure
/// near 0.42 cm, while the seeded starts share a chaotic motion of both units near 0.82 cm.
/// They are two motions, and a restart from each one's stored state reaches its own window
/// and not the other's (pooled, the first state measured 0.43 cm against the pool's 0.82).
#[test]
fn coexisting_motions_that_are_not_periodic_are_told_apart() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/multi-unit.toml");
    let study = Study::load(&path).unwrap();
    let plan = Plan::new(&study);
    // units = 2 (second of 4), d_spread = 0.5 (third of 4), r = 0.94 (tenth of 31).
    let point = (4 + 2) * 31 + 9;
    let (rec, scene, f, s0) = run_end(&study, &plan, point, 0);
    assert_eq!((f.sys.units, f.sys.d_spread), (2.0, 0.5));
    assert!((rec.r - 0.94).abs() < 1e-12, "r = {}", rec.r);
    let c = census_units(
        &f,
        &s0,
        &UnitsCensusSettings {
            starts: scene.starts,
            max_periods: scene.n_trans_max,
            seed: study.seed,
            point,
            ..UnitsCensusSettings::default()
        },
    );
    assert_eq!(
        c.motions.len(),
        2,
        "{:?}",
        c.motions
            .iter()
            .map(|m| (m.starts, m.window))
            .collect::<Vec<_>>()
    );
    let (small, large) = (&c.motions[0], &c.motions[1]);
    assert_eq!((small.first, small.starts), (0, 1));
    assert_eq!(large.starts, 3);
    assert!(
        large.window > 1.5 * small.window,
        "{} against {}",
        large.window,
        small.window
    );
    for m in &c.motions {
        let mut s = m.states[0].clone();
        let mut top = 0.0f64;
        for _ in 0..10_000 {
            let e = eval(&f, &s, 1);
            top = top.max(e.amplitude);
            s = e.end;
        }
        assert!(
            top >= 0.95 * m.window && top <= 1.15 * m.window,
            "restarted, the motion of window {:e} m reached {top:e} m",
            m.window
        );
    }
    // The chaotic one is named by its exponent.
    let p = large.probe.expect("an exponent");
    assert!(p.chaotic(), "{p:?}");
}

/// The rows of a CSV table as maps from column to value.
fn csv_rows(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            head.iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

/// `reduce` follows the periodic branches of several units (issue 68) from the orbits the sweep
/// stored: on two units with clearances 5 and 15 mm above resonance (r = 1.05 .. 1.15), the
/// period-1 orbit on which the unit in the larger cavity rests while the other rattles is one
/// branch through both frequencies that store it (the resting unit held: without that the
/// corrector is singular and the branch a single point; where the unit rests is not a second
/// orbit), every stable periodic attractor stored lies on a branch of its period, and the
/// period doubling of the period-3 orbit near r = 1.0996 is located (its multiplier at -1).
#[test]
fn reduce_follows_the_branches_of_several_units_through_their_stored_orbits() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "[study]\nname = \"branches\"\nseed = 1\n\
         [system]\nM = 0.1\nK = 400.0\nC = 0.1\nm = 0.01\nd = 0.01\ne = 0.8\n\
         x0 = 0.0\nv0 = 0.0\ny0 = 0.0\nw0 = 0.0\nunits = 2\nd_spread = 0.5\n\
         [scene]\nkind = \"harmonic\"\nF0 = 0.1\nstarts = 4\nlife_max_periods = 2000\n\
         [sweep]\nr = { start = 1.05, stop = 1.15, step = 0.025 }\n";
    let path = write(tmp.path(), "branches", text);
    run(&path, tmp.path(), &["--reduce"]);
    let dir = tmp.path().join("branches");
    let num = |r: &std::collections::HashMap<String, String>, k: &str| -> f64 {
        r[k].parse().unwrap_or(f64::NAN)
    };
    let branches = csv_rows(&dir.join("branches.csv"));
    let stored: Vec<_> = csv_rows(&dir.join("attractors.csv"))
        .into_iter()
        .filter(|a| a["ideal"] == "true" && a["kind"] == "periodic" && a["stability"] == "stable")
        .collect();
    assert!(
        stored.len() >= 3,
        "{} stable periodic attractors",
        stored.len()
    );
    for a in &stored {
        let (r, amp, period) = (num(a, "r"), num(a, "amplitude"), &a["period"]);
        let on = branches.windows(2).any(|w| {
            let (b, c) = (&w[0], &w[1]);
            if b["branch"] != c["branch"] || &b["period"] != period || &c["period"] != period {
                return false;
            }
            let (rb, rc) = (num(b, "r"), num(c, "r"));
            let (lo, hi) = if rb <= rc { (b, c) } else { (c, b) };
            let (l, h) = (num(lo, "r"), num(hi, "r"));
            if r < l || r > h {
                return false;
            }
            let t = if h > l { (r - l) / (h - l) } else { 0.0 };
            let at = num(lo, "amplitude") + t * (num(hi, "amplitude") - num(lo, "amplitude"));
            (at - amp).abs() <= 0.02 * amp
        }) || branches
            .iter()
            .any(|b| num(b, "r") == r && &b["period"] == period && num(b, "amplitude") == amp);
        assert!(
            on,
            "stored orbit at r = {r}, period {period}, {amp:e} m on no branch"
        );
    }
    let period_one: std::collections::BTreeSet<&str> = branches
        .iter()
        .filter(|b| b["period"] == "1")
        .map(|b| b["branch"].as_str())
        .collect();
    assert_eq!(period_one.len(), 1, "period-1 branches {period_one:?}");
    let span = |br: &str| {
        let rs: Vec<f64> = branches
            .iter()
            .filter(|b| b["branch"] == br)
            .map(|b| num(b, "r"))
            .collect();
        rs.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - rs.iter().cloned().fold(f64::INFINITY, f64::min)
    };
    let one = period_one.iter().next().unwrap();
    assert!(
        span(one) >= 0.05,
        "the period-1 branch spans {} in r",
        span(one)
    );
    for b in &branches {
        assert!(num(b, "amplitude") > 0.0, "{b:?}");
        assert!(
            ["stable", "unstable"].contains(&b["stability"].as_str()),
            "{b:?}"
        );
    }
    // Every located label is solved for: a period doubling's multiplier at -1, a fold's or a
    // branch point's at +1 (a Neimark-Sacker pair on the unit circle), each to 1e-6.
    let located: Vec<_> = branches.iter().filter(|b| b["located"] == "true").collect();
    assert!(!located.is_empty(), "no located bifurcation");
    for b in located {
        let mu: Vec<(f64, f64)> = (1..=4)
            .map(|k| (num(b, &format!("mu{k}_re")), num(b, &format!("mu{k}_im"))))
            .filter(|m| m.0.is_finite())
            .collect();
        let off = |target: (f64, f64)| {
            mu.iter()
                .map(|m| (m.0 - target.0).hypot(m.1 - target.1))
                .fold(f64::INFINITY, f64::min)
        };
        let miss = match b["label"].as_str() {
            "PD" => off((-1.0, 0.0)),
            "SN" | "BP" => off((1.0, 0.0)),
            "NS" => mu
                .iter()
                .filter(|m| m.1.abs() > 1e-9)
                .map(|m| (m.0.hypot(m.1) - 1.0).abs())
                .fold(f64::INFINITY, f64::min),
            other => panic!("label {other} located: {b:?}"),
        };
        assert!(
            miss <= 1e-6,
            "{} at r = {}: multipliers {mu:?}",
            b["label"],
            b["r"]
        );
    }
    assert!(dir.join("branches.png").exists() && dir.join("bifurcation.png").exists());
}

/// A closed branch of several units is followed once (issue 68): on the multi-unit showcase's
/// design of one unit (`units = 1`, `d_spread = 0.25`: no spread for one unit), the stable period-1 orbit of three impacts a period at
/// r = 0.91 lies on a closed curve between r = 0.90 and 0.95 (a fold, a period doubling and back).
/// Before the walk knew closed curves it went round it 23 times, to its 2,000 points.
#[test]
fn a_closed_branch_of_several_units_is_followed_once() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/multi-unit.toml");
    let study = Study::load(&path).unwrap();
    let plan = Plan::new(&study);
    // units = 1 (first of 4), d_spread = 0.25 (second of 4: no spread for one unit), r = 0.91
    // (seventh of 31).
    let point = 31 + 6;
    let (rec, scene, f, s0) = run_end(&study, &plan, point, 0);
    assert!((rec.r - 0.91).abs() < 1e-12, "r = {}", rec.r);
    let c = census_units(
        &f,
        &s0,
        &UnitsCensusSettings {
            starts: scene.starts,
            max_periods: scene.n_trans_max,
            seed: study.seed,
            point,
            ..UnitsCensusSettings::default()
        },
    );
    let orbit = c
        .attractors
        .iter()
        .map(|a| &a.orbit)
        .find(|o| o.period == 1 && o.impacts == 3)
        .unwrap_or_else(|| panic!("no period-1 orbit of 3 impacts at r = 0.91"));
    let settings = impactsweep::orbits::units::continuation::UnitsContSettings {
        range: (0.85, 1.15),
        h0: 0.01 / 0.85,
        h_min: 1e-6,
        h_max: 0.05,
        max_points: 2000,
    };
    let b = impactsweep::orbits::units::continuation::follow_units(&f, orbit, &settings);
    assert!(
        b.ends.0 == End::Closed || b.ends.1 == End::Closed,
        "ends {:?} after {} points",
        b.ends,
        b.points.len()
    );
    assert!(b.points.len() < 500, "{} points", b.points.len());
    let (lo, hi) = b.points.iter().fold((f64::INFINITY, 0.0f64), |(a, c), p| {
        (a.min(p.r), c.max(p.r))
    });
    assert!(lo < 0.905 && hi > 0.94, "r over [{lo}, {hi}]");
}
