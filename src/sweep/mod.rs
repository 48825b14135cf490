//! The sweep engine: plan → simulate → store, in parallel, resumable, sharded.
//!
//! A study's runs are cut into chunks ([`crate::plan`]: chunk `k` = a range of design points with
//! all their cases, in `point_id` order); each chunk becomes one Parquet part file
//! ([`crate::store`]). The engine processes this shard's pending chunks one after another as a
//! two-stage pipeline on a local rayon pool: while chunk `k` is encoded and written, chunk `k + 1`
//! is simulated, its runs spread over every thread by work stealing (`rayon::join` of the write
//! with a `par_iter` over the runs). So
//!
//! * every thread is busy until the last run (no tail of one slow chunk on one thread);
//! * at most two chunks are in memory (the one being written, the one being simulated), whatever
//!   the grid size;
//! * each run is a pure function of the study and its index (its noise stream is
//!   [`crate::plan::Plan::noise_stream`]), and `collect` keeps `point_id` order, so a part file's bytes do not
//!   depend on the thread count, the shard split, or an interruption.
//!
//! The records are the study's scene's ([`SceneRun`]): free-decay [`crate::sim::Record`]s,
//! harmonic [`crate::sim::HarmonicRecord`]s or a random study's
//! [`crate::sim::random::RealizationRecord`]s, each scene with its own points table.
//!
//! # The run directory `OUT/<name>/`
//!
//! * `study.toml`: the study text; a run directory holds one study and `--resume` refuses a
//!   different one.
//! * `points/part-NNNNNN.parquet`: written as `*.tmp`, then renamed (see [`crate::store::write_part`]).
//!   **The part files are the source of truth**; what the directory records of each (its rows,
//!   outcome counts and checksum) says what it must be.
//! * `journal.jsonl` / `journal-shard-I-of-N.jsonl`: while a shard runs, one line per finished
//!   chunk ([`journal`]), folded into the manifest when the shard ends.
//! * `manifest.json`: the summary ([`crate::store::Manifest`]): tool and schema version, sizes,
//!   the study text's checksum, and per finished chunk its row count, outcome counts and
//!   checksum (xxh3-64 of the file's bytes; the manifest names the algorithm).
//! * `.lock` (unsharded) or `.lock-shard-I-of-N`: the shard's writer lock, an OS lock on the file
//!   ([`lock`]).
//!
//! Every part is verified ([`verify`]) by `status`, `reduce` and `--resume`: a damaged one is
//! reported, refused and run again.
//!
//! Without `--resume`, an unsharded run refuses an existing non-empty directory (exit 2); a
//! sharded run joins a directory that holds the same study and nothing of its own shard (its
//! sibling shards may have created it), and refuses otherwise.
//!
//! # Accuracy audit
//!
//! With `audit = K > 0`, shard 0 re-runs `K` design points against the reference solver and
//! records the error in the manifest ([`audit`]).
//!
//! # Files
//!
//! [`options`] (how to run a study), [`engine`] (the pipeline, [`run_study`]), [`simulate`]
//! (what one chunk's runs are: each run on its own, or a harmonic study's curves as tasks with
//! their census), [`random`] (a random or record study's realizations, each design point set up
//! once), [`rundir`] (opening and claiming a run directory, what is already done), [`journal`]
//! (the bookkeeping of finished chunks), [`verify`] (is a part what the directory says),
//! [`lock`] (the shard's writer lock), [`audit`] and [`mod@status`] (what a run directory holds).
//! The manifest type and its file are [`crate::store::manifest`]'s.

pub mod audit;
pub mod engine;
pub mod journal;
pub mod lock;
pub mod options;
pub mod random;
pub mod rundir;
pub mod simulate;
pub mod status;
pub mod verify;

pub use audit::{audit_points, run_audit};
pub use engine::{
    SYNC_EVERY, SweepSummary, chunk_rows, clear_stop, request_stop, run_dir, run_study,
    stop_requested,
};
pub use lock::{LockHolder, RunLock, acquire_lock, lock_path, read_lock};
pub use options::{SweepOptions, shard_chunks};
pub use simulate::{SceneRun, run_row, simulate_chunk, simulate_forced_run, simulate_run};
pub use status::{Status, missing_chunks, outcome_names, ranges, status};
