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

/// `impactsweep slurm STUDY.toml --tasks N [--out DIR] [--partition P] [--constraint F] [--time T] [--cpus-per-task C] [--dry-run]`.
#[derive(Clone, Debug, Default)]
pub struct SlurmArgs {
    pub study: PathBuf,
    pub tasks: u64,
    pub out: PathBuf,
    pub partition: Option<String>,
    pub constraint: Option<String>,
    pub time: Option<String>,
    pub cpus_per_task: Option<u32>,
    pub dry_run: bool,
}

pub fn slurm(args: &SlurmArgs) -> anyhow::Result<()> {
    let study = Study::load(&args.study)?;
    let job = array_job(args, &study)?;
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
    warn_idle_tasks(args.tasks, Plan::new(&study).n_chunks());

    let logs = job.logs_dir();
    std::fs::create_dir_all(&logs).with_context(|| format!("creating {}", logs.display()))?;
    let scripts = Scripts {
        array: (job.slurm_dir().join(ARRAY_SCRIPT), array),
        analysis: analysis.map(|a| (job.slurm_dir().join(ANALYSIS_SCRIPT), a)),
        reduce: (job.slurm_dir().join(REDUCE_SCRIPT), reduce),
    };
    for (path, text) in scripts.all() {
        std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))?;
    }
    match sbatch {
        None => scripts.print_dry_run(),
        Some(sbatch) => {
            let ids = scripts.submit(&sbatch)?;
            print_submitted(&job, &scripts, &ids, args.tasks);
        }
    }
    Ok(())
}

/// The array job of `study` as `args` ask for it (paths made absolute).
fn array_job(args: &SlurmArgs, study: &Study) -> anyhow::Result<ArrayJob> {
    Ok(ArrayJob {
        exe: std::env::current_exe().context("finding the path of this executable")?,
        study: std::fs::canonicalize(&args.study)
            .with_context(|| format!("resolving {}", args.study.display()))?,
        study_name: study.name.clone(),
        out: std::path::absolute(&args.out)
            .with_context(|| format!("resolving --out {}", args.out.display()))?,
        tasks: args.tasks,
        partition: args.partition.clone(),
        constraint: args.constraint.clone(),
        time: args.time.clone(),
        cpus_per_task: args.cpus_per_task,
        // A harmonic study with a census: its per-design analysis is an array of its own.
        analysis_tasks: study.census().then_some(args.tasks),
    })
}

/// Warns when some of `tasks` array tasks would find no chunk of the study's `chunks`.
fn warn_idle_tasks(tasks: u64, chunks: u64) {
    if tasks > chunks {
        eprintln!(
            "warning: {tasks} tasks but the study has only {chunks} chunk{}: tasks {chunks}..{} \
             will have nothing to do (lower --tasks or [run].chunk_points)",
            if chunks == 1 { "" } else { "s" },
            tasks - 1
        );
    }
}

/// The job scripts, each with the path it is written to: the sweep's array, the analysis
/// array (a harmonic study with a census), the reduce.
struct Scripts {
    array: (PathBuf, String),
    analysis: Option<(PathBuf, String)>,
    reduce: (PathBuf, String),
}

/// The job ids `sbatch` gave.
struct JobIds {
    array: String,
    analysis: Option<String>,
    reduce: String,
}

impl Scripts {
    /// Every script, in submission order.
    fn all(&self) -> Vec<&(PathBuf, String)> {
        std::iter::once(&self.array)
            .chain(&self.analysis)
            .chain(std::iter::once(&self.reduce))
            .collect()
    }

    /// `--dry-run`: the scripts, and the commands that would submit them.
    fn print_dry_run(&self) {
        for (path, text) in self.all() {
            println!("# ==> {} <==", path.display());
            print!("{text}");
            println!();
        }
        println!("# Dry run: nothing submitted. To submit by hand:");
        println!("#   id=$(sbatch --parsable {})", shell_word(&self.array.0));
        if let Some((path, _)) = &self.analysis {
            println!(
                "#   id=$(sbatch --parsable --dependency=afterok:${{id%%;*}} {})",
                shell_word(path)
            );
        }
        println!(
            "#   sbatch --parsable --dependency=afterok:${{id%%;*}} {}",
            shell_word(&self.reduce.0)
        );
    }

    /// Submits the array, then each job after the one before it (`afterok`).
    fn submit(&self, sbatch: &Path) -> anyhow::Result<JobIds> {
        let array = submit(sbatch, &[], &self.array.0)?;
        let analysis = match &self.analysis {
            Some((path, _)) => Some(
                submit(sbatch, &[format!("--dependency=afterok:{array}")], path).with_context(
                    || {
                        format!(
                            "the array was submitted as job {array}, but its analysis array was \
                             not (cancel the array with `scancel {array}` or submit {} by hand)",
                            path.display()
                        )
                    },
                )?,
            ),
            None => None,
        };
        let before = analysis.as_deref().unwrap_or(&array);
        let reduce = submit(
            sbatch,
            &[format!("--dependency=afterok:{before}")],
            &self.reduce.0,
        )
        .with_context(|| {
            format!(
                "job {before} was submitted, but its reduce job was not \
                 (cancel the jobs with `scancel {array} {before}` or submit {} by hand)",
                self.reduce.0.display()
            )
        })?;
        Ok(JobIds {
            array,
            analysis,
            reduce,
        })
    }
}

/// What was submitted, and how to follow it and re-run a failed task.
fn print_submitted(job: &ArrayJob, scripts: &Scripts, ids: &JobIds, n: u64) {
    let JobIds {
        array: array_id,
        analysis: analysis_id,
        reduce: reduce_id,
    } = ids;
    println!("Submitted study '{}' to Slurm:", job.study_name);
    println!(
        "  array job  {array_id}  ({n} task{}, task i runs shard i/{n})",
        plural(n)
    );
    if let Some(a) = analysis_id {
        println!(
            "  analysis   {a}  ({n} task{}, task i analyses shard i/{n}; after the array)",
            plural(n)
        );
    }
    println!("  reduce job {reduce_id}  (starts when every task before it has succeeded)");
    println!("Follow:");
    match analysis_id {
        Some(a) => println!("  squeue -j {array_id},{a},{reduce_id}"),
        None => println!("  squeue -j {array_id},{reduce_id}"),
    }
    println!(
        "  logs:     {}  (task i: run-{array_id}_i.out)",
        job.task_log(array_id, "*").display()
    );
    if let Some(a) = analysis_id {
        println!(
            "            {}  (analysis task i)",
            job.analysis_log(a, "i").display()
        );
    }
    println!("            {}", job.reduce_log(reduce_id).display());
    println!("  progress: impactsweep status {}", job.run_dir().display());
    println!("Re-run a failed task i (it resumes its shard):");
    println!("  sbatch --array=i {}", scripts.array.0.display());
    println!(
        "  then reduce: sbatch --dependency=afterok:<new id> {}",
        scripts.reduce.0.display()
    );
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
