//! The study parser fuzzed (issue 9, item 6): valid studies (the bundled configs and one that sets
//! every table) mutated by deleting keys, giving values of the wrong type, huge, tiny, NaN,
//! infinite and negative numbers, unicode and empty strings, duplicate and unknown axes, huge
//! grids, and by cutting, splicing and repeating the text. Whatever comes in: no panic, no hang,
//! and either a study or an error whose message starts with the file name (then the key, the
//! value and what is allowed). Through the binary (fewer cases): exit 0 or 2, with a message on
//! exit 2.

use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

use impactsweep::study::{LoadOptions, Study};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;
use toml::Value;

/// Failures found, replayed first on every run (relative to the package root, where `cargo test`
/// runs the tests). The first, a table given as a list (`[reliability] = []`), got serde's
/// "invalid length 0, expected struct RawReliability with 8 elements"; it now says "must be a
/// table".
const REGRESSIONS: &str = "proptest-regressions/study_fuzz.txt";

/// A study that sets every table and key the parser knows.
const FULL: &str = r#"
[study]
name = "full"
seed = 7
outputs = ["xmax", "di", "t1"]

[system]
M = 0.1
m = 0.02
K = 400.0
C = 0.1
d = 0.01
e = 0.8
x0 = 0.0
v0 = 2.0
y0 = 0.0
w0 = 0.0

[sweep]
e = { start = 0.45, stop = 0.95, num = 6 }
m = [0.015, 0.02, 0.025]
d = { start = 0.005, stop = 0.015, step = 0.005 }

[noise]
power = 5e-10
sample_time = 1e-3

[perturb]
dm = [0.0, 0.001]
dd = [-0.001, 0.0]
noise_seeds = [1, 2]

[solver]
kind = "exact"
tol = 1e-10

[reliability]
E = 200e9
r = 3.4e-3
L = 0.5
strength_mean = 285e6
strength_sd = 20e6
safety_form = "exact"
bootstrap = 100
confidence = 0.9

[zones]
jump_k = 5.0
r_min = 0.95

[ranking]
wf1 = 0.4
wf2 = 0.6
di_source = "mean"

[run]
chunk_points = 4
audit = 2
"#;

fn bases() -> Vec<String> {
    let configs = Path::new(env!("CARGO_MANIFEST_DIR")).join("configs");
    let mut texts = vec![FULL.to_string()];
    for name in ["paper.toml", "quick.toml", "overnight.toml"] {
        texts.push(std::fs::read_to_string(configs.join(name)).unwrap());
    }
    texts
}

/// One step of a path into a TOML document.
#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

/// Every path to a value in `v` (tables by key, arrays by index).
fn paths(v: &Value, at: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match v {
        Value::Table(t) => {
            for (k, x) in t {
                at.push(Step::Key(k.clone()));
                out.push(at.clone());
                paths(x, at, out);
                at.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                at.push(Step::Index(i));
                out.push(at.clone());
                paths(x, at, out);
                at.pop();
            }
        }
        _ => {}
    }
}

/// The parent of the value at `path` and the last step.
fn parent<'a>(root: &'a mut Value, path: &[Step]) -> Option<(&'a mut Value, Step)> {
    let (last, head) = path.split_last()?;
    let mut v = root;
    for s in head {
        v = match (s, v) {
            (Step::Key(k), Value::Table(t)) => t.get_mut(k)?,
            (Step::Index(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some((v, last.clone()))
}

/// What a mutation does.
#[derive(Clone, Debug)]
enum Mutation {
    /// Removes the value at the `n`-th path.
    Delete(usize),
    /// Replaces the value at the `n`-th path.
    Replace(usize, Value),
    /// Adds `key = value` to the table at the `n`-th path (or the root).
    Insert(usize, String, Value),
    /// Cuts the text at a fraction of its length.
    Truncate(f64),
    /// Inserts a string at a fraction of the text's length.
    Splice(f64, String),
    /// Repeats the line at a fraction of the text's lines (a duplicate key or table).
    RepeatLine(f64),
}

fn number() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Float(f64::NAN)),
        Just(Value::Float(f64::INFINITY)),
        Just(Value::Float(f64::NEG_INFINITY)),
        Just(Value::Float(1e308)),
        Just(Value::Float(-1e308)),
        Just(Value::Float(5e-324)),
        Just(Value::Float(-0.0)),
        Just(Value::Float(0.0)),
        Just(Value::Integer(i64::MAX)),
        Just(Value::Integer(i64::MIN)),
        Just(Value::Integer(-1)),
        Just(Value::Integer(0)),
        Just(Value::Integer(1)),
        Just(Value::Integer(10_000_000_000)),
        any::<f64>().prop_map(Value::Float),
        (-1e3..1e3f64).prop_map(Value::Float),
        any::<i64>().prop_map(Value::Integer),
    ]
}

fn text() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("..".to_string()),
        Just("a/b".to_string()),
        Just("ünïcødé_名前".to_string()),
        Just("e".to_string()),
        Just("M".to_string()),
        "\\PC{0,16}",
    ]
}

fn value() -> impl Strategy<Value = Value> {
    let leaf = prop_oneof![
        4 => number(),
        2 => text().prop_map(Value::String),
        1 => any::<bool>().prop_map(Value::Boolean),
    ];
    let axis = prop_oneof![
        // Huge and tiny grids, steps that do not divide, reversed ranges.
        (number(), number(), number()).prop_map(|(a, b, n)| {
            let mut t = toml::Table::new();
            t.insert("start".into(), a);
            t.insert("stop".into(), b);
            t.insert("num".into(), n);
            Value::Table(t)
        }),
        (number(), number(), number()).prop_map(|(a, b, s)| {
            let mut t = toml::Table::new();
            t.insert("start".into(), a);
            t.insert("stop".into(), b);
            t.insert("step".into(), s);
            Value::Table(t)
        }),
        prop::collection::vec(number(), 0..5).prop_map(Value::Array),
    ];
    prop_oneof![
        6 => leaf.clone(),
        2 => axis,
        1 => prop::collection::vec(leaf, 0..4).prop_map(Value::Array),
        1 => Just(Value::Table(toml::Table::new())),
    ]
}

fn key() -> impl Strategy<Value = String> {
    prop_oneof![
        // Axis and system keys (some swept twice: `m` and `M`, `e` again), unknown and unicode.
        Just("e".to_string()),
        Just("m".to_string()),
        Just("M".to_string()),
        Just("d".to_string()),
        Just("K".to_string()),
        Just("name".to_string()),
        Just("chunk_points".to_string()),
        Just("cases".to_string()),
        "\\PC{1,8}",
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => any::<usize>().prop_map(Mutation::Delete),
        6 => (any::<usize>(), value()).prop_map(|(n, v)| Mutation::Replace(n, v)),
        2 => (any::<usize>(), key(), value()).prop_map(|(n, k, v)| Mutation::Insert(n, k, v)),
        1 => (0.0..1.0f64).prop_map(Mutation::Truncate),
        1 => (0.0..1.0f64, prop_oneof![
            Just("\"".to_string()),
            Just("[".to_string()),
            Just("\n[sweep]\n".to_string()),
            Just("é".to_string()),
            Just("\u{0}".to_string()),
            "\\PC{0,6}",
        ])
            .prop_map(|(at, s)| Mutation::Splice(at, s)),
        1 => (0.0..1.0f64).prop_map(Mutation::RepeatLine),
    ]
}

/// The char boundary at or before `at` of the text's length.
fn boundary(s: &str, at: f64) -> usize {
    let mut i = ((s.len() as f64) * at) as usize;
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// A mutation of the text itself (the others do nothing here).
fn apply_raw(t: &mut String, m: &Mutation) {
    match m {
        Mutation::Truncate(at) => t.truncate(boundary(t, *at)),
        Mutation::Splice(at, s) => t.insert_str(boundary(t, *at), s),
        Mutation::RepeatLine(at) => {
            let lines: Vec<&str> = t.lines().collect();
            if !lines.is_empty() {
                let i = ((lines.len() as f64 * at) as usize).min(lines.len() - 1);
                *t = format!("{}\n{}", t, lines[i]);
            }
        }
        _ => {}
    }
}

/// A base study with the mutations applied, as text.
fn mutate(base: &str, muts: &[Mutation]) -> String {
    let mut doc: Value = Value::Table(toml::from_str(base).unwrap());
    let mut text: Option<String> = None;
    for m in muts {
        if let Some(t) = &mut text {
            // Once the text is raw, only raw mutations apply.
            apply_raw(t, m);
            continue;
        }
        let mut all = Vec::new();
        paths(&doc, &mut Vec::new(), &mut all);
        match m {
            Mutation::Delete(n) if !all.is_empty() => {
                if let Some((p, last)) = parent(&mut doc, &all[n % all.len()]) {
                    match (p, last) {
                        (Value::Table(t), Step::Key(k)) => {
                            t.remove(&k);
                        }
                        (Value::Array(a), Step::Index(i)) if i < a.len() => {
                            a.remove(i);
                        }
                        _ => {}
                    }
                }
            }
            Mutation::Replace(n, v) if !all.is_empty() => {
                if let Some((p, last)) = parent(&mut doc, &all[n % all.len()]) {
                    match (p, last) {
                        (Value::Table(t), Step::Key(k)) => {
                            t.insert(k, v.clone());
                        }
                        (Value::Array(a), Step::Index(i)) if i < a.len() => a[i] = v.clone(),
                        _ => {}
                    }
                }
            }
            Mutation::Insert(n, k, v) => {
                let tables: Vec<&Vec<Step>> = all.iter().filter(|p| p.len() == 1).collect();
                let target = if tables.is_empty() {
                    Some(&mut doc)
                } else {
                    let p = tables[n % tables.len()].clone();
                    parent(&mut doc, &p).and_then(|(t, last)| match (t, last) {
                        (Value::Table(t), Step::Key(key)) => t.get_mut(&key),
                        _ => None,
                    })
                };
                if let Some(Value::Table(t)) = target {
                    t.insert(k.clone(), v.clone());
                }
            }
            Mutation::Truncate(_) | Mutation::Splice(..) | Mutation::RepeatLine(_) => {
                let mut t = toml::to_string(&doc).unwrap_or_default();
                apply_raw(&mut t, m);
                text = Some(t);
            }
            _ => {}
        }
    }
    text.unwrap_or_else(|| toml::to_string(&doc).unwrap_or_default())
}

/// Parses on another thread with a deadline: a hang fails the test instead of stalling it.
fn parse_in_time(text: &str, allow_large: bool) -> Result<Result<Study, String>, String> {
    let (tx, rx) = mpsc::channel();
    let owned = text.to_string();
    std::thread::spawn(move || {
        let r = std::panic::catch_unwind(|| {
            Study::parse_with(Path::new("fuzz.toml"), &owned, LoadOptions { allow_large })
                .map_err(|e| e.to_string())
        });
        let _ = tx.send(r);
    });
    match rx.recv_timeout(Duration::from_secs(20)) {
        Ok(Ok(r)) => Ok(r),
        Ok(Err(_)) => Err("panicked".into()),
        Err(_) => Err("did not finish within 20 s".into()),
    }
}

fn base_and_mutations() -> impl Strategy<Value = (usize, Vec<Mutation>)> {
    (0..4usize, prop::collection::vec(mutation(), 1..4))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("FUZZ_CASES").ok().and_then(|c| c.parse().ok()).unwrap_or(400),
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(REGRESSIONS))),
        ..ProptestConfig::default()
    })]

    /// Never a panic or a hang; an error names the file first.
    #[test]
    fn a_mutated_study_parses_or_says_why((base, muts) in base_and_mutations()) {
        let text = mutate(&bases()[base], &muts);
        for allow_large in [false, true] {
            match parse_in_time(&text, allow_large) {
                Err(why) => prop_assert!(false, "{why} on:\n{text}"),
                Ok(Ok(_)) => {}
                Ok(Err(msg)) => {
                    prop_assert!(msg.starts_with("fuzz.toml"), "message without the file: {msg}");
                    prop_assert!(msg.len() > "fuzz.toml: ".len() + 10, "message too short: {msg}");
                    // The parser's own type names are no words for a user.
                    prop_assert!(!msg.contains("Raw") && !msg.contains("struct "), "{msg}");
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(REGRESSIONS))),
        ..ProptestConfig::default()
    })]

    /// Through the binary (`slurm --dry-run`, which validates the study and writes two scripts,
    /// simulating nothing): exit 0, or 2 with `error: fuzz.toml…`.
    #[test]
    fn the_binary_exits_0_or_2_on_a_mutated_study((base, muts) in base_and_mutations()) {
        let text = mutate(&bases()[base], &muts);
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join("fuzz.toml"), &text).unwrap();
        let out = assert_cmd::Command::cargo_bin("impactsweep")
            .unwrap()
            .current_dir(tmp.path())
            .args(["slurm", "fuzz.toml", "--dry-run", "--tasks", "1", "--out", "out"])
            .timeout(Duration::from_secs(60))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        match out.status.code() {
            Some(0) => {}
            Some(2) => prop_assert!(err.starts_with("error: fuzz.toml"), "{err}"),
            other => prop_assert!(false, "exit {other:?}: {err}\non:\n{text}"),
        }
    }
}

/// Issue 9 (found by the fuzzer): a table given as a list got serde's words ("invalid length 0,
/// expected struct RawReliability with 8 elements").
#[test]
fn issue_9_a_table_given_as_a_list_must_be_a_table() {
    for (text, want) in [
        (
            "reliability = []\n[study]\nname = \"t\"\n",
            "t.toml: [reliability] = []: must be a table",
        ),
        (
            "[study]\nname = \"t\"\n[perturb]\ncases = [[0.001, 0.0]]\n",
            "t.toml: [perturb].cases[0] = [0.001, 0.0]: must be a table",
        ),
    ] {
        let err = Study::parse(Path::new("t.toml"), text).unwrap_err();
        assert_eq!(err.to_string(), want);
    }
}
