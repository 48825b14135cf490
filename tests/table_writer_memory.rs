//! Issue 45: a table written as it is made ([`TableWriter`]) takes a part without copying it
//! into its pending rows whole, however many row groups that part holds. `reduce` hands the
//! `branches` table over a batch of designs at a time (tens of thousands of rows each on the
//! 1,000-design study of BENCHMARKS.md); appending a batch to the pending rows whole made them
//! grow to hold it, and the rows past each row group were copied again (about 78 MB of the
//! 1,000-design `reduce`'s heap).
//!
//! The heap is measured with a counting allocator (this test binary's own): the peak above what
//! was live before an `append` of a part of 2 row groups and one of 8 must stay well below the
//! part's own heap (the bytes written are those of the whole table, `store::summary`'s unit
//! tests).

use std::alloc::{GlobalAlloc, Layout, System};
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

use impactsweep::store::TableKind;
use impactsweep::store::summary::{BATCH_ROWS, TableWriter};
use impactsweep::store::table::{Column, Table};

/// The system allocator, counting the bytes live and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grow(n: usize) {
    let live = LIVE.fetch_add(n, Ordering::SeqCst) + n;
    PEAK.fetch_max(live, Ordering::SeqCst);
}

// SAFETY: every call goes to the system allocator with the same arguments; the counters only
// observe.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        grow(layout.size());
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // The old block and the new one may both be live while it moves.
        grow(new_size);
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Rows `rows` of a table with a branches table's kinds of columns.
fn table(rows: Range<usize>) -> Table {
    let mut t = Table::default();
    t.push(
        "point",
        Column::U64(rows.clone().map(|i| Some(i as u64 / 41)).collect()),
    );
    t.push(
        "r",
        Column::F64(rows.clone().map(|i| 0.8 + (i % 41) as f64 * 0.01).collect()),
    );
    t.push(
        "amplitude",
        Column::F64(rows.clone().map(|i| (i as f64).sin()).collect()),
    );
    t.push(
        "stable",
        Column::Bool(rows.clone().map(|i| i % 3 != 0).collect()),
    );
    t.push(
        "label",
        Column::Str(rows.map(|i| ["", "SN", "PD"][i % 3].to_string()).collect()),
    );
    t
}

/// The heap a part of `groups` row groups holds, and the peak heap above what is live when
/// its append starts (the part included), appended behind some pending rows.
fn append_peak(groups: usize) -> (usize, usize) {
    let dir = tempfile::tempdir().unwrap();
    let mut w = TableWriter::create(dir.path(), TableKind::Branches).unwrap();
    w.append(table(0..1000)).unwrap();
    let before = LIVE.load(Ordering::SeqCst);
    let part = table(1000..1000 + groups * BATCH_ROWS);
    let base = LIVE.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    w.append(part).unwrap();
    let peak = PEAK.load(Ordering::SeqCst) - base;
    w.finish().unwrap();
    (base - before, peak)
}

#[test]
fn issue_45_appending_a_part_of_many_row_groups_holds_little_beside_it() {
    for groups in [2, 8] {
        let (part, peak) = append_peak(groups);
        eprintln!("{groups} row groups: the part holds {part} B, its append peaks {peak} B above");
        // Appended whole to the pending rows, the part's columns were copied into them (and the
        // rows past the row group once more): the append peaked at 0.87 of the part's heap for
        // 8 row groups. Converted to arrow a column at a time, it peaks at one column's copy.
        assert!(
            peak < part / 4,
            "appending {groups} row groups ({part} B) peaked {peak} B above the start"
        );
    }
}
