//! Thin binary: parse, run, print the error chain once, map it to an exit status
//! (0 ok, 1 failure, 2 bad input).

fn main() {
    // Output piped into a reader that stops early (`impactsweep reduce DIR | head -1`) ends the
    // process quietly, as it does any Unix filter, instead of a panic on the broken pipe.
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    if let Err(err) = impactsweep::cli::main() {
        eprintln!("error: {err:#}");
        std::process::exit(impactsweep::error::exit_code(&err));
    }
}
