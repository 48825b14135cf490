//! Issue 6: sweeps as Slurm job arrays, against a real single-node Slurm started by
//! `scripts/slurm-local.sh` (Debian's slurmctld, slurmd and munge; installed with apt-get when
//! missing). The test skips — loudly — only when that script reports that the cluster cannot
//! exist here (exit status 3: not root, or the packages cannot be installed). Once the packages
//! are there, any failure is a test failure. The cluster is stopped by PID on every exit path
//! (a Drop guard), and the test checks that its daemons are gone.

use crate::common;

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use arrow_array::RecordBatch;
use assert_cmd::cargo::cargo_bin;
use impactsweep::plan::Plan;
use impactsweep::slurm::ArrayJob;
use impactsweep::study::Study;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;

/// How long all the jobs of the test together may take before it gives up: the quick study
/// takes seconds, so this only bounds a hang (and keeps the suite under its 10 minutes).
const JOBS_TIMEOUT: Duration = Duration::from_secs(300);

const SKIP: i32 = 3;

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn show(out: &Output) -> String {
    format!(
        "status {}\n--- stdout ---\n{}\n--- stderr ---\n{}",
        out.status,
        text(&out.stdout),
        text(&out.stderr)
    )
}

/// How a job or an array task ended, from `scontrol -o show job`.
struct Ended {
    job: String,
    /// `?` for a job that is not an array task.
    task: String,
    state: String,
    code: String,
    line: String,
}

/// A running single-node cluster; stopped by PID when dropped, whatever happened.
struct Cluster {
    dir: tempfile::TempDir,
    conf: PathBuf,
    pids: Vec<(String, u32)>,
    stopped: bool,
    /// When waiting for jobs gives up.
    deadline: Instant,
}

impl Cluster {
    /// `None`: Slurm cannot run here (the script said so, loudly, and so do we).
    fn start() -> Option<Cluster> {
        let dir = tempfile::Builder::new()
            .prefix("impactsweep-slurm-")
            .tempdir()
            .expect("temp dir");
        let mut cluster = Cluster {
            conf: dir.path().join("etc/slurm.conf"),
            dir,
            pids: Vec::new(),
            stopped: false,
            deadline: Instant::now() + JOBS_TIMEOUT,
        };
        let t0 = Instant::now();
        // SLURM_LOCAL_OWNER: should this process die without running Drop (Ctrl-C, SIGKILL),
        // the script's watchdog stops the cluster.
        let out = Command::new(repo().join("scripts/slurm-local.sh"))
            .arg("start")
            .arg(cluster.dir.path())
            .env("SLURM_LOCAL_OWNER", std::process::id().to_string())
            .output()
            .expect("running scripts/slurm-local.sh");
        eprint!("{}", text(&out.stderr));
        if out.status.code() == Some(SKIP) {
            cluster.stopped = true;
            eprintln!(
                "\n{bar}\n!!! SKIPPED tests/cluster.rs: no Slurm cluster can run on this machine.\n\
                 !!! scripts/slurm-local.sh exited with status 3 (see its message above:\n\
                 !!! not root, or slurmctld/slurmd/munge cannot be installed with apt-get).\n\
                 !!! The Slurm integration was NOT tested.\n{bar}\n",
                bar = "!".repeat(78)
            );
            return None;
        }
        assert!(
            out.status.success(),
            "scripts/slurm-local.sh start failed:\n{}",
            show(&out)
        );
        for line in text(&out.stdout).lines() {
            if let Some((name, pid)) = line.split_once(' ')
                && let Ok(pid) = pid.trim().parse()
            {
                cluster.pids.push((name.to_string(), pid));
            }
        }
        let mut names: Vec<&str> = cluster.pids.iter().map(|(n, _)| n.as_str()).collect();
        names.sort();
        assert_eq!(
            names,
            ["munged", "slurmctld", "slurmd", "watchdog"],
            "expected the PIDs of the daemons and the watchdog:\n{}",
            show(&out)
        );
        eprintln!(
            "slurm test: cluster up in {:.1} s (install if needed + daemons)",
            t0.elapsed().as_secs_f64()
        );
        cluster.deadline = Instant::now() + JOBS_TIMEOUT;
        Some(cluster)
    }

    /// A Slurm client command aimed at this cluster.
    fn cmd(&self, prog: &str) -> Command {
        let mut c = Command::new(prog);
        c.env("SLURM_CONF", &self.conf);
        c
    }

    /// The binary, aimed at this cluster.
    fn impactsweep(&self) -> Command {
        let mut c = Command::new(cargo_bin("impactsweep"));
        c.env("SLURM_CONF", &self.conf);
        c
    }

    fn run(&self, prog: &str, args: &[&str]) -> String {
        let out = self.cmd(prog).args(args).output().expect(prog);
        assert!(out.status.success(), "{prog} {args:?}:\n{}", show(&out));
        text(&out.stdout)
    }

    /// Submits a script file (or text on stdin) and returns the job id.
    fn sbatch(&self, extra: &[&str], script: &str) -> String {
        use std::io::Write;
        let mut child = self
            .cmd("sbatch")
            .arg("--parsable")
            .args(extra)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("sbatch");
        child
            .stdin
            .take()
            .unwrap()
            .write_all(script.as_bytes())
            .unwrap();
        let out = child.wait_with_output().unwrap();
        assert!(out.status.success(), "sbatch {extra:?}:\n{}", show(&out));
        let id = text(&out.stdout)
            .trim()
            .split(';')
            .next()
            .unwrap()
            .to_string();
        assert!(id.parse::<u64>().is_ok(), "sbatch printed '{id}'");
        id
    }

    /// Waits until the jobs have left the queue; returns how each job (each array task) ended.
    fn wait(&self, ids: &[&str], logs: &Path) -> Vec<Ended> {
        let list = ids.join(",");
        let t0 = Instant::now();
        loop {
            let q = self.run("squeue", &["-h", "-o", "%i %T", "-j", &list]);
            if q.trim().is_empty() {
                break;
            }
            if Instant::now() > self.deadline {
                panic!(
                    "jobs {list} still queued after {:.0?} ({JOBS_TIMEOUT:?} for all the jobs \
                     of this test):\n{q}\n{}",
                    t0.elapsed(),
                    self.diagnostics(logs)
                );
            }
            std::thread::sleep(Duration::from_millis(200));
        }
        eprintln!(
            "slurm test: jobs {list} done in {:.1} s",
            t0.elapsed().as_secs_f64()
        );
        let mut ended = Vec::new();
        for id in ids {
            let shown = self.run("scontrol", &["-o", "show", "job", id]);
            for line in shown.lines().filter(|l| !l.trim().is_empty()) {
                let field = |k: &str| {
                    line.split_whitespace()
                        .find_map(|w| w.strip_prefix(k))
                        .unwrap_or("?")
                        .to_string()
                };
                ended.push(Ended {
                    job: field("JobId="),
                    task: field("ArrayTaskId="),
                    state: field("JobState="),
                    code: field("ExitCode="),
                    line: line.to_string(),
                });
            }
        }
        ended
    }

    /// [`Cluster::wait`], then asserts that every job (every array task) completed with exit
    /// code 0. Returns the number of job records checked.
    fn wait_ok(&self, ids: &[&str], logs: &Path) -> usize {
        let ended = self.wait(ids, logs);
        for e in &ended {
            assert!(
                e.state == "COMPLETED" && e.code == "0:0",
                "job {} (task {}) ended {} with exit code {}:\n{}\n{}",
                e.job,
                e.task,
                e.state,
                e.code,
                e.line,
                self.diagnostics(logs)
            );
        }
        ended.len()
    }

    /// The job logs and the daemons' logs, for a failure message.
    fn diagnostics(&self, logs: &Path) -> String {
        let mut s = String::new();
        let mut files: Vec<PathBuf> = std::fs::read_dir(logs)
            .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        files.sort();
        for dir in ["log", "munge-run"] {
            if let Ok(d) = std::fs::read_dir(self.dir.path().join(dir)) {
                files.extend(
                    d.filter_map(|e| e.ok().map(|e| e.path()))
                        .filter(|p| p.extension().is_some_and(|x| x == "log")),
                );
            }
        }
        for f in files {
            let t = std::fs::read_to_string(&f).unwrap_or_default();
            let tail: Vec<&str> = t.lines().rev().take(40).collect();
            s += &format!("--- {} (tail) ---\n", f.display());
            for l in tail.into_iter().rev() {
                s += l;
                s += "\n";
            }
        }
        s
    }

    /// Stops the daemons by PID and checks they are gone.
    fn stop(&mut self) -> Result<(), String> {
        if self.stopped {
            return Ok(());
        }
        self.stopped = true;
        let out = Command::new(repo().join("scripts/slurm-local.sh"))
            .arg("stop")
            .arg(self.dir.path())
            .output()
            .map_err(|e| format!("running slurm-local.sh stop: {e}"))?;
        eprint!("{}", text(&out.stderr));
        if !out.status.success() {
            return Err(format!("slurm-local.sh stop failed:\n{}", show(&out)));
        }
        let alive: Vec<String> = self
            .pids
            .iter()
            .filter(|(name, pid)| {
                // The watchdog is a bash subshell of the script.
                let comm = if name == "watchdog" { "bash" } else { name };
                std::fs::read_to_string(format!("/proc/{pid}/comm")).is_ok_and(|c| c.trim() == comm)
            })
            .map(|(name, pid)| format!("{name} ({pid})"))
            .collect();
        if alive.is_empty() {
            Ok(())
        } else {
            Err(format!("daemons still running after stop: {alive:?}"))
        }
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        if let Err(e) = self.stop() {
            eprintln!("slurm test: teardown: {e}");
        }
    }
}

/// Every `points/part-*.parquet` of a run directory, by file name, read back as record batches.
fn dataset(run_dir: &Path) -> BTreeMap<String, Vec<RecordBatch>> {
    let points = run_dir.join("points");
    let mut parts = BTreeMap::new();
    let entries =
        std::fs::read_dir(&points).unwrap_or_else(|e| panic!("reading {}: {e}", points.display()));
    for e in entries {
        let path = e.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !(name.starts_with("part-") && name.ends_with(".parquet")) {
            continue;
        }
        let reader = ParquetRecordBatchReaderBuilder::try_new(File::open(&path).unwrap())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .build()
            .unwrap();
        let batches: Vec<RecordBatch> = reader
            .map(|b| b.unwrap_or_else(|e| panic!("{}: {e}", path.display())))
            .collect();
        parts.insert(name, batches);
    }
    parts
}

/// Asserts that two run directories hold the same dataset: the same part files with the same
/// schema (metadata included) and the same values, bit for bit (arrow compares the buffers).
fn assert_same_dataset(what: &str, got: &Path, want: &Path, n_chunks: u64) {
    let (g, w) = (dataset(got), dataset(want));
    assert_eq!(
        w.len() as u64,
        n_chunks,
        "single-machine run: {} part files for {n_chunks} chunks",
        w.len()
    );
    assert_eq!(
        g.keys().collect::<Vec<_>>(),
        w.keys().collect::<Vec<_>>(),
        "{what}: part files differ from the single-machine run"
    );
    let mut rows = 0;
    for (name, wb) in &w {
        let gb = &g[name];
        let gr: usize = gb.iter().map(|b| b.num_rows()).sum();
        let wr: usize = wb.iter().map(|b| b.num_rows()).sum();
        assert_eq!(gr, wr, "{what}: {name}: {gr} rows, single machine {wr}");
        // Batch boundaries are the reader's business; compare the concatenation.
        let cat = |b: &[RecordBatch]| {
            arrow_select::concat::concat_batches(&b[0].schema(), b).expect("concat")
        };
        assert!(
            cat(gb) == cat(wb),
            "{what}: {name}: values differ from the single-machine run"
        );
        rows += wr;
    }
    assert!(rows > 0, "{what}: the dataset is empty");
    eprintln!(
        "slurm test: {what}: {} part files, {rows} rows, identical to the single-machine run",
        w.len()
    );
}

/// `configs/quick.toml` with `[run].chunk_points` lowered so that a 4-task array gives every
/// task at least one chunk (the shards must add up, not one shard do everything).
fn quick_study(dir: &Path) -> (PathBuf, Study, u64) {
    let src = repo().join("configs/quick.toml");
    let toml_text = std::fs::read_to_string(&src).unwrap_or_else(|e| {
        panic!(
            "{}: {e} (the study issue provides configs/quick.toml; this test needs it)",
            src.display()
        )
    });
    let original = Study::load(&src).unwrap_or_else(|e| panic!("configs/quick.toml: {e}"));
    let n_points = original.n_points();
    let chunk_points = n_points.div_ceil(8).max(1);
    let mut table: toml::Table = toml_text.parse().expect("quick.toml is TOML");
    let run = table
        .entry("run")
        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
    run.as_table_mut().expect("[run] is a table").insert(
        "chunk_points".into(),
        toml::Value::Integer(chunk_points as i64),
    );
    let path = dir.join("quick.toml");
    std::fs::write(&path, toml::to_string(&table).unwrap()).unwrap();
    let study = Study::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let n_chunks = Plan::new(&study).n_chunks();
    assert!(
        n_chunks >= 4 || n_points < 4,
        "quick study: {n_points} points in {n_chunks} chunks; wanted at least 4 chunks"
    );
    (path, study, n_chunks)
}

/// The array and reduce scripts from `impactsweep slurm --dry-run` output, split at the
/// `# ==> PATH <==` headers.
fn split_dry_run(stdout: &str) -> BTreeMap<String, String> {
    let mut scripts = BTreeMap::new();
    let mut current: Option<(String, String)> = None;
    for line in stdout.lines() {
        if let Some(p) = line
            .strip_prefix("# ==> ")
            .and_then(|l| l.strip_suffix(" <=="))
        {
            if let Some((k, v)) = current.take() {
                scripts.insert(k, v);
            }
            let name = Path::new(p)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            current = Some((name, String::new()));
        } else if line.starts_with("# Dry run:") {
            break;
        } else if let Some((_, v)) = current.as_mut() {
            v.push_str(line);
            v.push('\n');
        }
    }
    if let Some((k, v)) = current {
        scripts.insert(k, v);
    }
    // A blank line separates the scripts in the output; it is not part of them.
    for v in scripts.values_mut() {
        while v.ends_with("\n\n") {
            v.pop();
        }
    }
    scripts
}

fn job_ids(stdout: &str) -> (String, String) {
    let id = |prefix: &str| {
        stdout
            .lines()
            .find_map(|l| l.trim().strip_prefix(prefix))
            .and_then(|r| r.split_whitespace().next())
            .unwrap_or_else(|| panic!("no '{prefix}' line in:\n{stdout}"))
            .to_string()
    };
    (id("array job"), id("reduce job"))
}

fn part_files(run_dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(run_dir.join("points"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "parquet"))
        .collect();
    v.sort();
    v
}

#[test]
fn slurm_array_on_a_real_cluster_adds_up_to_the_single_machine_run() {
    let t_all = Instant::now();
    let Some(mut cluster) = Cluster::start() else {
        return;
    };
    let work = tempfile::tempdir().unwrap();
    let w = work.path();

    // --- 1. The generated scripts on the real cluster, with a stand-in executable that records
    // its arguments: the arguments each task gets, SLURM_CPUS_PER_TASK → --threads, and the
    // reduce job starting only after every task.
    let stand_in = w.join("stand-in.sh");
    std::fs::write(
        &stand_in,
        "#!/bin/sh\n\
         # records how it was called: one file per array task, one for reduce; fails when\n\
         # calls/fail-I exists; holds a lock like the engine's and sleeps when calls/hold-I does\n\
         d=\"$(dirname \"$0\")/calls\"; mkdir -p \"$d\"\n\
         if [ -e \"$d/fail-$SLURM_ARRAY_TASK_ID\" ]; then echo failing on purpose; exit 1; fi\n\
         if [ -e \"$d/hold-$SLURM_ARRAY_TASK_ID\" ]; then mkdir -p \"$6/standin\"; \
         echo \"$$ $(hostname)\" > \"$6/standin/.lock-shard-$SLURM_ARRAY_TASK_ID-of-4\"; \
         sleep 120; exit 0; fi\n\
         if [ \"$1\" = reduce ]; then s=$(ls \"$d\"); echo \"$s\" > \"$d/reduce.seen\"; f=reduce; \
         else f=task-$SLURM_ARRAY_TASK_ID; fi\n\
         echo \"$@\" > \"$d/$f.tmp\" && mv \"$d/$f.tmp\" \"$d/$f\"\n",
    )
    .unwrap();
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&stand_in, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let job = ArrayJob {
        exe: stand_in.clone(),
        study: w.join("some study.toml"),
        study_name: "standin".into(),
        // Spaces: the #SBATCH --output quoting and the shell quoting meet the real sbatch.
        out: w.join("out stand-in"),
        tasks: 4,
        partition: Some("debug".into()),
        constraint: None,
        time: Some("5".into()),
        cpus_per_task: Some(2),
        analysis_tasks: None,
    };
    std::fs::create_dir_all(job.logs_dir()).unwrap();
    let a = cluster.sbatch(&[], &job.array_script().unwrap());
    let r = cluster.sbatch(
        &[&format!("--dependency=afterok:{a}")],
        &job.reduce_script().unwrap(),
    );
    assert_eq!(cluster.wait_ok(&[&a, &r], &job.logs_dir()), 5);
    let calls = w.join("calls");
    for i in 0..4 {
        let got = std::fs::read_to_string(calls.join(format!("task-{i}"))).unwrap();
        assert_eq!(
            got.trim(),
            format!(
                "run {} --shard {i}/4 --out {} --resume --quiet --threads 2",
                job.study.display(),
                job.out.display()
            )
        );
        let log = job.task_log(&a, &i.to_string());
        let log_text =
            std::fs::read_to_string(&log).unwrap_or_else(|e| panic!("{}: {e}", log.display()));
        assert!(
            log_text.contains(&format!("shard {i}/4 of job {a}")),
            "{log_text}"
        );
    }
    let reduce_args = std::fs::read_to_string(calls.join("reduce")).unwrap();
    assert_eq!(
        reduce_args.trim(),
        format!("reduce {}", job.run_dir().display())
    );
    let seen = std::fs::read_to_string(calls.join("reduce.seen")).unwrap();
    assert_eq!(
        seen.split_whitespace().collect::<Vec<_>>(),
        ["task-0", "task-1", "task-2", "task-3"],
        "reduce must start after every task has finished"
    );
    assert!(job.reduce_log(&r).is_file());

    // --- 1b. The recovery the scripts document: task 2 fails, so the reduce job is cancelled
    // (--kill-on-invalid-dep) instead of waiting forever; re-running task 2 alone and then the
    // reduce with the new id finishes the job.
    std::fs::remove_dir_all(&calls).unwrap();
    std::fs::create_dir(&calls).unwrap();
    std::fs::write(calls.join("fail-2"), "").unwrap();
    let a = cluster.sbatch(&[], &job.array_script().unwrap());
    let r = cluster.sbatch(
        &[&format!("--dependency=afterok:{a}")],
        &job.reduce_script().unwrap(),
    );
    let ended = cluster.wait(&[&a, &r], &job.logs_dir());
    let mut outcome: Vec<(String, String)> = ended
        .iter()
        .map(|e| (e.task.clone(), e.state.clone()))
        .collect();
    outcome.sort();
    let want = |t: &str, s: &str| (t.to_string(), s.to_string());
    assert_eq!(
        outcome,
        [
            want("0", "COMPLETED"),
            want("1", "COMPLETED"),
            want("2", "FAILED"),
            want("3", "COMPLETED"),
            want("?", "CANCELLED"),
        ],
        "task 2 fails and the reduce is cancelled:\n{}",
        ended
            .iter()
            .map(|e| e.line.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert!(!calls.join("reduce").exists(), "the reduce must not run");
    std::fs::remove_file(calls.join("fail-2")).unwrap();
    let again = cluster.sbatch(&["--array=2"], &job.array_script().unwrap());
    let r = cluster.sbatch(
        &[&format!("--dependency=afterok:{again}")],
        &job.reduce_script().unwrap(),
    );
    assert_eq!(cluster.wait_ok(&[&again, &r], &job.logs_dir()), 2);
    assert!(calls.join("task-2").is_file() && calls.join("reduce").is_file());

    // --- 1c. A task Slurm stops (scancel sends SIGTERM, as a time limit or pre-emption does)
    // dies holding its shard's lock; the script's shell must remove that lock, or a re-run on
    // another node would be refused (the engine only recognises a dead holder on its own host).
    std::fs::write(calls.join("hold-1"), "").unwrap();
    let lock = job.run_dir().join(".lock-shard-1-of-4");
    let held = cluster.sbatch(&["--array=1"], &job.array_script().unwrap());
    while !lock.is_file() {
        assert!(
            Instant::now() < cluster.deadline,
            "the held task never wrote {}:\n{}",
            lock.display(),
            cluster.diagnostics(&job.logs_dir())
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    cluster.run("scancel", &[&held]);
    let ended = cluster.wait(&[&held], &job.logs_dir());
    assert_eq!(
        ended.iter().map(|e| e.state.as_str()).collect::<Vec<_>>(),
        ["CANCELLED"],
        "{}",
        ended[0].line
    );
    assert!(
        !lock.exists(),
        "the stopped task left {} behind:\n{}",
        lock.display(),
        cluster.diagnostics(&job.logs_dir())
    );
    let log = std::fs::read_to_string(job.task_log(&held, "1")).unwrap();
    assert!(log.contains("impactsweep: removed "), "{log}");

    // --- 2. The real thing. The reference: one machine, one process.
    let (study_path, study, n_chunks) = quick_study(w);
    let name = study.name.clone();
    let t = Instant::now();
    let out = Command::new(cargo_bin("impactsweep"))
        .arg("run")
        .arg(&study_path)
        .arg("--out")
        .arg(w.join("ref"))
        .args(["--quiet", "--threads", "2"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "impactsweep run (single machine):\n{}",
        show(&out)
    );
    eprintln!(
        "slurm test: single-machine run: {:.1} s, {n_chunks} chunks",
        t.elapsed().as_secs_f64()
    );
    let reference = w.join("ref").join(&name);

    // --- 3. `impactsweep slurm`: submits a 4-task array and the reduce, prints the ids.
    let out_c = w.join("out-slurm");
    let out = cluster
        .impactsweep()
        .arg("slurm")
        .arg(&study_path)
        .args(["--tasks", "4", "--out"])
        .arg(&out_c)
        .output()
        .unwrap();
    assert!(out.status.success(), "impactsweep slurm:\n{}", show(&out));
    let stdout = text(&out.stdout);
    eprintln!("{stdout}");
    let (a, r) = job_ids(&stdout);
    let run_dir = out_c.join(&name);
    let logs = run_dir.join("slurm/logs");
    for must in [
        format!("squeue -j {a},{r}"),
        logs.display().to_string(),
        format!("impactsweep status {}", run_dir.display()),
    ] {
        assert!(
            stdout.contains(&must),
            "the output should say '{must}':\n{stdout}"
        );
    }
    assert_eq!(cluster.wait_ok(&[&a, &r], &logs), 5);
    assert_same_dataset("impactsweep slurm", &run_dir, &reference, n_chunks);
    for f in ["summary.parquet", "report.md"] {
        assert!(
            run_dir.join(f).is_file(),
            "reduce job should have written {f}:\n{}",
            cluster.diagnostics(&logs)
        );
    }
    assert!(logs.join(format!("reduce-{r}.out")).is_file());
    for i in 0..4 {
        assert!(logs.join(format!("run-{a}_{i}.out")).is_file());
    }
    let status = Command::new(cargo_bin("impactsweep"))
        .arg("status")
        .arg(&run_dir)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "impactsweep status:\n{}",
        show(&status)
    );
    let status = text(&status.stdout);
    eprintln!("{status}");
    for i in 0..4 {
        assert!(
            status.contains(&format!("shard {i}/4")),
            "status should report shard {i}/4:\n{status}"
        );
    }

    // --- 4. A failed or pre-empted task resubmitted later resumes its own shard: take away the
    // last chunk shard 1 wrote (as if it had been killed before it), resubmit task 1 alone.
    // It must write exactly that chunk again and leave every other file alone.
    let shard1: Vec<PathBuf> = (0..n_chunks)
        .filter(|k| k % 4 == 1)
        .map(|k| run_dir.join(format!("points/part-{k:06}.parquet")))
        .collect();
    if let Some(lost) = shard1.last() {
        let before: Vec<(PathBuf, std::time::SystemTime)> = part_files(&run_dir)
            .into_iter()
            .filter(|p| p != lost)
            .map(|p| {
                let m = std::fs::metadata(&p).unwrap().modified().unwrap();
                (p, m)
            })
            .collect();
        std::fs::remove_file(lost).unwrap();
        let array_sbatch = std::fs::read_to_string(run_dir.join("slurm/array.sbatch")).unwrap();
        let again = cluster.sbatch(&["--array=1"], &array_sbatch);
        assert_eq!(cluster.wait_ok(&[&again], &logs), 1);
        assert!(
            lost.is_file(),
            "resubmitted task 1 did not rewrite {}",
            lost.display()
        );
        for (p, m) in before {
            assert_eq!(
                std::fs::metadata(&p).unwrap().modified().unwrap(),
                m,
                "resubmitted task 1 rewrote {} (finished chunks must be kept)",
                p.display()
            );
        }
        assert_same_dataset("resubmitted task", &run_dir, &reference, n_chunks);
    }

    // --- 5. `--dry-run` prints valid sbatch scripts: submit the printed text as it is.
    let out_b = w.join("out-dry");
    let out = cluster
        .impactsweep()
        .arg("slurm")
        .arg(&study_path)
        .args(["--tasks", "4", "--dry-run", "--out"])
        .arg(&out_b)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "impactsweep slurm --dry-run:\n{}",
        show(&out)
    );
    let scripts = split_dry_run(&text(&out.stdout));
    assert_eq!(
        scripts.keys().collect::<Vec<_>>(),
        ["array.sbatch", "reduce.sbatch"],
        "dry-run output:\n{}",
        text(&out.stdout)
    );
    let run_dir_b = out_b.join(&name);
    for (file, printed) in &scripts {
        let written = std::fs::read_to_string(run_dir_b.join("slurm").join(file)).unwrap();
        assert_eq!(
            &written, printed,
            "{file}: the printed script is the one written"
        );
    }
    let queued = cluster.run("squeue", &["-h", "-o", "%i"]);
    assert!(
        queued.trim().is_empty(),
        "--dry-run must not submit: {queued}"
    );
    let a = cluster.sbatch(&[], &scripts["array.sbatch"]);
    let r = cluster.sbatch(
        &[&format!("--dependency=afterok:{a}")],
        &scripts["reduce.sbatch"],
    );
    let logs_b = run_dir_b.join("slurm/logs");
    assert_eq!(cluster.wait_ok(&[&a, &r], &logs_b), 5);
    assert_same_dataset("--dry-run scripts", &run_dir_b, &reference, n_chunks);
    assert!(run_dir_b.join("report.md").is_file());

    // --- 6. Issue 23: a harmonic study with an attractor census gets a third job, the analysis
    // array (`reduce --shard i/N`) between the sweep and the reduce. The sweep's points and
    // attractors parts and the reduce's tables equal a single machine's `run` and `reduce`.
    let fr = w.join("fr.toml");
    std::fs::write(&fr, HARMONIC_STUDY).unwrap();
    let single = w.join("fr-single");
    let out = Command::new(cargo_bin("impactsweep"))
        .arg("run")
        .arg(&fr)
        .arg("--out")
        .arg(&single)
        .args(["--quiet", "--reduce"])
        .output()
        .unwrap();
    assert!(out.status.success(), "single-machine run:\n{}", show(&out));
    let out_h = w.join("fr-slurm");
    let out = cluster
        .impactsweep()
        .arg("slurm")
        .arg(&fr)
        .args(["--tasks", "2", "--out"])
        .arg(&out_h)
        .output()
        .unwrap();
    assert!(out.status.success(), "impactsweep slurm:\n{}", show(&out));
    let stdout = text(&out.stdout);
    eprintln!("{stdout}");
    let (a, r) = job_ids(&stdout);
    let an = stdout
        .lines()
        .find_map(|l| l.trim().strip_prefix("analysis"))
        .and_then(|l| l.split_whitespace().next())
        .unwrap_or_else(|| panic!("no analysis job in:\n{stdout}"))
        .to_string();
    let run_h = out_h.join("frs");
    let logs_h = run_h.join("slurm/logs");
    assert_eq!(cluster.wait_ok(&[&a, &an, &r], &logs_h), 5);
    let want = single.join("frs");
    assert_eq!(
        common::dataset(&run_h)
            .into_iter()
            .filter(|f| f.0 != "manifest.json")
            .collect::<Vec<_>>(),
        common::dataset(&want)
            .into_iter()
            .filter(|f| f.0 != "manifest.json")
            .collect::<Vec<_>>(),
        "the sharded sweep's points and attractors differ from one machine's"
    );
    for i in 0..2 {
        for t in ["probes", "branches", "verification"] {
            let f = run_h.join(format!("analysis/{t}-{i}-of-2.parquet"));
            assert!(
                f.is_file(),
                "{} missing:\n{}",
                f.display(),
                cluster.diagnostics(&logs_h)
            );
        }
    }
    assert_eq!(
        run_h.join("verification.csv").is_file(),
        want.join("verification.csv").is_file(),
        "one reduction verified motions, the other did not"
    );
    for f in [
        "summary.csv",
        "jumps.csv",
        "branches.csv",
        "attractors.csv",
        "zones.csv",
        "verification.csv",
    ]
    .into_iter()
    .filter(|f| want.join(f).is_file())
    {
        assert_eq!(
            std::fs::read(run_h.join(f)).unwrap(),
            std::fs::read(want.join(f)).unwrap(),
            "{f}: the sharded analysis differs from one machine's reduce"
        );
    }

    cluster.stop().unwrap();
    eprintln!("slurm test: total {:.1} s", t_all.elapsed().as_secs_f64());
}

/// Issue 23's harmonic study for the analysis array: three inner masses (a jump between them
/// to locate), five frequencies, a short census, two chunks.
const HARMONIC_STUDY: &str = r#"[study]
name = "frs"
seed = 9

[system]
v0 = 0.0

[scene]
kind = "harmonic"
F0 = 0.3
n_trans_max = 400
life_max_periods = 2000
starts = 4

[sweep]
m = [0.0, 0.01, 0.02]
r = { start = 0.9, stop = 1.1, num = 5 }

[reliability]
strength_mean = 300e6
strength_sd = 20e6
bootstrap = 20

[run]
chunk_points = 5
"#;

#[test]
fn without_sbatch_on_path_it_says_so_and_dry_run_still_works() {
    let w = tempfile::tempdir().unwrap();
    let study = repo().join("configs/quick.toml");
    assert!(
        study.is_file(),
        "{} is missing (the study issue provides it)",
        study.display()
    );
    let empty_path = w.path().join("bin");
    std::fs::create_dir(&empty_path).unwrap();
    let out = Command::new(cargo_bin("impactsweep"))
        .env("PATH", &empty_path)
        .arg("slurm")
        .arg(&study)
        .args(["--tasks", "3", "--out"])
        .arg(w.path().join("out"))
        .output()
        .unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{}", show(&out));
    assert!(err.contains("sbatch was not found on PATH"), "{err}");
    assert!(err.contains("--dry-run"), "{err}");
    assert!(
        !w.path().join("out").exists(),
        "nothing is written when it cannot submit"
    );

    // More tasks than chunks: a warning, and the scripts all the same.
    let loaded = Study::load(&study).unwrap();
    let chunks = Plan::new(&loaded).n_chunks();
    let tasks = chunks + 2;
    let out = Command::new(cargo_bin("impactsweep"))
        .env("PATH", &empty_path)
        .arg("slurm")
        .arg(&study)
        .args(["--tasks", &tasks.to_string(), "--dry-run", "--out"])
        .arg(w.path().join("out"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", show(&out));
    let stdout = text(&out.stdout);
    assert!(
        text(&out.stderr).contains(&format!(
            "warning: {tasks} tasks but the study has only {chunks} chunk"
        )),
        "{}",
        show(&out)
    );
    let name = loaded.name;
    let slurm_dir = w.path().join("out").join(&name).join("slurm");
    let exe = std::fs::canonicalize(cargo_bin("impactsweep")).unwrap();
    assert!(
        stdout.contains(&format!("#SBATCH --array=0-{}\n", tasks - 1)),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("\n{} run ", exe.display())),
        "tasks run the binary by its absolute path:\n{stdout}"
    );
    assert!(slurm_dir.join("array.sbatch").is_file());
    assert!(slurm_dir.join("reduce.sbatch").is_file());
    assert!(
        slurm_dir.join("logs").is_dir(),
        "Slurm needs the log directory to exist"
    );
}

#[test]
fn zero_tasks_is_bad_input() {
    let w = tempfile::tempdir().unwrap();
    let out = Command::new(cargo_bin("impactsweep"))
        .arg("slurm")
        .arg(repo().join("configs/quick.toml"))
        .args(["--tasks", "0", "--dry-run", "--out"])
        .arg(w.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", show(&out));
    assert!(
        text(&out.stderr).contains("--tasks 0: a job array needs at least 1 task"),
        "{}",
        show(&out)
    );
}
