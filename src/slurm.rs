//! Slurm job arrays: the sbatch scripts for a sharded sweep and its dependent reduce, as a pure
//! function of the settings (no I/O; the command line's `app/slurm.rs` writes and submits them).
//!
//! A sweep of `N` tasks is one job array `--array=0-(N-1)`; task `i` runs
//! `impactsweep run STUDY --shard i/N --out OUT --resume --quiet --threads $SLURM_CPUS_PER_TASK`,
//! which simulates the chunks `k` with `k % N == i` (see [`crate::plan`]). The shards' part files
//! together are the dataset a single-machine run writes, bit for bit. A second job, submitted
//! with `--dependency=afterok:<array id>`, runs `impactsweep reduce OUT/<name>` once every task
//! has succeeded.
//!
//! Every path in the scripts is absolute (the executable, the study, the output root), so a
//! compute node needs nothing on its `PATH` and the job does not depend on the directory it was
//! submitted from; the output root must be on a file system the compute nodes share.
//!
//! Resubmitting: `--resume` keeps the chunks a shard already finished and the per-shard lock
//! keeps two copies of one shard apart, so a failed or pre-empted task is simply run again
//! (`sbatch --array=i array.sbatch`, or Slurm's own requeue).

use std::path::{Path, PathBuf};

use crate::error::InputError;

/// What the scripts need to know. Paths must be absolute.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayJob {
    /// The `impactsweep` executable the tasks run.
    pub exe: PathBuf,
    /// The study file.
    pub study: PathBuf,
    /// `[study].name`: the run directory is `out/<name>`.
    pub study_name: String,
    /// The output root (`--out`).
    pub out: PathBuf,
    /// Array tasks (shards), at least 1.
    pub tasks: u64,
    /// `--partition`.
    pub partition: Option<String>,
    /// `--constraint`: the node features every task needs (Slurm's syntax, e.g. `avx2`), so
    /// that every shard and every re-run computes with one math library (docs/cluster.md).
    pub constraint: Option<String>,
    /// `--time` per task, in Slurm's format (`MM`, `HH:MM:SS`, `D-HH`, ...).
    pub time: Option<String>,
    /// `--cpus-per-task`; each task runs that many threads (1 when absent).
    pub cpus_per_task: Option<u32>,
    /// Tasks of the analysis array (a harmonic study with an attractor census): between the
    /// sweep and the reduce, task `i` runs shard `i` of the per-design analysis. `None`: no
    /// analysis array (free decay, or a study without a census).
    pub analysis_tasks: Option<u64>,
}

/// The scripts' file names inside [`ArrayJob::slurm_dir`].
pub const ARRAY_SCRIPT: &str = "array.sbatch";
pub const REDUCE_SCRIPT: &str = "reduce.sbatch";
pub const ANALYSIS_SCRIPT: &str = "analysis.sbatch";

impl ArrayJob {
    /// `OUT/<name>`: the run directory.
    pub fn run_dir(&self) -> PathBuf {
        self.out.join(&self.study_name)
    }

    /// `OUT/<name>/slurm`: the scripts.
    pub fn slurm_dir(&self) -> PathBuf {
        self.run_dir().join("slurm")
    }

    /// `OUT/<name>/slurm/logs`: one log per array task and one for the reduce job. Slurm does
    /// not create it: it must exist before the jobs start.
    pub fn logs_dir(&self) -> PathBuf {
        self.slurm_dir().join("logs")
    }

    /// The log of array task `task` of job `job` (what `%A_%a` expands to).
    pub fn task_log(&self, job: &str, task: &str) -> PathBuf {
        self.logs_dir().join(format!("run-{job}_{task}.out"))
    }

    /// The log of analysis task `task` of job `job`.
    pub fn analysis_log(&self, job: &str, task: &str) -> PathBuf {
        self.logs_dir().join(format!("analysis-{job}_{task}.out"))
    }

    /// The log of reduce job `job`.
    pub fn reduce_log(&self, job: &str) -> PathBuf {
        self.logs_dir().join(format!("reduce-{job}.out"))
    }

    /// Checks what the scripts cannot express; the messages name the option and the value.
    pub fn validate(&self) -> Result<(), InputError> {
        if self.tasks == 0 {
            return Err(InputError::new(
                "--tasks 0: a job array needs at least 1 task",
            ));
        }
        for (what, p) in [
            ("the executable", &self.exe),
            ("the study file", &self.study),
            ("--out", &self.out),
        ] {
            if !p.is_absolute() {
                return Err(InputError::new(format!(
                    "{what} {}: the job script needs an absolute path",
                    p.display()
                )));
            }
            utf8(what, p)?;
        }
        // The log path goes into `#SBATCH --output="..."`: Slurm reads `%` as a pattern and
        // its quoting cannot hold a `"`, `\` or newline.
        let logs = utf8("--out", &self.out)?;
        if let Some(c) = logs
            .chars()
            .find(|c| matches!(c, '"' | '\\' | '%' | '\n' | '\r'))
        {
            return Err(InputError::new(format!(
                "--out {logs}: the character {c:?} cannot appear in a Slurm log path; \
                 choose an output directory without it"
            )));
        }
        if self.study_name.is_empty()
            || !self
                .study_name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-'))
        {
            return Err(InputError::new(format!(
                "study name '{}': expected [A-Za-z0-9_.-]+",
                self.study_name
            )));
        }
        for (opt, v) in [
            ("--partition", &self.partition),
            ("--constraint", &self.constraint),
            ("--time", &self.time),
        ] {
            if let Some(v) = v
                && (v.is_empty() || !v.chars().all(|c| c.is_ascii_graphic() && c != '"'))
            {
                return Err(InputError::new(format!(
                    "{opt} '{v}': expected a Slurm value without spaces or quotes"
                )));
            }
        }
        if let Some(t) = &self.time
            && !t
                .chars()
                .all(|c| c.is_ascii_digit() || c == ':' || c == '-')
            && !matches!(t.as_str(), "infinite" | "UNLIMITED" | "unlimited")
        {
            return Err(InputError::new(format!(
                "--time '{t}': expected Slurm's format: minutes, MM:SS, HH:MM:SS, D-HH, \
                 D-HH:MM or D-HH:MM:SS (e.g. 02:00:00)"
            )));
        }
        if self.cpus_per_task == Some(0) {
            return Err(InputError::new(
                "--cpus-per-task 0: each task needs at least 1 CPU",
            ));
        }
        Ok(())
    }

    /// The job-array script: task `i` runs shard `i/N`.
    pub fn array_script(&self) -> Result<String, InputError> {
        self.validate()?;
        let n = self.tasks;
        let mut s = String::new();
        s += "#!/bin/bash\n";
        s += &format!(
            "# impactsweep: study '{}' as a Slurm job array of {n} task{}.\n",
            self.study_name,
            if n == 1 { "" } else { "s" }
        );
        s += &format!(
            "# Task i runs shard i/{n}: the chunks k of the sweep with k % {n} == i. Together the\n\
             # shards write {}/points/, the same dataset (same rows, same bits)\n\
             # as one `impactsweep run` on one machine.\n",
            self.run_dir().display()
        );
        s += "#\n# Submit:   sbatch --parsable THIS_FILE   (prints the array's job id)\n";
        s += "# Then:     sbatch --dependency=afterok:<that id> reduce.sbatch\n";
        s += "# Re-run task i (failed, pre-empted, timed out): sbatch --array=i THIS_FILE\n";
        s += "#   --resume keeps the chunks the shard already wrote and runs only the rest; the\n";
        s += "#   per-shard lock stops two copies of one shard from writing at once.\n";
        s += "# Progress: impactsweep status RUN_DIR   (chunks and runs done per shard)\n";
        s += &format!("#SBATCH --job-name=impactsweep-{}\n", self.study_name);
        s += &format!("#SBATCH --array=0-{}\n", n - 1);
        s += &self.common_options();
        s += "# One log per task (%A = array job id, %a = task id); appended to on requeue.\n";
        s += &format!(
            "#SBATCH --output=\"{}\"\n",
            self.logs_dir().join("run-%A_%a.out").display()
        );
        s += "#SBATCH --open-mode=append\n";
        s += "# Pre-emption or node failure may requeue the task: it resumes its shard.\n";
        s += "#SBATCH --requeue\n";
        s += "\nset -euo pipefail\n";
        s += &format!(
            "echo \"impactsweep: shard $SLURM_ARRAY_TASK_ID/{n} of job $SLURM_ARRAY_JOB_ID \
             on $(hostname), $(date -u +%FT%TZ)\"\n"
        );
        s += "# Absolute paths: the compute node needs nothing on its PATH. Threads = the CPUs\n";
        s += "# Slurm gave the task (1 unless --cpus-per-task is set). The run is a child of\n";
        s += "# this shell rather than exec'd: see the lock file below.\n";
        s += &format!(
            "{} run {} \\\n    --shard \"$SLURM_ARRAY_TASK_ID/{n}\" --out {} \\\n    \
             --resume --quiet --threads \"${{SLURM_CPUS_PER_TASK:-1}}\" &\n",
            shell_word(&self.exe),
            shell_word(&self.study),
            shell_word(&self.out),
        );
        s += "run=$!\n";
        s += "# Slurm stops a task (time limit, scancel, pre-emption) with SIGTERM to all its\n";
        s += "# processes; the run dies at once and cannot release its shard's lock file. This\n";
        s += "# shell survives the signal, waits for the run, and removes the lock if it still\n";
        s += "# names the run's PID, so a re-run of this task on any node can take the shard over.\n";
        s += "trap 'kill -TERM \"$run\" 2>/dev/null || true' TERM INT\n";
        s += "status=0\n";
        s += "wait \"$run\" || status=$?\n";
        s += "while kill -0 \"$run\" 2>/dev/null; do wait \"$run\" || status=$?; done\n";
        s += &format!("lock={}\n", self.lock_file());
        s += "pid=\n";
        s += "{ read -r pid _ <\"$lock\"; } 2>/dev/null || true\n";
        s += "if [ \"$pid\" = \"$run\" ]; then\n";
        s += "    rm -f \"$lock\"\n";
        s += "    echo \"impactsweep: removed $lock, left by the stopped run (PID $run)\"\n";
        s += "fi\n";
        s += "exit \"$status\"\n";
        Ok(s)
    }

    /// The lock file of this task's shard, as a shell word: the sweep engine's
    /// `sweep::lock_path` (`RUN_DIR/.lock` for a single shard, else
    /// `RUN_DIR/.lock-shard-I-of-N`; its first word is the holder's PID).
    fn lock_file(&self) -> String {
        let dir = shell_word(&self.run_dir());
        if self.tasks <= 1 {
            format!("{dir}/.lock")
        } else {
            format!(
                "{dir}/.lock-shard-\"$SLURM_ARRAY_TASK_ID\"-of-{}",
                self.tasks
            )
        }
    }

    /// The analysis array's script (a harmonic study with a census), to be submitted with
    /// `--dependency=afterok:<array job id>`: task `i` of `M` runs `impactsweep reduce RUN_DIR
    /// --shard i/M`, its share of the per-design analysis (continuation and jump probes), into
    /// `RUN_DIR/analysis/`. `None` without an analysis array.
    pub fn analysis_script(&self) -> Result<Option<String>, InputError> {
        self.validate()?;
        let Some(m) = self.analysis_tasks else {
            return Ok(None);
        };
        if m == 0 {
            return Err(InputError::new(
                "--tasks 0: the analysis array needs at least 1 task",
            ));
        }
        let mut s = String::new();
        s += "#!/bin/bash\n";
        s += &format!(
            "# impactsweep: the per-design analysis of study '{}' as a job array of {m} task{}.\n",
            self.study_name,
            if m == 1 { "" } else { "s" }
        );
        s += &format!(
            "# Task i runs shard i/{m}: the branches of the designs d with d % {m} == i and the\n\
             # jump probes of its grid lines, into {}/analysis/. The reduce job\n\
             # then reads every shard's results instead of computing them.\n",
            self.run_dir().display()
        );
        s += "# Submit:   sbatch --parsable --dependency=afterok:<array job id> THIS_FILE\n";
        s += "# Re-run task i: sbatch --array=i THIS_FILE (a shard's files are rewritten whole).\n";
        s += &format!(
            "#SBATCH --job-name=impactsweep-{}-analysis\n",
            self.study_name
        );
        s += &format!("#SBATCH --array=0-{}\n", m - 1);
        s += &self.common_options();
        s += &format!(
            "#SBATCH --output=\"{}\"\n",
            self.logs_dir().join("analysis-%A_%a.out").display()
        );
        s += "#SBATCH --kill-on-invalid-dep=yes\n";
        s += "#SBATCH --requeue\n";
        s += "\nset -euo pipefail\n";
        s += &format!(
            "echo \"impactsweep: analysis shard $SLURM_ARRAY_TASK_ID/{m} of job \
             $SLURM_ARRAY_JOB_ID on $(hostname), $(date -u +%FT%TZ)\"\n"
        );
        s += "# The analysis runs on the CPUs Slurm gave the task.\n";
        s += "export RAYON_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-1}\"\n";
        s += &format!(
            "exec {} reduce {} --shard \"$SLURM_ARRAY_TASK_ID/{m}\"\n",
            shell_word(&self.exe),
            shell_word(&self.run_dir())
        );
        Ok(Some(s))
    }

    /// The reduce script, to be submitted with `--dependency=afterok:<array job id>` (or the
    /// analysis array's, when there is one).
    pub fn reduce_script(&self) -> Result<String, InputError> {
        self.validate()?;
        let mut s = String::new();
        s += "#!/bin/bash\n";
        s += &format!(
            "# impactsweep: reduce study '{}' once its job array has finished.\n",
            self.study_name
        );
        s += "# Submit:   sbatch --parsable --dependency=afterok:<array job id> THIS_FILE\n";
        if self.analysis_tasks.is_some() {
            s += "# (the analysis array's id: it waits for the sweep, and this job for it.)\n";
        }
        s += "# afterok waits for every array task to succeed. If a task fails, this job is\n";
        s += "# cancelled (--kill-on-invalid-dep): re-run the task (sbatch --array=i array.sbatch),\n";
        s += "# then submit this script again with the new id.\n";
        s += &format!(
            "#SBATCH --job-name=impactsweep-{}-reduce\n",
            self.study_name
        );
        s += &self.common_options();
        s += &format!(
            "#SBATCH --output=\"{}\"\n",
            self.logs_dir().join("reduce-%j.out").display()
        );
        s += "#SBATCH --kill-on-invalid-dep=yes\n";
        s += "\nset -euo pipefail\n";
        s += "echo \"impactsweep: reduce, job $SLURM_JOB_ID on $(hostname), $(date -u +%FT%TZ)\"\n";
        s += "# Writes summary.parquet, report.md and the charts into the run directory.\n";
        s += &format!(
            "exec {} reduce {}\n",
            shell_word(&self.exe),
            shell_word(&self.run_dir())
        );
        Ok(s)
    }

    fn common_options(&self) -> String {
        let mut s = String::new();
        if let Some(p) = &self.partition {
            s += &format!("#SBATCH --partition={p}\n");
        }
        if let Some(c) = &self.constraint {
            s += &format!("#SBATCH --constraint={c}\n");
        }
        if let Some(t) = &self.time {
            s += &format!("#SBATCH --time={t}\n");
        }
        if let Some(c) = self.cpus_per_task {
            s += &format!("#SBATCH --cpus-per-task={c}\n");
        }
        s
    }
}

fn utf8<'a>(what: &str, p: &'a Path) -> Result<&'a str, InputError> {
    p.to_str().ok_or_else(|| {
        InputError::new(format!(
            "{what} {}: the job script needs a UTF-8 path",
            p.display()
        ))
    })
}

/// A path as one POSIX shell word: bare when it is made of safe characters, else single-quoted.
pub fn shell_word(p: &Path) -> String {
    let s = p.to_string_lossy();
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,@".contains(c))
    {
        s.into_owned()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job() -> ArrayJob {
        ArrayJob {
            exe: "/opt/bin/impactsweep".into(),
            study: "/home/u/studies/quick.toml".into(),
            study_name: "quick".into(),
            out: "/scratch/u/out".into(),
            tasks: 4,
            partition: None,
            constraint: None,
            time: None,
            cpus_per_task: None,
            analysis_tasks: None,
        }
    }

    #[test]
    fn array_script_runs_shard_i_of_n_with_absolute_paths() {
        let s = job().array_script().unwrap();
        assert!(s.starts_with("#!/bin/bash\n"), "{s}");
        assert!(s.contains("#SBATCH --array=0-3\n"), "{s}");
        assert!(
            s.contains("#SBATCH --output=\"/scratch/u/out/quick/slurm/logs/run-%A_%a.out\"\n"),
            "{s}"
        );
        assert!(
            s.contains(
                "\n/opt/bin/impactsweep run /home/u/studies/quick.toml \\\n    \
                 --shard \"$SLURM_ARRAY_TASK_ID/4\" --out /scratch/u/out \\\n    \
                 --resume --quiet --threads \"${SLURM_CPUS_PER_TASK:-1}\" &\nrun=$!\n"
            ),
            "{s}"
        );
        assert!(
            s.contains("\nlock=/scratch/u/out/quick/.lock-shard-\"$SLURM_ARRAY_TASK_ID\"-of-4\n"),
            "{s}"
        );
        assert!(s.ends_with("exit \"$status\"\n"), "{s}");
        // No partition/time/cpus unless asked for: the cluster's defaults apply.
        assert!(!s.contains("--partition"), "{s}");
        assert!(!s.contains("#SBATCH --time"), "{s}");
        assert!(!s.contains("#SBATCH --cpus-per-task"), "{s}");
        // sbatch stops reading #SBATCH lines at the first command: all options come first.
        let first_cmd = s
            .lines()
            .position(|l| !l.is_empty() && !l.starts_with('#'))
            .unwrap();
        let lines: Vec<&str> = s.lines().collect();
        let last_opt = lines
            .iter()
            .rposition(|l| l.starts_with("#SBATCH"))
            .unwrap();
        assert!(last_opt < first_cmd, "{s}");
    }

    #[test]
    fn options_appear_when_given() {
        let mut j = job();
        j.partition = Some("short".into());
        j.constraint = Some("avx2&fma".into());
        j.time = Some("02:00:00".into());
        j.cpus_per_task = Some(8);
        for s in [j.array_script().unwrap(), j.reduce_script().unwrap()] {
            assert!(s.contains("#SBATCH --partition=short\n"), "{s}");
            assert!(s.contains("#SBATCH --constraint=avx2&fma\n"), "{s}");
            assert!(s.contains("#SBATCH --time=02:00:00\n"), "{s}");
            assert!(s.contains("#SBATCH --cpus-per-task=8\n"), "{s}");
        }
    }

    #[test]
    fn single_task_array() {
        let mut j = job();
        j.tasks = 1;
        let s = j.array_script().unwrap();
        assert!(s.contains("#SBATCH --array=0-0\n"), "{s}");
        assert!(s.contains("--shard \"$SLURM_ARRAY_TASK_ID/1\""), "{s}");
        // One shard: the engine's lock is the unsharded one.
        assert!(s.contains("\nlock=/scratch/u/out/quick/.lock\n"), "{s}");
    }

    #[test]
    fn reduce_script_reduces_the_run_dir() {
        let s = job().reduce_script().unwrap();
        assert!(
            s.contains("exec /opt/bin/impactsweep reduce /scratch/u/out/quick\n"),
            "{s}"
        );
        assert!(
            s.contains("#SBATCH --output=\"/scratch/u/out/quick/slurm/logs/reduce-%j.out\"\n"),
            "{s}"
        );
        assert!(s.contains("#SBATCH --kill-on-invalid-dep=yes\n"), "{s}");
        assert!(!s.contains("#SBATCH --array"), "{s}");
    }

    #[test]
    fn analysis_script_runs_reduce_shard_i_of_m() {
        assert_eq!(job().analysis_script().unwrap(), None);
        let mut j = job();
        j.analysis_tasks = Some(3);
        let s = j.analysis_script().unwrap().unwrap();
        assert!(s.contains("#SBATCH --array=0-2\n"), "{s}");
        assert!(
            s.contains(
                "\nexec /opt/bin/impactsweep reduce /scratch/u/out/quick --shard \"$SLURM_ARRAY_TASK_ID/3\"\n"
            ),
            "{s}"
        );
        assert!(
            s.contains("#SBATCH --output=\"/scratch/u/out/quick/slurm/logs/analysis-%A_%a.out\"\n"),
            "{s}"
        );
        j.analysis_tasks = Some(0);
        assert!(
            j.analysis_script()
                .unwrap_err()
                .to_string()
                .starts_with("--tasks 0: the analysis")
        );
    }

    #[test]
    fn paths_with_spaces_and_quotes_are_one_shell_word() {
        let mut j = job();
        j.study = "/home/u/my studies/it's.toml".into();
        j.out = "/scratch/u/out dir".into();
        let s = j.array_script().unwrap();
        assert!(s.contains(r"run '/home/u/my studies/it'\''s.toml'"), "{s}");
        assert!(s.contains("--out '/scratch/u/out dir'"), "{s}");
        assert!(
            s.contains("#SBATCH --output=\"/scratch/u/out dir/quick/slurm/logs/run-%A_%a.out\""),
            "{s}"
        );
    }

    #[test]
    fn bad_settings_name_the_option_and_value() {
        let err = |f: &dyn Fn(&mut ArrayJob)| {
            let mut j = job();
            f(&mut j);
            j.array_script().unwrap_err().to_string()
        };
        assert_eq!(
            err(&|j| j.tasks = 0),
            "--tasks 0: a job array needs at least 1 task"
        );
        assert_eq!(
            err(&|j| j.out = "out".into()),
            "--out out: the job script needs an absolute path"
        );
        assert!(
            err(&|j| j.out = "/scratch/100%".into())
                .starts_with("--out /scratch/100%: the character '%' cannot appear"),
        );
        assert!(err(&|j| j.time = Some("2 hours".into())).starts_with("--time '2 hours'"));
        assert!(err(&|j| j.time = Some("2h".into())).starts_with("--time '2h': expected Slurm"));
        assert!(err(&|j| j.partition = Some("a b".into())).starts_with("--partition 'a b'"));
        assert!(err(&|j| j.constraint = Some("".into())).starts_with("--constraint ''"));
        assert_eq!(
            err(&|j| j.cpus_per_task = Some(0)),
            "--cpus-per-task 0: each task needs at least 1 CPU"
        );
        assert!(err(&|j| j.study_name = "a/b".into()).starts_with("study name 'a/b'"));
    }
}
