//! `slurm`: a study as a Slurm job array plus a dependent reduce job (issue 6).
//!
//! Writes `OUT/<name>/slurm/array.sbatch` and `reduce.sbatch` (see [`crate::slurm`]), creates
//! the log directory `OUT/<name>/slurm/logs/` (Slurm does not), then submits the array with
//! `sbatch --parsable` and the reduce with `--dependency=afterok:<array id>`. `--dry-run` writes
//! and prints the scripts and the two commands that would submit them, and submits nothing.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::Context;

use crate::plan::Plan;
use crate::slurm::{ANALYSIS_SCRIPT, ARRAY_SCRIPT, ArrayJob, REDUCE_SCRIPT, shell_word};
use crate::study::Study;

/// `impactsweep slurm STUDY.toml --tasks N [--out DIR] [--partition P] [--time T] [--cpus-per-task C] [--dry-run]`.
#[derive(Clone, Debug, Default)]
pub struct SlurmArgs {
    pub study: PathBuf,
    pub tasks: u64,
    pub out: PathBuf,
    pub partition: Option<String>,
    pub time: Option<String>,
    pub cpus_per_task: Option<u32>,
    pub dry_run: bool,
}

pub fn slurm(args: &SlurmArgs) -> anyhow::Result<()> {
    let study = Study::load(&args.study)?;
    let job = ArrayJob {
        exe: std::env::current_exe().context("finding the path of this executable")?,
        study: std::fs::canonicalize(&args.study)
            .with_context(|| format!("resolving {}", args.study.display()))?,
        study_name: study.name.clone(),
        out: std::path::absolute(&args.out)
            .with_context(|| format!("resolving --out {}", args.out.display()))?,
        tasks: args.tasks,
        partition: args.partition.clone(),
        time: args.time.clone(),
        cpus_per_task: args.cpus_per_task,
        // A harmonic study with a census: its per-design analysis is an array of its own.
        analysis_tasks: matches!(study.scene, crate::sim::Scene::Harmonic(h) if h.starts > 0)
            .then_some(args.tasks),
    };
    let array = job.array_script()?;
    let analysis = job.analysis_script()?;
    let reduce = job.reduce_script()?;

    // Before touching anything: without sbatch there is nothing to submit to.
    let sbatch = if args.dry_run {
        None
    } else {
        // Not bad input (exit status 1, not 2): the command is fine, this machine lacks Slurm.
        Some(find_on_path("sbatch").ok_or_else(|| {
            anyhow::anyhow!(
                "sbatch was not found on PATH: `impactsweep slurm` submits to Slurm and needs \
                 its client commands (run it on the cluster's login node). Use --dry-run to \
                 write and print the job scripts without submitting them."
            )
        })?)
    };

    let chunks = Plan::new(&study).n_chunks();
    if args.tasks > chunks {
        eprintln!(
            "warning: {} tasks but the study has only {chunks} chunk{}: tasks {chunks}..{} will \
             have nothing to do (lower --tasks or [run].chunk_points)",
            args.tasks,
            if chunks == 1 { "" } else { "s" },
            args.tasks - 1
        );
    }

    let logs = job.logs_dir();
    std::fs::create_dir_all(&logs).with_context(|| format!("creating {}", logs.display()))?;
    let array_path = job.slurm_dir().join(ARRAY_SCRIPT);
    let analysis_path = job.slurm_dir().join(ANALYSIS_SCRIPT);
    let reduce_path = job.slurm_dir().join(REDUCE_SCRIPT);
    let mut scripts = vec![(&array_path, &array)];
    if let Some(a) = &analysis {
        scripts.push((&analysis_path, a));
    }
    scripts.push((&reduce_path, &reduce));
    for (path, text) in &scripts {
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
    }

    let Some(sbatch) = sbatch else {
        for (path, text) in &scripts {
            println!("# ==> {} <==", path.display());
            print!("{text}");
            println!();
        }
        println!("# Dry run: nothing submitted. To submit by hand:");
        println!("#   id=$(sbatch --parsable {})", shell_word(&array_path));
        if analysis.is_some() {
            println!(
                "#   id=$(sbatch --parsable --dependency=afterok:${{id%%;*}} {})",
                shell_word(&analysis_path)
            );
        }
        println!(
            "#   sbatch --parsable --dependency=afterok:${{id%%;*}} {}",
            shell_word(&reduce_path)
        );
        return Ok(());
    };

    let array_id = submit(&sbatch, &[], &array_path)?;
    let analysis_id = match &analysis {
        Some(_) => Some(
            submit(
                &sbatch,
                &[format!("--dependency=afterok:{array_id}")],
                &analysis_path,
            )
            .with_context(|| {
                format!(
                    "the array was submitted as job {array_id}, but its analysis array was not \
                     (cancel the array with `scancel {array_id}` or submit {} by hand)",
                    analysis_path.display()
                )
            })?,
        ),
        None => None,
    };
    let before = analysis_id.as_deref().unwrap_or(&array_id);
    let reduce_id = submit(
        &sbatch,
        &[format!("--dependency=afterok:{before}")],
        &reduce_path,
    )
    .with_context(|| {
        format!(
            "job {before} was submitted, but its reduce job was not \
             (cancel the jobs with `scancel {array_id} {before}` or submit {} by hand)",
            reduce_path.display()
        )
    })?;

    let n = args.tasks;
    println!("Submitted study '{}' to Slurm:", job.study_name);
    println!(
        "  array job  {array_id}  ({n} task{}, task i runs shard i/{n})",
        plural(n)
    );
    if let Some(a) = &analysis_id {
        println!(
            "  analysis   {a}  ({n} task{}, task i analyses shard i/{n}; after the array)",
            plural(n)
        );
    }
    println!("  reduce job {reduce_id}  (starts when every task before it has succeeded)");
    println!("Follow:");
    match &analysis_id {
        Some(a) => println!("  squeue -j {array_id},{a},{reduce_id}"),
        None => println!("  squeue -j {array_id},{reduce_id}"),
    }
    println!(
        "  logs:     {}  (task i: run-{array_id}_i.out)",
        job.task_log(&array_id, "*").display()
    );
    if let Some(a) = &analysis_id {
        println!(
            "            {}  (analysis task i)",
            job.analysis_log(a, "i").display()
        );
    }
    println!("            {}", job.reduce_log(&reduce_id).display());
    println!("  progress: impactsweep status {}", job.run_dir().display());
    println!("Re-run a failed task i (it resumes its shard):");
    println!("  sbatch --array=i {}", array_path.display());
    println!(
        "  then reduce: sbatch --dependency=afterok:<new id> {}",
        reduce_path.display()
    );
    Ok(())
}

fn plural(n: u64) -> &'static str {
    if n == 1 { "" } else { "s" }
}

/// Runs `sbatch --parsable [extra] SCRIPT` and returns the job id (`id` or `id;cluster` → `id`).
fn submit(sbatch: &Path, extra: &[String], script: &Path) -> anyhow::Result<String> {
    let out = Command::new(sbatch)
        .arg("--parsable")
        .args(extra)
        .arg(script)
        .output()
        .with_context(|| format!("running {}", sbatch.display()))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        anyhow::bail!(
            "sbatch {} failed ({}): {}",
            script.display(),
            out.status,
            stderr.trim()
        );
    }
    parse_job_id(&stdout).ok_or_else(|| {
        anyhow::anyhow!(
            "sbatch {}: expected a job id on stdout, got '{}' (stderr: {})",
            script.display(),
            stdout.trim(),
            stderr.trim()
        )
    })
}

/// The job id in `sbatch --parsable` output: `id` or, on a federation/multi-cluster setup,
/// `id;cluster`.
fn parse_job_id(stdout: &str) -> Option<String> {
    let id = stdout.trim().split(';').next()?.trim();
    (!id.is_empty() && id.chars().all(|c| c.is_ascii_digit())).then(|| id.to_string())
}

/// The first executable file called `name` in `PATH`.
fn find_on_path(name: impl AsRef<OsStr>) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name.as_ref()))
        .find(|p| is_executable(p))
}

#[cfg(unix)]
fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(p: &Path) -> bool {
    p.is_file()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn job_id_from_parsable_output() {
        assert_eq!(parse_job_id("123\n").as_deref(), Some("123"));
        assert_eq!(parse_job_id("4567;cluster2\n").as_deref(), Some("4567"));
        assert_eq!(parse_job_id(""), None);
        assert_eq!(parse_job_id("Submitted batch job 12\n"), None);
    }
}
