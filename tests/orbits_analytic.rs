//! Masri and Caughey's symmetric period-1 orbit (`orbits::analytic`, docs/model.md §8) against
//! the exact forced simulator (issue 16): started on the analytic section, the simulator stays on
//! the orbit, hits the walls where the closed form says, and measures the same amplitude.

use impactsweep::model::System;
use impactsweep::orbits::analytic::{SymmetricOrbit, symmetric_period1};
use impactsweep::sim::{
    self, Drive, Harmonic, HarmonicRecord, Probe, Request, SolverSettings, State, Wall,
};

/// Impacts seen by the simulator: time, wall, state just before and just after.
#[derive(Default)]
struct Impacts(Vec<(f64, Wall, State, State)>);

impl Probe for Impacts {
    fn impact(&mut self, t: f64, wall: Wall, before: &State, after: &State) {
        self.0.push((t, wall, *before, *after));
    }
}

/// Trace samples: time and state.
#[derive(Default)]
struct Samples(Vec<(f64, State)>);

impl Probe for Samples {
    fn sample(&mut self, t: f64, state: &State) {
        self.0.push((t, *state));
    }
}

/// The Table I system (`M = 0.1 kg`, `K = 400 N/m`) with the given inner mass, clearance,
/// restitution and damping.
fn system(m: f64, d: f64, e: f64, c: f64) -> System {
    System {
        m,
        d,
        e,
        C: c,
        ..System::TABLE_I
    }
}

/// The harmonic scene from the section `start` = `(x, x', y - x, y')` at `t = 0`.
fn run(
    sys: &System,
    f0: f64,
    omega: f64,
    start: [f64; 4],
    n_trans: Option<u64>,
    n_meas: u64,
    probe: &mut impl Probe,
) -> HarmonicRecord {
    run_with(
        sys,
        f0,
        omega,
        start,
        n_trans,
        n_meas,
        &Request::default(),
        probe,
    )
}

/// [`run`] with a request (for a sampled trace).
#[allow(clippy::too_many_arguments)]
fn run_with(
    sys: &System,
    f0: f64,
    omega: f64,
    start: [f64; 4],
    n_trans: Option<u64>,
    n_meas: u64,
    req: &Request,
    probe: &mut impl Probe,
) -> HarmonicRecord {
    let mut s = *sys;
    s.x0 = start[0];
    s.v0 = start[1];
    s.y0 = start[0] + start[2];
    s.w0 = start[3];
    // A section on a wall may round to a hair outside the cavity: move it in.
    while (s.y0 - s.x0).abs() > 0.5 * s.d {
        s.y0 -= (s.y0 - s.x0).signum() * f64::EPSILON * s.y0.abs().max(s.x0.abs());
    }
    let scene = Harmonic {
        F0: f0,
        drive: Drive::Omega(omega),
        n_trans,
        n_meas,
        ..Harmonic::default()
    };
    scene.validate(&s).unwrap();
    s.validate().unwrap();
    sim::simulate_harmonic(&s, &SolverSettings::default(), req, &scene, None, probe)
}

fn section(r: &HarmonicRecord) -> [f64; 4] {
    [r.end.x, r.end.v, r.end.y - r.end.x, r.end.w]
}

/// Distance between sections relative to the orbit's amplitude, velocities over `omega_n`
/// (the simulator's section norm).
fn distance(a: &[f64; 4], b: &[f64; 4], sys: &System, amplitude: f64) -> f64 {
    let wn = sys.omega();
    let d2 = (a[0] - b[0]).powi(2)
        + ((a[1] - b[1]) / wn).powi(2)
        + (a[2] - b[2]).powi(2)
        + ((a[3] - b[3]) / wn).powi(2);
    d2.sqrt() / amplitude
}

/// Admissible orbits not close to grazing: the approach speed `W- - V-` is proportional to
/// `2 X + d`, and an orbit that barely reaches its wall (`2 X + d < d / 10`) makes the impact
/// time ill-conditioned (a simulation error of `1e-16` in `z` moves it by `1e-16 / z'`).
fn clear_orbits(sys: &System, f0: f64, omega: f64) -> Vec<SymmetricOrbit> {
    symmetric_period1(sys, f0, omega)
        .into_iter()
        .filter(|o| o.admissible && 2.0 * o.x_impact + sys.d > 0.1 * sys.d)
        .collect()
}

/// One forcing period from the analytic section: the state comes back to the section, the
/// simulator meets the right wall at the analytic phase in the analytic state and the left wall
/// half a period later in the mirror state, and its amplitude is the analytic one.
fn check_one_period(sys: &System, f0: f64, omega: f64, o: &SymmetricOrbit, what: &str) {
    let mut probe = Impacts::default();
    let rec = run(sys, f0, omega, o.section, Some(0), 1, &mut probe);
    assert_eq!(rec.outcome, sim::Outcome::Ok, "{what}");
    let gap = distance(&section(&rec), &o.section, sys, o.amplitude);
    assert!(
        gap <= 1e-9,
        "{what}: section moved by {gap:e} of the amplitude: {o:?}"
    );
    let amp = (rec.amplitude - o.amplitude).abs() / o.amplitude;
    assert!(
        amp <= 1e-9,
        "{what}: amplitude {} vs {} ({amp:e})",
        rec.amplitude,
        o.amplitude
    );
    assert_eq!(rec.impacts_per_period, 2.0, "{what}");
    assert_eq!(rec.sticks, 0, "{what}");
    assert_eq!(probe.0.len(), 2, "{what}");
    let t_f = std::f64::consts::TAU / omega;
    let vs = o.w_before.abs().max(o.v_before.abs());
    let xs = o.amplitude.max(sys.d);
    for &(t, wall, before, after) in &probe.0 {
        // The right-wall state, and the left wall's mirrored onto it.
        let (sign, phase) = match wall {
            Wall::Right => (1.0, o.phase),
            Wall::Left => (
                -1.0,
                (o.phase + std::f64::consts::PI) % std::f64::consts::TAU,
            ),
        };
        let dt = (t - phase / omega).abs();
        assert!(
            dt.min(t_f - dt) <= 1e-9 * t_f,
            "{what}: {wall:?} impact at {t} s, {o:?}"
        );
        let close = |a: f64, b: f64, scale: f64| (sign * a - b).abs() <= 1e-8 * scale;
        assert!(
            close(before.x, o.x_impact, xs),
            "{what}: {before:?} vs {o:?}"
        );
        assert!(
            close(before.y - before.x, 0.5 * sys.d, xs),
            "{what}: {before:?}"
        );
        assert!(
            close(before.v, o.v_before, vs),
            "{what}: {before:?} vs {o:?}"
        );
        assert!(
            close(before.w, o.w_before, vs),
            "{what}: {before:?} vs {o:?}"
        );
        assert!(close(after.v, o.v_after, vs), "{what}: {after:?} vs {o:?}");
        assert!(close(after.w, o.w_after, vs), "{what}: {after:?} vs {o:?}");
    }
    // On a periodic orbit the force's work pays for the viscous and impact losses.
    let work = rec.energy_force;
    let lost = rec.energy_viscous + rec.energy_impact;
    assert!(
        (work - lost).abs() <= 1e-9 * work.abs().max(lost),
        "{what}: {work} vs {lost}"
    );
}

/// Issue 16's acceptance grid: wherever the closed form gives an admissible orbit, the
/// simulator started on it stays on it for a period (stable or not), to 1e-9 of the amplitude.
#[test]
fn the_simulator_stays_on_every_admissible_orbit_of_a_grid() {
    let mut checked = 0;
    for e in [0.5, 0.8, 0.9] {
        for m in [0.005, 0.02] {
            for d in [0.005, 0.02] {
                for f0 in [0.1, 1.0] {
                    let sys = system(m, d, e, 0.1);
                    for r in [0.6, 0.8, 0.95, 1.1, 1.3] {
                        let omega = r * sys.omega();
                        for o in clear_orbits(&sys, f0, omega) {
                            let what = format!("e={e} m={m} d={d} F0={f0} r={r}");
                            check_one_period(&sys, f0, omega, &o, &what);
                            checked += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(checked >= 60, "only {checked} orbits checked");
}

/// Stable orbits of the grid (found by a scan): after a period, and after 300 more from a start
/// 1e-4 of the amplitude away, the simulator is on the analytic section.
const STABLE: [(f64, f64, f64, f64, f64); 6] = [
    // (e, m, d, F0, r)
    (0.9, 0.005, 0.005, 0.1, 1.10),
    (0.5, 0.005, 0.01, 0.3, 0.70),
    (0.8, 0.01, 0.01, 0.1, 0.75),
    (0.9, 0.02, 0.01, 0.3, 1.00),
    (0.8, 0.005, 0.02, 1.0, 1.20),
    (0.5, 0.02, 0.005, 0.3, 1.20),
];

#[test]
fn stable_orbits_return_to_the_section_every_period_and_attract_nearby_starts() {
    for (e, m, d, f0, r) in STABLE {
        let what = format!("e={e} m={m} d={d} F0={f0} r={r}");
        let sys = system(m, d, e, 0.1);
        let omega = r * sys.omega();
        let orbits = clear_orbits(&sys, f0, omega);
        let mut attracting = 0;
        for o in &orbits {
            check_one_period(&sys, f0, omega, o, &what);
            let mut near = o.section;
            near[0] += 1e-4 * o.amplitude;
            near[1] -= 1e-4 * o.amplitude * sys.omega();
            let rec = run(&sys, f0, omega, near, Some(300), 2, &mut Impacts::default());
            let gap = distance(&section(&rec), &o.section, &sys, o.amplitude);
            if gap > 1e-9 {
                continue;
            }
            attracting += 1;
            assert_eq!(rec.period, 1, "{what}");
            assert_eq!(rec.impacts_per_period, 2.0, "{what}");
            let amp = (rec.amplitude - o.amplitude).abs() / o.amplitude;
            assert!(amp <= 1e-9, "{what}: {} vs {}", rec.amplitude, o.amplitude);
            // Period after period, one at a time: back on the section after each.
            let mut s = o.section;
            for k in 1..=4 {
                let rec = run(&sys, f0, omega, s, Some(0), 1, &mut Impacts::default());
                s = section(&rec);
                let gap = distance(&s, &o.section, &sys, o.amplitude);
                assert!(gap <= 1e-9, "{what}: period {k}: {gap:e}");
            }
        }
        assert_eq!(attracting, 1, "{what}: {orbits:?}");
    }
}

/// Issue 16's table: at `r = 1.10` the design `m = 5 g, d = 5 mm, e = 0.9, F0 = 0.1 N` settles
/// from most starts on a period-1 orbit of 0.049 cm; it is the stable symmetric orbit, and a
/// default transient from a start 10 % away reaches it.
#[test]
fn the_attractor_of_issue_16s_table_is_the_stable_symmetric_orbit() {
    let sys = system(0.005, 0.005, 0.9, 0.1);
    let omega = 1.10 * sys.omega();
    let orbits = clear_orbits(&sys, 0.1, omega);
    let o = orbits
        .iter()
        .find(|o| (o.amplitude - 4.9e-4).abs() < 0.05e-4)
        .expect("the 0.049 cm orbit");
    let mut start = o.section;
    start[0] *= 1.1;
    start[3] *= 0.9;
    let rec = run(&sys, 0.1, omega, start, None, 20, &mut Impacts::default());
    assert!(rec.converged);
    assert_eq!((rec.period, rec.impacts_per_period), (1, 2.0));
    let amp = (rec.amplitude - o.amplitude).abs() / o.amplitude;
    assert!(amp <= 1e-8, "{} vs {}", rec.amplitude, o.amplitude);
}

/// The symmetry `x(t + T/2) = -x(t)`, `y(t + T/2) = -y(t)` on the simulated motion: sampled
/// every half period from the analytic section, the state alternates between the section and
/// minus the section.
#[test]
fn half_a_period_later_the_state_is_mirrored() {
    for (e, m, d, f0, r) in STABLE {
        let sys = system(m, d, e, 0.1);
        let omega = r * sys.omega();
        let half = std::f64::consts::PI / omega;
        let req = Request {
            trace_dt: Some(half),
            ..Request::default()
        };
        for o in clear_orbits(&sys, f0, omega) {
            let mut probe = Samples::default();
            run_with(&sys, f0, omega, o.section, Some(0), 1, &req, &mut probe);
            assert!(probe.0.len() >= 3, "{:?}", probe.0);
            for (k, (t, st)) in probe.0.iter().take(3).enumerate() {
                assert!((t - k as f64 * half).abs() <= 1e-12 * half);
                let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
                let s = [st.x, st.v, st.y - st.x, st.w].map(|v| sign * v);
                let gap = distance(&s, &o.section, &sys, o.amplitude);
                assert!(
                    gap <= 1e-9,
                    "e={e} m={m} d={d} F0={f0} r={r}: k={k} {gap:e}"
                );
            }
        }
    }
}

/// Elastic impacts without damping: nothing is lost, so over a period the force does no work;
/// the main mass's velocity reverses at each impact like the inner mass's, and the orbit is
/// symmetric in time as well, with its impacts at the force's extremes (phase 0 or pi). The
/// section then lies on an impact, where the simulator may take the impact at `T` just before
/// or just after its section (the event is located to `1e-12` of a period), so the check is on
/// the impacts inside the period, the amplitude and the energy.
#[test]
fn elastic_undamped_orbits_take_no_work_from_the_force() {
    let mut checked = 0;
    for (m, d) in [(0.01, 0.01), (0.02, 0.005)] {
        let sys = system(m, d, 1.0, 0.0);
        for r in [0.6, 0.8, 1.2, 1.4] {
            let omega = r * sys.omega();
            let half = std::f64::consts::PI / omega;
            for o in clear_orbits(&sys, 0.3, omega) {
                let what = format!("m={m} d={d} r={r}: {o:?}");
                assert!(
                    (o.v_after + o.v_before).abs() <= 1e-14 * o.v_before.abs(),
                    "{what}"
                );
                let off = o.phase.min((o.phase - std::f64::consts::PI).abs());
                assert!(off <= 1e-12, "{what}");
                let mut probe = Impacts::default();
                let rec = run(&sys, 0.3, omega, o.section, Some(0), 1, &mut probe);
                let amp = (rec.amplitude - o.amplitude).abs() / o.amplitude;
                assert!(amp <= 1e-9, "{what}: {} ({amp:e})", rec.amplitude);
                assert!(rec.energy_force.abs() <= 1e-9 * 0.3 * o.amplitude, "{what}");
                assert!(
                    rec.energy_impact.abs() <= 1e-12 * 0.3 * o.amplitude,
                    "{what}"
                );
                // The impact half a period in: the other wall, in the mirror of the first.
                let inside: Vec<_> = probe
                    .0
                    .iter()
                    .filter(|(t, ..)| (t - half).abs() <= 1e-6 * half)
                    .collect();
                assert_eq!(inside.len(), 1, "{what}: {:?}", probe.0);
                let (_, wall, before, _) = *inside[0];
                let sign = if wall == Wall::Right { 1.0 } else { -1.0 };
                let xs = o.amplitude.max(d);
                assert!((sign * before.x - o.x_impact).abs() <= 1e-9 * xs, "{what}");
                let vs = o.w_before.abs();
                assert!((sign * before.w - o.w_before).abs() <= 1e-9 * vs, "{what}");
                assert!((sign * before.v - o.v_before).abs() <= 1e-9 * vs, "{what}");
                checked += 1;
            }
        }
    }
    assert!(checked >= 2, "only {checked} orbits");
}

/// Heavy damping: the closed form holds in every regime (the half-period map `Phi` is the
/// critically or over-damped closed form), and the simulator agrees there too.
#[test]
fn critically_and_over_damped_orbits_agree_with_the_simulator() {
    let crit = 2.0 * (400.0f64 * 0.1).sqrt();
    for zeta in [0.5, 1.0, 2.0] {
        let mut checked = 0;
        for e in [0.5, 0.9] {
            for d in [0.001, 0.005] {
                for f0 in [1.0, 3.0] {
                    let sys = system(0.005, d, e, zeta * crit);
                    for r in [0.8, 1.3, 2.0] {
                        let omega = r * sys.omega();
                        for o in clear_orbits(&sys, f0, omega) {
                            let what = format!("zeta={zeta} e={e} d={d} F0={f0} r={r}");
                            check_one_period(&sys, f0, omega, &o, &what);
                            checked += 1;
                        }
                    }
                }
            }
        }
        assert!(checked >= 5, "zeta={zeta}: only {checked} orbits");
    }
}
