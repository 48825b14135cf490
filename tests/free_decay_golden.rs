//! The free-decay scene is unchanged by the forced scene (issue 12, "a free-decay study gives
//! bit-identical records before and after this change").
//!
//! Every field of every record (outcome, each peak, every observable, counts, energies, stop time,
//! steps) of a fixed set of free-decay runs is hashed as `f64::to_bits` / integers into one 64-bit
//! FNV-1a digest. The set covers the Table I sweep in `e`, the damping extremes, no damper, an
//! unreachable and a tiny clearance, noisy runs (their own seeded streams) and the two integrators.
//!
//! The golden value was minted on `main` at commit 5ecb2e8, before the forced scene was added,
//! and the forced scene's commits leave it as it is; issue 11's solver work re-minted it (see
//! `GOLDEN`).
//!
//! **Re-minting.** A change that is *meant* to move free-decay bits (the simulator speed work of
//! issue 11 may move the last bits of event times, for instance) re-mints it: run
//! `cargo test --test integration free_decay_golden:: -- --nocapture`, check that the change is
//! the one intended (the failing message prints the new digest and the record count; compare a few
//! records with `impactsweep simulate --json` before and after), and paste the new digest here
//! with the commit it was minted on.

use impactsweep::model::System;
use impactsweep::sim::noise::NoiseStream;
use impactsweep::sim::{
    NoProbe, NoiseSettings, Record, Request, SolverKind, SolverSettings, simulate,
};

/// FNV-1a over 64-bit words (each word fed as its 8 little-endian bytes).
struct Fnv(u64);

impl Fnv {
    fn word(&mut self, w: u64) {
        for b in w.to_le_bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01B3);
        }
    }
    fn f(&mut self, v: f64) {
        self.word(v.to_bits());
    }
}

fn hash_record(h: &mut Fnv, r: &Record) {
    for b in r.outcome.name().bytes() {
        h.word(u64::from(b));
    }
    h.word(r.peaks.len() as u64);
    for (x, t) in &r.peaks {
        h.f(*x);
        h.f(*t);
    }
    for v in [r.x1, r.t1, r.x2, r.t2, r.xmax, r.di] {
        h.f(v);
    }
    h.word(r.impacts);
    h.word(r.sticks);
    h.f(r.energy_impact);
    h.f(r.energy_viscous);
    h.f(r.t_stop);
    h.word(r.steps);
}

/// One run: system, solver settings, request, noise `(power, Ts, seed)`.
type Case = (System, SolverSettings, Request, Option<(f64, f64, u64)>);

fn cases() -> Vec<Case> {
    let t1 = System::TABLE_I;
    let crit = 2.0 * (t1.K * t1.M).sqrt();
    let exact = SolverSettings::default();
    let two = Request::default();
    let mut out = Vec::new();
    for i in 0..=20 {
        let e = 0.45 + 0.025 * i as f64;
        out.push((System { e, ..t1 }, exact, two, None));
    }
    for sys in [
        System { e: 0.0, ..t1 },
        System { e: 1.0, ..t1 },
        System { m: 0.0, ..t1 },
        System { C: 0.0, ..t1 },
        System {
            C: crit * (1.0 - 1e-12),
            ..t1
        },
        System { C: crit, ..t1 },
        System {
            C: 3.0 * crit,
            ..t1
        },
        System { d: 1.0, ..t1 },
        System { d: 1e-6, ..t1 },
        System { m: 10.0, ..t1 },
        System {
            x0: 0.003,
            v0: -1.0,
            y0: 0.001,
            w0: 0.5,
            ..t1
        },
    ] {
        out.push((sys, exact, two, None));
    }
    // Longer runs: five peaks, and a fixed horizon.
    out.push((
        System { e: 0.74, ..t1 },
        exact,
        Request { peaks: 5, ..two },
        None,
    ));
    out.push((
        System { e: 0.6, ..t1 },
        exact,
        Request {
            t_end: Some(0.4),
            ..two
        },
        None,
    ));
    // Noise (model.md §4): the paper's power with two sample times, several seeds.
    for (seed, e) in [(1u64, 0.9), (2, 0.9), (3, 0.45), (4, 0.74)] {
        out.push((System { e, ..t1 }, exact, two, Some((5e-10, 1e-4, seed))));
    }
    out.push((System::TABLE_I, exact, two, Some((5e-9, 1e-3, 7))));
    // The integrators.
    for kind in [SolverKind::Rk4, SolverKind::Dopri5] {
        for e in [0.45, 0.9] {
            out.push((
                System { e, ..t1 },
                SolverSettings { kind, ..exact },
                two,
                None,
            ));
        }
    }
    out
}

fn digest() -> (usize, u64) {
    let mut h = Fnv(0xcbf2_9ce4_8422_2325);
    let cases = cases();
    for (i, (sys, settings, req, noise)) in cases.iter().enumerate() {
        sys.validate().unwrap();
        let rec = match noise {
            None => simulate(sys, settings, req, None, &mut NoProbe),
            Some((power, sample_time, seed)) => {
                let ns = NoiseSettings {
                    power: *power,
                    sample_time: *sample_time,
                };
                let mut stream = NoiseStream::new(2013, *seed, i as u64);
                simulate(sys, settings, req, Some((&ns, &mut stream)), &mut NoProbe)
            }
        };
        hash_record(&mut h, &rec);
    }
    (cases.len(), h.0)
}

/// Pinned with the build's numerics version ([`impactsweep::sim::math::NUMERICS`]): a re-mint
/// raises it in the same commit, so that a run directory started by the build before refuses a
/// resume by this one rather than mixing two builds' bits.
const NUMERICS: u32 = 1;

/// Minted at commit 5ecb2e8 (main, before issue 12) as `(43, 0x6e2e_e319_eb7c_68fa)`; re-minted
/// for issue 11 on branch `speed` (merged with main at a196743), whose exact solver locates
/// events by other arithmetic and takes noise samples by a propagator: the records moved in
/// their last bits (compared run by run against the old solver and against `exact` at
/// `tol = 1e-14`; BENCHMARKS.md, results/afsharfard2013). See the module doc to re-mint.
const GOLDEN: (usize, u64) = (43, 0xaac8_01d8_7a73_5c63);

#[test]
fn free_decay_records_are_bit_identical_to_the_golden_digest() {
    assert_eq!(
        impactsweep::sim::math::NUMERICS,
        NUMERICS,
        "the numerics version moved without a re-mint of the golden digest beside it"
    );
    let got = digest();
    assert_eq!(
        got, GOLDEN,
        "free-decay records changed: (count, digest) = ({}, {:#018x}); re-mint only if the change \
         is meant to move free-decay bits (see the module doc), and then raise \
         impactsweep::sim::math::NUMERICS and NUMERICS here",
        got.0, got.1
    );
}

/// Two free-decay studies (the quick study's and the paper's design and cases; the study text
/// lives here, not in `configs/`, because the text is stored in every part and would move the
/// bytes whenever a comment there changes).
const GOLDEN_QUICK: &str = r#"[study]
name = "golden_quick"
seed = 1

[sweep]
e = { start = 0.5, stop = 0.9, num = 6 }

[noise]
power = 5e-10
sample_time = 1e-3

[perturb]
cases = [
  { dd = 0.001 },
  { dm = -0.001, dd = -0.001 },
  { noise_seed = 7 },
]

[run]
chunk_points = 2
"#;
const GOLDEN_PAPER: &str = r#"[study]
name = "golden_paper"
seed = 2013

[sweep]
e = { start = 0.45, stop = 0.95, step = 0.01 }

[noise]
power = 5e-10
sample_time = 1e-3

[perturb]
cases = [
  { dd = 0.001 },
  { dd = -0.001 },
  { noise_seed = 23341 },
  { noise_seed = 32324 },
  { noise_seed = 22413 },
  { noise_seed = 41313 },
  { noise_seed = 32324 },
  { dm = 0.001, dd = 0.001, noise_seed = 41313 },
  { dm = 0.001, dd = -0.001, noise_seed = 22413 },
  { dm = -0.001, dd = -0.001, noise_seed = 22413 },
  { dm = -0.001, dd = 0.001, noise_seed = 23341 },
]
"#;

/// Their part files as written by `main` at commit d9774b9 (before the harmonic scene reached
/// studies, the store and the engine; after issue 11's solver work, which moved free-decay bits
/// on purpose, so it re-minted these from aa2c7ae's): the 64-bit FNV-1a of each part's bytes (whatever checksum
/// the manifest uses), in chunk order.
/// Issue 12 gave the store one table per scene; the free-decay table's bytes must not move. The
/// bytes carry the tool's version (`impactsweep.version`), so a version bump re-mints these
/// (write the two texts to files, `impactsweep run FILE --out OUT` and read the checksums in
/// `OUT/*/manifest.json`), as does any change meant to move free-decay bits (module doc).
const GOLDEN_PARTS: [(&str, &[&str]); 2] = [
    (
        GOLDEN_QUICK,
        &["62e5cb5d748b00a7", "9d5608a98539c2d1", "e055b450c6c50525"],
    ),
    (GOLDEN_PAPER, &["f1436699e34e8a5e"]),
];

#[test]
fn issue_12_free_decay_part_files_are_byte_identical() {
    let tmp = tempfile::tempdir().unwrap();
    for (text, want) in GOLDEN_PARTS {
        let study =
            impactsweep::study::Study::parse(std::path::Path::new("golden.toml"), text).unwrap();
        let opts = impactsweep::sweep::SweepOptions::default();
        let sum = impactsweep::sweep::run_study(&study, tmp.path(), &opts).unwrap();
        let got: Vec<String> = impactsweep::store::part_files(&sum.dir)
            .unwrap()
            .iter()
            .map(|p| {
                let bytes = std::fs::read(p).unwrap();
                format!("{:016x}", impactsweep::store::fnv1a64(&bytes))
            })
            .collect();
        assert_eq!(
            got, want,
            "{}: the free-decay part files changed",
            study.name
        );
    }
}
