use impactsweep::model::System;
use impactsweep::sim::*;
struct P;
impl Probe for P {
    fn impact(&mut self, t: f64, w: Wall, b: &State, a: &State) {
        println!(
            "impact {t:.6} {w:?} x={:.5e} v_b={:.4} v_a={:.4} w_b={:.4} w_a={:.4}",
            b.x, b.v, a.v, b.w, a.w
        );
    }
    fn stick(&mut self, t: f64, w: Wall, s: &State) {
        println!("stick {t:.6} {w:?} x={:e} v={:e}", s.x, s.v);
    }
    fn separate(&mut self, t: f64, w: Wall, s: &State) {
        println!("sep {t:.6} {w:?} x={:e} v={:e}", s.x, s.v);
    }
}
fn main() {
    let e: f64 = std::env::args().nth(1).unwrap().parse().unwrap();
    let sys = System {
        e,
        ..System::TABLE_I
    };
    let r = simulate(
        &sys,
        &SolverSettings::default(),
        &Request::default(),
        None,
        &mut P,
    );
    println!("{:?}", r);
}
