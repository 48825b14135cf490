//! Thin binary: parse, run, print the error chain once, map it to an exit status
//! (0 ok, 1 failure, 2 bad input).

fn main() {
    if let Err(err) = impactsweep::cli::main() {
        eprintln!("error: {err:#}");
        std::process::exit(impactsweep::error::exit_code(&err));
    }
}
