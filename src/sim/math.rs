//! The math library the records depend on, and its fingerprint.
//!
//! The closed forms call the platform's `exp`, `sin`, `cos`, `ln`, `atan2`, `powf`, … (Rust's
//! `f64` methods call the C library's; only the driven scenes' forcing phase uses the `libm`
//! crate). glibc on x86-64 picks one of two codes for each of these when the program loads, by
//! the processor: its FMA code on processors with FMA and AVX2, its SSE2 code elsewhere. The
//! two round differently in about 7 results of 10,000 (`exp`, `sin`, `cos`; measured here over
//! 200,000 arguments each; `ln` about 1 in 400,000). So one study run on two kinds of processor
//! gives records that differ in their last bits (4 of `configs/paper.toml`'s 612 free-decay
//! rows), and its chaotic motions part altogether.
//!
//! [`fingerprint`] tells two math libraries apart: a hash of the bits of each function the
//! records use at arguments where those two codes were seen to differ, and at a few thousand
//! more. A run directory records its writer's ([`crate::store::Manifest::math`]); a shard or a
//! resume whose library computes otherwise is refused (docs/run.md, "Determinism across
//! machines"), so that a dataset's records are always one library's bits; likewise a build whose
//! own arithmetic moved ([`NUMERICS`]).
//!
//! # The processor
//! On x86-64 the project builds for the x86-64-v3 level (`.cargo/config.toml`: AVX2, FMA, BMI1,
//! BMI2, F16C, LZCNT, MOVBE; every x86-64 processor since 2013-2015). The compiler then encodes
//! the same operations in fewer instructions (three-operand forms, wider moves); it never fuses a
//! multiplication and an addition on its own, so every record has the same bits as a build for
//! any x86-64 processor (BENCHMARKS.md, "A build for x86-64-v3"). [`MISSING_CPU`] is what the
//! binary says, instead of dying on an illegal instruction, on a processor without those
//! extensions ([`cpu_lacks_build_features`]). The Python module cannot say it: pyo3's loader, which
//! runs before any code of ours, already holds such instructions (`vzeroupper`, seen under
//! QEMU's Nehalem), so there it is an illegal instruction.

use std::hint::black_box;
use std::sync::OnceLock;

/// The version of the records' arithmetic in this build: raised by every change meant to move a
/// record's bits (the golden digests of `tests/free_decay_golden.rs` and
/// `tests/forced_golden.rs` are pinned beside it, so re-minting one means raising it). A run
/// directory records its writer's ([`crate::store::Manifest::numerics`]), and a resume or a
/// shard by a build of another version is refused: one dataset, one build's arithmetic.
pub const NUMERICS: u32 = 1;

/// The message for a processor that lacks an extension this build was compiled to use
/// ([`cpu_lacks_build_features`]); static, so that nothing compiled for those extensions runs
/// before it is written.
pub const MISSING_CPU: &str = "error: this build of impactsweep uses the x86-64-v3 \
instructions (AVX2, FMA, BMI1, BMI2, F16C, LZCNT, MOVBE) and this processor lacks some of them. \
Build it for any x86-64 processor with `RUSTFLAGS= cargo build --release` (Python: \
`RUSTFLAGS= pip install ./python`): the same results, about a tenth slower.\n";

/// Whether the processor lacks an instruction-set extension this build was compiled to use
/// (`.cargo/config.toml`'s `target-cpu`): `false` where the build can run (always on other
/// architectures, and for a build without those extensions). Read from
/// `cpuid` and `xgetbv` (the system saves the vector registers) and tested in assembly of the
/// base instruction set: `std::arch::is_x86_feature_detected!` answers `true` for a feature
/// the build was compiled with, without asking the processor, and code the compiler writes
/// may already use the extensions it checks.
#[inline(never)]
pub fn cpu_lacks_build_features() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        let (max, _, _) = cpuid(0);
        let (_, _, leaf1) = cpuid(1);
        let leaf7 = if max >= 7 { cpuid(7).1 } else { 0 };
        let (ext_max, _, _) = cpuid(0x8000_0000);
        let ext1 = if ext_max >= 0x8000_0001 {
            cpuid(0x8000_0001).2
        } else {
            0
        };
        // Leaf 1, ecx: SSE3 0, SSSE3 9, FMA 12, CX16 13, SSE4.1 19, SSE4.2 20, MOVBE 22,
        // POPCNT 23, XSAVE 26, OSXSAVE 27, AVX 28, F16C 29.
        let v2 = (1 << 0) | (1 << 9) | (1 << 13) | (1 << 19) | (1 << 20) | (1 << 23);
        let v3 = (1 << 12) | (1 << 22) | (1 << 26) | (1 << 27) | (1 << 28) | (1 << 29);
        let lacks_v2 = cfg!(target_feature = "sse4.2") && !has_all(leaf1, v2);
        // Leaf 7, ebx: BMI1 3, AVX2 5, BMI2 8; leaf 0x8000_0001, ecx: LZCNT 5.
        let lacks_v3 = cfg!(target_feature = "avx2")
            && !(has_all(leaf1, v3)
                && has_all(leaf7, (1 << 3) | (1 << 5) | (1 << 8))
                && has_all(ext1, 1 << 5)
                // The system saves the vector registers: XCR0, read once `v3` has shown
                // OSXSAVE.
                && has_all(xcr0(), 0b110));
        lacks_v2 || lacks_v3
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// `(eax, ebx, ecx)` of `cpuid` at `leaf` (subleaf 0), in registers (`rbx`, which the compiler
/// keeps, saved around it).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn cpuid(leaf: u32) -> (u32, u32, u32) {
    let (eax, ebx, ecx): (u32, u32, u32);
    // SAFETY: `cpuid` is in the base instruction set; it writes eax, ebx, ecx and edx only.
    unsafe {
        std::arch::asm!(
            "mov {b:r}, rbx",
            "cpuid",
            "xchg {b:r}, rbx",
            b = out(reg) ebx,
            inout("eax") leaf => eax,
            inout("ecx") 0u32 => ecx,
            out("edx") _,
            options(nomem, nostack, preserves_flags),
        );
    }
    (eax, ebx, ecx)
}

/// Whether every bit of `mask` is set in `reg`, in base instructions (`and`, `cmp`, `sete`).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn has_all(reg: u32, mask: u32) -> bool {
    let set: u8;
    // SAFETY: register arithmetic only.
    unsafe {
        std::arch::asm!(
            "and {x:e}, {m:e}",
            "cmp {x:e}, {m:e}",
            "sete {r}",
            x = inout(reg) reg => _,
            m = in(reg) mask,
            r = out(reg_byte) set,
            options(pure, nomem, nostack),
        );
    }
    set != 0
}

/// The low word of `XCR0` (bits 1 and 2: the system saves the SSE and AVX registers); called
/// only where `cpuid` reports OSXSAVE (bit 27 of the `v3` mask).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn xcr0() -> u32 {
    let eax: u32;
    // SAFETY: `xgetbv` with ecx = 0 reads XCR0; the caller has checked OSXSAVE first.
    unsafe {
        std::arch::asm!(
            "xgetbv",
            in("ecx") 0u32,
            out("eax") eax,
            out("edx") _,
            options(nomem, nostack),
        );
    }
    eax
}

/// `(function, argument bits, second argument bits)` where glibc 2.36's FMA and SSE2 codes give
/// different results (found by evaluating 200,000 pseudo-random arguments with each code,
/// `GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA` selecting the SSE2 one).
const SEEN: &[(Fn, u64, u64)] = &[
    (Fn::Exp, 0x40312ffaf37b21ca, 0),
    (Fn::Exp, 0x403d073ef0ead6b8, 0),
    (Fn::Exp, 0xc038bffc0c6024fe, 0),
    (Fn::Sin, 0x40296547813bbe50, 0),
    (Fn::Sin, 0x405b6d374050643a, 0),
    (Fn::Cos, 0x40669ae4cedb6068, 0),
    (Fn::Cos, 0x406808869c725c37, 0),
    (Fn::SinCos, 0x4062c093596f0b96, 0),
    (Fn::SinCos, 0x40688f4077b5b3e7, 0),
    (Fn::Ln, 0x406254c4fa33c495, 0),
    (Fn::Ln, 0x405276bdb80cc152, 0),
    (Fn::Atan2, 0x3fe3e04a2d26166a, 0x3fd0b4cc325ae736),
    (Fn::Atan2, 0xbfa7317e9ee25fc0, 0x3fcef6436d4ec3ac),
    (Fn::Pow, 0x4045a5730650e7ee, 0xbfe7f266a12aa42e),
    (Fn::Pow, 0x40588ba1e4753289, 0xbfe2891eced6aa62),
    (Fn::ExpM1, 0x3fd30f5d9dd9fc58, 0),
    (Fn::ExpM1, 0x3ff14e0f6c416592, 0),
    (Fn::Ln1p, 0x3fcf11adf3f4b7e0, 0),
    (Fn::Ln1p, 0x3fd81adc9c2138c8, 0),
    (Fn::Sinh, 0x3fd23bdba2c94980, 0),
    (Fn::Sinh, 0x400e84ad63889376, 0),
    (Fn::Cosh, 0xc001c7ec66b89db9, 0),
    (Fn::Cosh, 0xc0040bd61e53e5c6, 0),
    (Fn::Log10, 0x401d9507e4ff7050, 0),
    (Fn::Log10, 0x4038fd9405a3a0fa, 0),
];

/// The functions of the platform's math library the records use.
#[derive(Clone, Copy, Debug)]
enum Fn {
    Exp,
    Sin,
    Cos,
    SinCos,
    Ln,
    Atan2,
    Pow,
    ExpM1,
    Ln1p,
    Sinh,
    Cosh,
    Log10,
}

const ALL: [Fn; 12] = [
    Fn::Exp,
    Fn::Sin,
    Fn::Cos,
    Fn::SinCos,
    Fn::Ln,
    Fn::Atan2,
    Fn::Pow,
    Fn::ExpM1,
    Fn::Ln1p,
    Fn::Sinh,
    Fn::Cosh,
    Fn::Log10,
];

/// Pseudo-random arguments per function beyond [`SEEN`] (about 1.4 differing results expected
/// per function between the two codes above; the cost is about a millisecond).
const SWEEP: u32 = 2048;

impl Fn {
    /// The function's bits at `(a, b)` (`b` read by the two-argument ones only), through
    /// `black_box` so that the compiler cannot fold the call with its own library.
    fn eval(self, a: f64, b: f64) -> [u64; 2] {
        let (a, b) = (black_box(a), black_box(b));
        let one = |y: f64| [y.to_bits(), 0];
        match self {
            Fn::Exp => one(a.exp()),
            Fn::Sin => one(a.sin()),
            Fn::Cos => one(a.cos()),
            Fn::SinCos => {
                let (s, c) = a.sin_cos();
                [s.to_bits(), c.to_bits()]
            }
            Fn::Ln => one(a.ln()),
            Fn::Atan2 => one(a.atan2(b)),
            Fn::Pow => one(a.powf(b)),
            Fn::ExpM1 => one(a.exp_m1()),
            Fn::Ln1p => one(a.ln_1p()),
            Fn::Sinh => one(a.sinh()),
            Fn::Cosh => one(a.cosh()),
            Fn::Log10 => one(a.log10()),
        }
    }

    /// A pseudo-random argument pair from two uniforms on `[0, 1)`, in the range the function
    /// sees in the closed forms and the fits.
    fn args(self, u: f64, w: f64) -> (f64, f64) {
        match self {
            Fn::Exp => ((u - 0.5) * 80.0, 0.0),
            Fn::Sin | Fn::Cos | Fn::SinCos | Fn::Ln | Fn::Log10 => (w * 200.0 + 1e-3, 0.0),
            Fn::Atan2 => (2.0 * u - 1.0, w - 0.5),
            Fn::Pow => (w * 200.0 + 1e-3, (u - 0.5) * 6.0),
            Fn::ExpM1 => ((u - 0.5) * 4.0, 0.0),
            Fn::Ln1p => (w * 2.0, 0.0),
            Fn::Sinh | Fn::Cosh => ((u - 0.5) * 20.0, 0.0),
        }
    }
}

/// The fingerprint of this process's math library: 16 hex digits, the XXH3-64 of the bits of
/// every function the records use at the arguments of [`SEEN`] and at [`SWEEP`] pseudo-random
/// ones each (a fixed xorshift stream). Two libraries with different fingerprints give
/// different records; equal fingerprints make it likely, not certain, that they give the same
/// (a difference in 1 result of 100,000 could pass unseen). Computed once per process.
pub fn fingerprint() -> &'static str {
    static FINGERPRINT: OnceLock<String> = OnceLock::new();
    FINGERPRINT.get_or_init(|| {
        let mut bits: Vec<u64> = Vec::with_capacity(2 * (SEEN.len() + ALL.len() * SWEEP as usize));
        for &(f, a, b) in SEEN {
            bits.extend(f.eval(f64::from_bits(a), f64::from_bits(b)));
        }
        let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut uniform = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..SWEEP {
            let (u, w) = (uniform(), uniform());
            for f in ALL {
                let (a, b) = f.args(u, w);
                bits.extend(f.eval(a, b));
            }
        }
        let bytes: Vec<u8> = bits.iter().flat_map(|b| b.to_le_bytes()).collect();
        format!("{:016x}", twox_hash::XxHash3_64::oneshot(&bytes))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fingerprint_is_sixteen_hex_digits_and_stable() {
        let f = fingerprint();
        assert_eq!(f.len(), 16);
        assert!(f.chars().all(|c| c.is_ascii_hexdigit()), "{f}");
        assert_eq!(f, fingerprint());
    }

    #[test]
    fn every_function_is_swept_and_seen() {
        for f in ALL {
            assert!(
                SEEN.iter()
                    .any(|&(g, _, _)| std::mem::discriminant(&g) == std::mem::discriminant(&f)),
                "{f:?} has no argument where the two codes were seen to differ"
            );
        }
    }
}
