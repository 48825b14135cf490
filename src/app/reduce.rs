//! `reduce` and `plot waveform`: the reducer's commands, printing what
//! [`crate::api::reduce`] writes.

pub use crate::api::reduce::{ReduceArgs, WaveformArgs, reduce_dir, waveform_files};
pub use crate::reduce::harmonic::analysis::CurveLines;

pub fn reduce(args: &ReduceArgs) -> anyhow::Result<()> {
    let (line, files) = reduce_dir(args)?;
    println!("{line}");
    for f in files {
        println!("wrote {}", f.display());
    }
    Ok(())
}

pub fn waveform(args: &WaveformArgs) -> anyhow::Result<()> {
    for f in waveform_files(args)? {
        println!("wrote {}", f.display());
    }
    Ok(())
}
