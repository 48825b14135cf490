//! Whether a design's perturbed cases could share its ideal case's census (the lever the
//! issue-23 note of session 17 named): on the frequency-response showcase
//! (`configs/frequency-response.toml`: nine designs, four perturbed cases each, m and d 1 g and
//! 1 mm off), each perturbed curve's census as the sweep runs it (its own 8 starts at every
//! frequency, the up and down passes) against the same curve whose every frequency also
//! continues the ideal case's attractors at that frequency (Newton on the periodic ones, a run
//! from its state otherwise), with `S` own starts (1 and 3: cheaper, a weaker promise; 8: the
//! same promise, only more). Compared: the census's forcing periods and time, the stable
//! periodic attractors each finds that the other does not (same frequency, period, amplitude
//! to 1e-8), those of today's that carried their frequency's largest amplitude, and each
//! curve's largest amplitude (its design peak before the design life: exact where a periodic
//! orbit carries it, a 200-period window maximum otherwise). Prints `results/shared_census.md`.
//!
//! `cargo run --release --example shared_census > results/shared_census.md`
//! `cargo run --release --example shared_census -- --seed 7` (other starts)

#[path = "showcase/curve.rs"]
mod showcase;

use impactsweep::orbits::census::{Census, Kind, Origin};
use impactsweep::orbits::curve::{census_passes, census_passes_with};
use impactsweep::orbits::shoot::Newton;
use rayon::prelude::*;
use std::time::Instant;

/// Own starts of the shared variants.
const VARIANTS: [u32; 3] = [1, 3, 8];

/// One curve's census: its periods, seconds, and per frequency its periodic attractors
/// `(period, amplitude)` and its largest amplitude, with whether a periodic orbit carries it.
struct Found {
    periods: u64,
    seconds: f64,
    periodic: Vec<Vec<(u32, f64)>>,
    worst: Vec<Option<(f64, bool)>>,
}

fn found(cs: &[Option<Census>], seconds: f64) -> Found {
    let periodic = cs
        .iter()
        .map(|c| {
            c.iter()
                .flat_map(|c| &c.attractors)
                .filter(|a| matches!(a.kind, Kind::Periodic(_)))
                .map(|a| (a.period, a.amplitude))
                .collect()
        })
        .collect();
    let worst = cs
        .iter()
        .map(|c| {
            c.as_ref().and_then(|c| {
                c.attractors
                    .iter()
                    .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
                    .map(|a| (a.amplitude, matches!(a.kind, Kind::Periodic(_))))
            })
        })
        .collect();
    Found {
        periods: cs.iter().flatten().map(|c| c.periods).sum(),
        seconds,
        periodic,
        worst,
    }
}

impl Found {
    /// The largest amplitude over the curve and whether a periodic orbit carries it.
    fn peak(&self) -> (f64, bool) {
        self.worst
            .iter()
            .flatten()
            .copied()
            .fold(
                (f64::NEG_INFINITY, false),
                |m, w| if w.0 > m.0 { w } else { m },
            )
    }

    /// The periodic attractors of `self` that `other` does not have, and how many of them
    /// carried their frequency's largest amplitude in `self` above `other`'s there.
    fn missing_in(&self, other: &Found) -> (usize, usize) {
        let (mut missing, mut carried) = (0, 0);
        for (i, (ours, theirs)) in self.periodic.iter().zip(&other.periodic).enumerate() {
            for &(p, a) in ours {
                if theirs
                    .iter()
                    .any(|&(q, b)| q == p && (b - a).abs() <= 1e-8 * a)
                {
                    continue;
                }
                missing += 1;
                let their_worst = other.worst[i].map_or(f64::NEG_INFINITY, |w| w.0);
                carried += usize::from(self.worst[i].is_some_and(|w| w.0 == a) && a > their_worst);
            }
        }
        (missing, carried)
    }
}

/// A perturbed curve: today's census, then each variant's.
fn curve(
    study: &impactsweep::study::Study,
    ideal: &[Option<Census>],
    design: u64,
    case: u32,
) -> (Found, Vec<Found>) {
    let (points, _) = showcase::showcase_points(study, design, case);
    let t = Instant::now();
    let today = census_passes(&points);
    let today = found(&today, t.elapsed().as_secs_f64());
    let newton = Newton::default();
    let variants = VARIANTS
        .iter()
        .map(|&s| {
            let mut own = points.clone();
            for (_, c, _) in own.iter_mut().flatten() {
                c.starts = s;
            }
            let t = Instant::now();
            let cs = census_passes_with(&own, |i, census| {
                if let (Some((f, c, _)), Some(id)) = (&points[i], &ideal[i]) {
                    for a in &id.attractors {
                        census.seed(f, a, Origin::Up, c, &newton);
                    }
                }
            });
            found(&cs, t.elapsed().as_secs_f64())
        })
        .collect();
    (today, variants)
}

fn main() {
    let mut study = showcase::study();
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--seed") {
        study.seed = args
            .get(i + 1)
            .and_then(|s| s.parse().ok())
            .expect("--seed takes a whole number");
    }
    let designs = showcase::designs(&study);
    let ideal: Vec<Vec<Option<Census>>> = (0..designs)
        .into_par_iter()
        .map(|d| census_passes(&showcase::showcase_points(&study, d, 0).0))
        .collect();
    let cases = study.cases.len() as u32;
    let curves: Vec<(u64, u32)> = (0..designs)
        .flat_map(|d| (1..cases).map(move |c| (d, c)))
        .collect();
    let outs: Vec<(Found, Vec<Found>)> = curves
        .par_iter()
        .map(|&(d, c)| curve(&study, &ideal[d as usize], d, c))
        .collect();
    print(&study, &outs);
}

fn print(study: &impactsweep::study::Study, outs: &[(Found, Vec<Found>)]) {
    let n_periodic: usize = outs
        .iter()
        .map(|(t, _)| t.periodic.iter().map(Vec::len).sum::<usize>())
        .sum();
    let periods: u64 = outs.iter().map(|(t, _)| t.periods).sum();
    let seconds: f64 = outs.iter().map(|(t, _)| t.seconds).sum();
    println!(
        "## A perturbed case's census seeded with the ideal case's attractors (seed {})\n",
        study.seed
    );
    println!(
        "`cargo run --release --example shared_census` (module doc): the {} perturbed curves of \
         study `{}` with `seed = {}`. Today each runs its own census: {} forcing periods, {:.1} \
         CPU-s, {} stable periodic attractors over its frequencies. Each variant adds the ideal \
         case's attractors at every frequency and runs `S` own starts (the census's periods \
         and CPU time as a share of today's; attractors as counts over all curves):\n",
        outs.len(),
        study.name,
        study.seed,
        periods,
        seconds,
        n_periodic
    );
    println!(
        "| own starts S | periods | CPU time | periodic attractors of today's not found | of them carrying their frequency's largest amplitude | found that today's census does not | of them carrying their frequency's largest amplitude | curves whose peak falls, periodic carrier | chaotic carrier (window maxima) | curves whose peak rises, periodic carrier | chaotic carrier | lowest peak ratio |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (k, s) in VARIANTS.iter().enumerate() {
        let (mut p, mut sec, mut miss, mut carried, mut new, mut new_carried) =
            (0u64, 0.0, 0, 0, 0, 0);
        let (mut fall_p, mut fall_c, mut rise_p, mut rise_c, mut lowest) =
            (0, 0, 0, 0, f64::INFINITY);
        for (today, vs) in outs {
            let v = &vs[k];
            p += v.periods;
            sec += v.seconds;
            let (m, c) = today.missing_in(v);
            miss += m;
            carried += c;
            let (n, nc) = v.missing_in(today);
            new += n;
            new_carried += nc;
            let ((a, periodic), (b, now_periodic)) = (today.peak(), v.peak());
            lowest = lowest.min(b / a);
            if b > a * (1.0 + 1e-8) {
                if now_periodic {
                    rise_p += 1;
                } else {
                    rise_c += 1;
                }
            }
            if b < a * (1.0 - 1e-8) {
                if periodic {
                    fall_p += 1;
                } else {
                    fall_c += 1;
                }
            }
        }
        println!(
            "| {s} | {:.3} | {:.3} | {miss} | {carried} | {new} | {new_carried} | {fall_p} | {fall_c} | {rise_p} | {rise_c} | {lowest:.4} |",
            p as f64 / periods as f64,
            sec / seconds
        );
    }
}
