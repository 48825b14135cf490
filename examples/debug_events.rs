use impactsweep::model::System;
use impactsweep::sim::*;
struct P(usize);
impl Probe for P {
    fn impact(&mut self, t: f64, w: Wall, b: &State, a: &State) { self.0 += 1; if self.0 < 60 { println!("impact {t:.12} {w:?} z={:e} vrel_b={:e} vrel_a={:e}", b.y-b.x, b.w-b.v, a.w-a.v); } }
    fn stick(&mut self, t: f64, w: Wall, s: &State) { if self.0 < 60 { println!("stick {t:.12} {w:?} x={:e} v={:e}", s.x, s.v); } }
    fn separate(&mut self, t: f64, w: Wall, s: &State) { if self.0 < 60 { println!("sep {t:.12} {w:?} x={:e} v={:e}", s.x, s.v); } }
}
fn main() {
    let e: f64 = std::env::args().nth(1).unwrap().parse().unwrap();
    let sys = System { e, ..System::TABLE_I };
    let r = simulate(&sys, &SolverSettings::default(), &Request::default(), None, &mut P(0));
    println!("{:?}", r);
}
