//! Thin binary: parse, run, print the error chain once, map it to an exit status
//! (0 ok, 1 failure, 2 bad input). The command line is the binary's own: [`cli`] parses the
//! arguments (the only module that knows clap) and [`app`] runs each command over the library
//! (arguments in, library calls, printing out).

mod app;
mod cli;

// The library's modules, by the paths the command line names them (`crate::api`, ...).
use impactsweep::{
    accuracy, api, error, model, plan, reduce, report, sim, slurm, store, study, sweep,
};

fn main() {
    // First, before anything compiled for the build's instruction set can run: a processor
    // without it gets a sentence, not an illegal instruction (`sim::math::MISSING_CPU`).
    if sim::math::cpu_lacks_build_features() {
        let msg = sim::math::MISSING_CPU;
        // SAFETY: writing a static buffer to standard error.
        unsafe {
            libc::write(2, msg.as_ptr().cast(), msg.len());
        }
        std::process::exit(error::EXIT_FAILURE);
    }
    // Output piped into a reader that stops early (`impactsweep reduce DIR | head -1`) ends the
    // process quietly, as it does any Unix filter, instead of a panic on the broken pipe.
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    if let Err(err) = cli::main() {
        eprintln!("error: {err:#}");
        std::process::exit(error::exit_code(&err));
    }
}
