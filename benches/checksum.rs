//! The cost of a part file's checksum (issue 9): xxh3-64, what new run directories use, against
//! FNV-1a byte at a time, what impactsweep used before, on 8 MiB (about a 90,000-run part).
//! `status`, `reduce` and `--resume` hash every part they verify.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use impactsweep::store::Checksum;

fn checksum(c: &mut Criterion) {
    let bytes: Vec<u8> = (0..8u64 << 20)
        .map(|i| (i.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 56) as u8)
        .collect();
    let mut g = c.benchmark_group("checksum_8MiB");
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    for alg in Checksum::ALL {
        g.bench_function(format!("{alg:?}"), |b| {
            b.iter(|| alg.of(std::hint::black_box(&bytes)))
        });
    }
    g.finish();
}

criterion_group!(benches, checksum);
criterion_main!(benches);
