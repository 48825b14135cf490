//! Store: tables ↔ Parquet. The only module that knows arrow/parquet.
//!
//! One writer ([`write_batch`]) and one reader ([`open`], [`read_batches`]) serve every table:
//!
//! * [`points`]: the sweep's runs, one part file per chunk (`points/part-NNNNNN.parquet`);
//! * [`random`]: the random and record scenes' points table (`random_points`);
//! * [`attractors`]: a harmonic sweep's steady states, one part file per chunk beside the
//!   points (`attractors/part-NNNNNN.parquet`);
//! * [`summary`]: the reducer's summary, zones and jumps tables (Parquet and CSV), from the plain
//!   [`table::Table`] the reducer and the report fill;
//! * [`tradeoff`]: the solver trade-off table;
//! * [`manifest`]: `manifest.json`, the run directory's summary (JSON, not Parquet).
//!
//! [`schema`] holds the contract: column names ([`schema::column_name`]), units, the schema
//! version; `docs/schema.md` lists every column of every table.
//!
//! Every Parquet file carries key-value metadata `impactsweep.version`,
//! `impactsweep.schema_version` and `impactsweep.table` (points also `impactsweep.study`), and
//! each field carries its unit in its metadata (key `unit`). Files are encoded in memory with no
//! timestamps (the same rows always give the same bytes), written to `NAME.tmp`, synced and
//! renamed, so a finished name always holds a complete file. A file's checksum is
//! [`Checksum::DEFAULT`] (xxh3-64) of its bytes; a run directory's manifest names its algorithm.

pub mod analysis;
pub mod attractors;
pub mod audit;
pub mod columns;
pub mod manifest;
pub mod points;
pub mod random;
pub mod schema;
pub mod summary;
pub mod table;
pub mod tradeoff;

use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result, anyhow};
use arrow_array::{ArrayRef, RecordBatch};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use parquet::arrow::ArrowWriter;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::basic::Compression;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::schema::types::ColumnPath;

pub use manifest::{ChunkEntry, Manifest, ManifestFile, read_manifest, read_manifest_file};
pub use points::{
    PartInfo, RunRow, StoredRecord, encode_part, part_chunk, part_files, part_metadata, part_path,
    part_rows, read_ids_outcomes, read_part, read_rows, write_part,
};
pub use schema::{
    META_SCHEMA_VERSION, META_STUDY, META_TABLE, META_UNITS, META_VERSION, SCHEMA_VERSION,
    TableKind, column_name,
};

use crate::error::InputError;

/// A field of `table` with its unit in the field metadata; fails for a column the contract
/// ([`schema::unit`]) does not know, so no column goes undocumented.
pub fn field(table: TableKind, name: &str, data_type: DataType, nullable: bool) -> Result<Field> {
    let unit = schema::unit(table, name).ok_or_else(|| {
        anyhow!(
            "column `{name}` of the {} table has no unit in store::schema (add it there and to \
             docs/schema.md)",
            table.name()
        )
    })?;
    Ok(
        Field::new(name, data_type, nullable).with_metadata(HashMap::from([(
            schema::FIELD_UNIT.to_string(),
            unit.to_string(),
        )])),
    )
}

/// Builds a record batch from named columns of `table` (types from the arrays; `nullable`
/// says which may hold nulls).
pub fn batch(table: TableKind, columns: Vec<(String, ArrayRef, bool)>) -> Result<RecordBatch> {
    let mut fields = Vec::with_capacity(columns.len());
    let mut arrays = Vec::with_capacity(columns.len());
    for (name, array, nullable) in columns {
        fields.push(field(table, &name, array.data_type().clone(), nullable)?);
        arrays.push(array);
    }
    let schema: SchemaRef = Arc::new(Schema::new(fields));
    RecordBatch::try_new(schema, arrays)
        .with_context(|| format!("building the {} table", table.name()))
}

/// How [`encode`] writes one file.
#[derive(Clone, Debug, Default)]
pub struct WriteOptions<'a> {
    /// Columns to dictionary-encode (all others plain).
    pub dictionary: &'a [&'a str],
    /// Key-value metadata beyond the version keys every file gets.
    pub extra: Vec<(String, String)>,
}

/// Encodes one batch as one Parquet file in memory: one row group, snappy, the key-value
/// metadata `impactsweep.version`, `impactsweep.schema_version`, `impactsweep.table` and
/// `extra`, no timestamps (the same batch always gives the same bytes).
pub fn encode(table: TableKind, batch: &RecordBatch, opts: &WriteOptions) -> Result<Vec<u8>> {
    let mut writer = ArrowWriter::try_new(
        Vec::new(),
        batch.schema(),
        Some(properties(table, batch.num_rows(), opts)),
    )
    .context("starting a Parquet writer")?;
    writer.write(batch).context("encoding Parquet")?;
    writer.into_inner().context("finishing Parquet")
}

/// The writer properties of every file: row groups of `rows` rows (one per file, but for the
/// summary of more than [`summary::BATCH_ROWS`] design points), snappy, the version and table
/// keys and `opts.extra`, dictionary encoding only for `opts.dictionary`.
pub fn properties(table: TableKind, rows: usize, opts: &WriteOptions) -> WriterProperties {
    let mut kv = Vec::new();
    for (k, v) in &opts.extra {
        kv.push(KeyValue::new(k.clone(), v.clone()));
    }
    kv.push(KeyValue::new(
        META_VERSION.to_string(),
        env!("CARGO_PKG_VERSION").to_string(),
    ));
    kv.push(KeyValue::new(
        META_SCHEMA_VERSION.to_string(),
        SCHEMA_VERSION.to_string(),
    ));
    kv.push(KeyValue::new(
        META_TABLE.to_string(),
        table.name().to_string(),
    ));
    let mut props = WriterProperties::builder()
        .set_compression(Compression::SNAPPY)
        .set_dictionary_enabled(false)
        .set_max_row_group_row_count(Some(rows.max(1)))
        .set_max_row_group_bytes(None)
        .set_key_value_metadata(Some(kv));
    for col in opts.dictionary {
        props = props.set_column_dictionary_enabled(ColumnPath::from(*col), true);
    }
    props.build()
}

/// What [`write_bytes`] wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FileInfo {
    /// [`Checksum::DEFAULT`] of the file's bytes.
    pub checksum: u64,
    pub bytes: u64,
}

/// When [`write_bytes`] makes a file durable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Durability {
    /// `fsync` the temp file before its rename: on stable storage when the call returns.
    Now,
    /// No `fsync`: the caller syncs later (the sweep engine syncs its file system about once a
    /// second, [`sync_file_system`]). A process crash loses nothing written; a machine crash may
    /// lose the last writes, which the checksums catch.
    Later,
}

/// Writes `bytes` to `path` atomically: to `path` + `.tmp`, then renamed. A crash leaves either
/// the complete file or a `.tmp` leftover, never a truncated file under the final name (with
/// [`Durability::Later`], a machine crash before the next sync may; the checksum catches it).
pub fn write_bytes(path: &Path, bytes: &[u8], durability: Durability) -> Result<FileInfo> {
    let tmp = write_tmp(path, bytes, durability)?;
    rename_into_place(&tmp, path)?;
    Ok(FileInfo {
        checksum: Checksum::DEFAULT.of(bytes),
        bytes: bytes.len() as u64,
    })
}

/// The first half of [`write_bytes`]: `bytes` written to `path` + `.tmp` (synced with
/// [`Durability::Now`]); returns the temporary path, for [`rename_into_place`]. Between the two a
/// caller can record what it is about to rename (the sweep records a part's checksum).
pub fn write_tmp(path: &Path, bytes: &[u8], durability: Durability) -> Result<PathBuf> {
    let tmp = tmp_path(path);
    let mut f = File::create(&tmp).with_context(|| format!("creating {}", tmp.display()))?;
    f.write_all(bytes)
        .and_then(|()| match durability {
            Durability::Now => f.sync_all(),
            Durability::Later => Ok(()),
        })
        .with_context(|| format!("writing {}", tmp.display()))?;
    Ok(tmp)
}

/// The second half of [`write_bytes`]: `tmp` renamed to `path`.
pub fn rename_into_place(tmp: &Path, path: &Path) -> Result<()> {
    std::fs::rename(tmp, path)
        .with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
}

/// Flushes every file written on the file system that holds `path` to stable storage
/// (`syncfs(2)`): one call for all the part files and journal lines written since the last.
pub fn sync_file_system(path: &Path) -> Result<()> {
    use std::os::fd::AsRawFd;
    let f = File::open(path).with_context(|| format!("opening {}", path.display()))?;
    // SAFETY: syncfs on a descriptor we own.
    if unsafe { libc::syncfs(f.as_raw_fd()) } != 0 {
        return Err(std::io::Error::last_os_error())
            .with_context(|| format!("syncing the file system of {}", path.display()));
    }
    Ok(())
}

/// Makes a rename or removal in directory `dir` durable (`fsync` of the directory).
pub fn sync_dir(dir: &Path) -> Result<()> {
    File::open(dir)
        .and_then(|f| f.sync_all())
        .with_context(|| format!("syncing {}", dir.display()))
}

/// Writes a file that several processes may rewrite (`manifest.json`, `study.toml`): to a temp
/// name unique to this process, synced, then renamed, and the rename synced: on stable storage
/// when the call returns. [`remove_dead_temp_files`] clears what a killed writer left.
pub fn write_shared(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp.{}", std::process::id()));
    let tmp = path.with_file_name(name);
    File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes).and_then(|()| f.sync_all()))
        .with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path)
        .with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))?;
    sync_dir(path.parent().unwrap_or(Path::new(".")))
}

/// Removes `*.tmp.PID` files (from [`write_shared`]) in `dir` whose writer no longer runs on
/// this host.
pub fn remove_dead_temp_files(dir: &Path) -> Result<()> {
    for entry in std::fs::read_dir(dir).with_context(|| format!("listing {}", dir.display()))? {
        let path = entry?.path();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let Some((_, pid)) = name.rsplit_once(".tmp.") else {
            continue;
        };
        if pid.parse::<u32>().is_ok() && !Path::new(&format!("/proc/{pid}")).exists() {
            std::fs::remove_file(&path).with_context(|| format!("removing {}", path.display()))?;
        }
    }
    Ok(())
}

/// The one Parquet writer: [`encode`] then [`write_bytes`].
pub fn write_batch(
    path: &Path,
    table: TableKind,
    batch: &RecordBatch,
    opts: &WriteOptions,
) -> Result<FileInfo> {
    write_bytes(path, &encode(table, batch, opts)?, Durability::Now)
}

/// The temporary name a file is written under before its rename.
pub fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".tmp");
    path.with_file_name(name)
}

/// How a part file's checksum is computed; a manifest names its algorithm in its `checksum`
/// key ([`Checksum::doc`]), so a run directory written by an earlier build still verifies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Checksum {
    /// XXH3, 64 bits (about 30 GB/s on one core here: see BENCHMARKS.md).
    Xxh3_64,
    /// 64-bit FNV-1a, byte at a time (about 0.7 GB/s): impactsweep before xxh3.
    Fnv1a64,
}

impl Checksum {
    /// What new run directories use.
    pub const DEFAULT: Checksum = Checksum::Xxh3_64;
    /// Every algorithm this build verifies.
    pub const ALL: [Checksum; 2] = [Checksum::Xxh3_64, Checksum::Fnv1a64];

    /// The manifest's `checksum` value for this algorithm.
    pub fn doc(self) -> &'static str {
        match self {
            Checksum::Xxh3_64 => "xxh3-64 of the part file's bytes (hex)",
            Checksum::Fnv1a64 => "fnv1a-64 of the part file's bytes (hex)",
        }
    }

    /// The algorithm a manifest's `checksum` value names.
    pub fn from_doc(doc: &str) -> Option<Checksum> {
        Checksum::ALL.into_iter().find(|c| c.doc() == doc)
    }

    /// The checksum of `bytes`.
    pub fn of(self, bytes: &[u8]) -> u64 {
        match self {
            Checksum::Xxh3_64 => twox_hash::XxHash3_64::oneshot(bytes),
            Checksum::Fnv1a64 => fnv1a64(bytes),
        }
    }

    /// The checksum of `bytes` as the manifest writes it (16 hex digits).
    pub fn hex(self, bytes: &[u8]) -> String {
        format!("{:016x}", self.of(bytes))
    }
}

/// 64-bit FNV-1a hash (offset basis 0xcbf29ce484222325, prime 0x100000001b3) of `bytes`: the
/// part files' checksum before xxh3 ([`Checksum::Fnv1a64`]).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// [`Checksum::DEFAULT`] of a file's bytes.
pub fn checksum_file(path: &Path) -> Result<u64> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    Ok(Checksum::DEFAULT.of(&bytes))
}

/// The one reader: opens a Parquet file (footer read and checked).
pub fn open(path: &Path) -> Result<ParquetRecordBatchReaderBuilder<File>> {
    let file = File::open(path).with_context(|| format!("opening {}", path.display()))?;
    ParquetRecordBatchReaderBuilder::try_new(file)
        .with_context(|| format!("{}: not a readable Parquet file", path.display()))
}

/// The key-value metadata of an opened file.
pub fn metadata_of(builder: &ParquetRecordBatchReaderBuilder<File>) -> BTreeMap<String, String> {
    builder
        .metadata()
        .file_metadata()
        .key_value_metadata()
        .into_iter()
        .flatten()
        .map(|kv| (kv.key.clone(), kv.value.clone().unwrap_or_default()))
        .collect()
}

/// Refuses a file of another schema version with what it is, what this build reads and what
/// to do. A file without the key (not written by impactsweep) passes; its columns decide.
pub fn check_version(path: &Path, meta: &BTreeMap<String, String>) -> Result<(), InputError> {
    match meta.get(META_SCHEMA_VERSION) {
        Some(v) if *v != SCHEMA_VERSION.to_string() => Err(version_error(
            &path.display().to_string(),
            v,
            meta.get(META_VERSION).map(String::as_str),
        )),
        _ => Ok(()),
    }
}

/// The message for data of schema version `found` (written by tool version `writer`).
pub fn version_error(what: &str, found: &str, writer: Option<&str>) -> InputError {
    let by = writer
        .map(|v| format!(", written by impactsweep {v}"))
        .unwrap_or_default();
    let names = if found == "1" {
        " (mass columns `M` and `m`)"
    } else {
        ""
    };
    InputError::new(format!(
        "{what}: data of schema version {found}{names}{by}; this build of impactsweep reads schema \
         version {SCHEMA_VERSION} (mass columns `mass_main` and `mass_inner`, see docs/schema.md). \
         Run the study again with this build into a new directory (`impactsweep run STUDY.toml \
         --out NEW_DIR`), or use the impactsweep version that wrote it"
    ))
}

/// Reads every batch of an opened file.
pub fn read_batches(
    path: &Path,
    builder: ParquetRecordBatchReaderBuilder<File>,
) -> Result<Vec<RecordBatch>> {
    let reader = builder
        .with_batch_size(65536)
        .build()
        .with_context(|| format!("{}: not a readable Parquet file", path.display()))?;
    reader
        .map(|b| b.with_context(|| format!("reading {}", path.display())))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_matches_reference_vectors() {
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
    }

    #[test]
    fn xxh3_matches_reference_vectors_and_docs_round_trip() {
        // XXH3_64bits with seed 0 (the xxHash reference: empty input).
        assert_eq!(Checksum::Xxh3_64.of(b""), 0x2d06800538d394c2);
        for c in Checksum::ALL {
            assert_eq!(Checksum::from_doc(c.doc()), Some(c));
        }
        assert_eq!(Checksum::from_doc("md5"), None);
        assert_eq!(Checksum::Fnv1a64.hex(b"a"), "af63dc4c8601ec8c");
    }

    #[test]
    fn an_unknown_column_is_refused() {
        let e = field(TableKind::Summary, "m", DataType::Float64, false).unwrap_err();
        assert!(
            e.to_string().contains("column `m` of the summary table"),
            "{e}"
        );
        let f = field(TableKind::Summary, "mass_inner", DataType::Float64, false).unwrap();
        assert_eq!(f.metadata()[schema::FIELD_UNIT], "kg");
    }
}
