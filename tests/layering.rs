//! The layering the code promises (issues 25 and 45; `docs/architecture.md` states the rules).
//!
//! Each module's imports are read from its source: every `use` tree expanded to its paths, and
//! every path written in the code that starts with `crate::`, `super::` or `self::`, resolved to
//! the module it names (`crate::reduce::core::tables::outcome_text` names
//! `reduce::core::tables`). Comments and the unit tests (from the first `#[cfg(test)]` on) are
//! left out: a doc link is no import, and a test may use anything. A path that starts with a name
//! a `use` brought in (`forced::design_study` after `use crate::reduce::forced`) is covered by
//! that `use`.
//!
//! The rules:
//! * no import circle among the modules of any folder of `src/` (the crate's own top-level
//!   modules included): a module never imports one that imports it back, directly or through
//!   others; in particular `orbits::continuation` and `orbits::locate`, and the forced scene's
//!   modules in `reduce/forced/`, form no circle;
//! * the store never imports the reducer, the report, the sweep or the command line's layers;
//! * the reducer never imports the report, the sweep, the API or the command line;
//! * `reduce/core/` knows no scene: it imports neither `reduce::free`, `reduce::forced` nor
//!   `reduce::random`, nor the scenes' layers below it (`orbits`, `sim::forced`, `sim::random`);
//! * a scene module of `reduce/` never imports another scene's;
//! * the report's scene-independent modules (`report/text.rs`, `charts/plumbing.rs`,
//!   `charts/core/`, `markdown/core/`, `html/`) import no scene module, of the report or of the
//!   reducer, and a scene module of the report never imports another scene's;
//! * the library never imports the command line's layer (`app`; `cli.rs` and `main.rs` are the
//!   command line), and the Python binding (`python/src`) never does either;
//! * only the store knows arrow and parquet, only the report knows plotters, only `cli.rs` knows
//!   clap;
//! * the simulator and the steady-state and statistics layers below the pipeline (`sim`,
//!   `orbits`, `stats`) do no I/O (`std::fs`) and import no layer above them.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// One source file of the library: its module path (`reduce::core::tables`; `""` for `lib.rs`)
/// and its code.
struct Source {
    file: PathBuf,
    module: Vec<String>,
    code: String,
}

/// Every `.rs` file below `dir`.
fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rs_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The code of a file: before its unit tests, without comments.
fn code_of(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .map(|l| match l.find("//") {
            // A `//` inside a string (a URL) is rare in this code; the lines that matter are
            // `use` lines and paths, which hold none.
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The library's sources (not `main.rs`, the binary).
fn sources() -> Vec<Source> {
    let src = root().join("src");
    let mut files = Vec::new();
    rs_files(&src, &mut files);
    files.sort();
    files
        .into_iter()
        .filter(|f| f.file_name().is_some_and(|n| n != "main.rs"))
        .map(|file| {
            let rel = file.strip_prefix(&src).unwrap().with_extension("");
            let mut module: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().to_string())
                .collect();
            if matches!(module.last().map(String::as_str), Some("mod" | "lib")) {
                module.pop();
            }
            let code = code_of(&std::fs::read_to_string(&file).unwrap());
            Source { file, module, code }
        })
        .collect()
}

/// The `use` trees of `code`, each expanded to its full paths (`a::{b, c::{d, e}}` gives
/// `a::b`, `a::c::d`, `a::c::e`; `self` in braces names the prefix).
fn use_paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = find_use(rest) {
        let after = &rest[i..];
        let end = after.find(';').unwrap_or(after.len());
        // One space between words (`c as d`), none around the punctuation of a tree.
        let mut tree = after[..end]
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        for p in ["::", "{", "}", ","] {
            tree = tree
                .replace(&format!(" {p}"), p)
                .replace(&format!("{p} "), p);
        }
        expand("", &tree, &mut out);
        rest = &after[end..];
    }
    out
}

/// The byte offset of the next `use` tree's first path segment (after `use ` or `pub use `, at
/// the start of a statement).
fn find_use(code: &str) -> Option<usize> {
    let mut from = 0;
    while let Some(i) = code[from..].find("use ") {
        let at = from + i;
        let before = code[..at].trim_end();
        let starts = before.is_empty()
            || before.ends_with(';')
            || before.ends_with('{')
            || before.ends_with('}')
            || before.ends_with(']')
            || before.ends_with("pub")
            || before.ends_with(')');
        let word = at == 0 || !code.as_bytes()[at - 1].is_ascii_alphanumeric();
        if starts && word {
            return Some(at + 4);
        }
        from = at + 4;
    }
    None
}

fn expand(prefix: &str, tree: &str, out: &mut Vec<String>) {
    let join = |p: &str, s: &str| {
        if p.is_empty() {
            s.to_string()
        } else if s == "self" {
            p.to_string()
        } else {
            format!("{p}::{s}")
        }
    };
    match tree.find('{') {
        None => {
            let path = tree.split(" as ").next().unwrap_or(tree);
            out.push(join(prefix, path.trim_end_matches("::*")));
        }
        Some(b) => {
            let head = tree[..b].trim_end_matches("::");
            let inner = &tree[b + 1..tree.rfind('}').unwrap_or(tree.len())];
            let base = join(prefix, head);
            let (mut depth, mut start) = (0, 0);
            for (i, c) in inner.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        if i > start {
                            expand(&base, &inner[start..i], out);
                        }
                        start = i + 1;
                    }
                    _ => {}
                }
            }
            if inner.len() > start {
                expand(&base, &inner[start..], out);
            }
        }
    }
}

/// The paths written in `code` that start with `crate::`, `super::` or `self::`.
fn inline_paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    for start in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(i) = code[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            if at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_') {
                continue;
            }
            let mut end = at;
            while end < bytes.len()
                && (bytes[end].is_ascii_alphanumeric()
                    || bytes[end] == b'_'
                    || code[end..].starts_with("::"))
            {
                end += if code[end..].starts_with("::") { 2 } else { 1 };
            }
            let path = code[at..end].trim_end_matches("::");
            // A bare `super` (`super::{a, b}` is a use tree, read as such) names nothing more.
            if path.contains("::") {
                out.push(path.to_string());
            }
        }
    }
    out
}

/// `path` (as written in a file of module `module`) as a path from the crate's root; `None` for
/// a path that starts elsewhere (a dependency, a name brought in by `use`). `super` in `a/b.rs`
/// and in `a/b/mod.rs` alike names `a`.
fn resolve(module: &[String], path: &str) -> Option<Vec<String>> {
    let mut segs = path.split("::").filter(|s| !s.is_empty());
    let first = segs.next()?;
    let mut here: Vec<String> = module.to_vec();
    let mut out = match first {
        "crate" => Vec::new(),
        "self" => here.clone(),
        "super" => {
            here.pop();
            here.clone()
        }
        _ => return None,
    };
    for s in segs {
        if s == "super" {
            out.pop();
        } else {
            out.push(s.to_string());
        }
    }
    Some(out)
}

/// Every module path each source refers to (see the module doc), by source.
fn imports(sources: &[Source]) -> Vec<(usize, Vec<Vec<String>>)> {
    sources
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let paths: Vec<Vec<String>> = use_paths(&s.code)
                .into_iter()
                .chain(inline_paths(&s.code))
                .filter_map(|p| resolve(&s.module, &p))
                .collect();
            (i, paths)
        })
        .collect()
}

fn starts_with(path: &[String], prefix: &str) -> bool {
    let p: Vec<&str> = prefix.split("::").collect();
    path.len() >= p.len() && path.iter().zip(&p).all(|(a, b)| a == b)
}

fn module_name(s: &Source) -> String {
    s.module.join("::")
}

/// The sources under module `prefix` (the module itself and everything below it).
fn under<'a>(sources: &'a [Source], prefix: &str) -> impl Iterator<Item = usize> + 'a {
    let prefix = prefix.to_string();
    sources
        .iter()
        .enumerate()
        .filter(move |(_, s)| starts_with(&s.module, &prefix))
        .map(|(i, _)| i)
}

/// The imports of the sources under `from` that name a module under any of `forbidden`, as
/// `file -> module` lines.
fn violations(sources: &[Source], from: &[&str], forbidden: &[&str]) -> Vec<String> {
    let all = imports(sources);
    let mut out = BTreeSet::new();
    for prefix in from {
        for i in under(sources, prefix) {
            for p in &all[i].1 {
                if let Some(f) = forbidden.iter().find(|f| starts_with(p, f)) {
                    out.insert(format!(
                        "{} -> {f} ({})",
                        module_name(&sources[i]),
                        p.join("::")
                    ));
                }
            }
        }
    }
    out.into_iter().collect()
}

fn assert_none(what: &str, v: Vec<String>) {
    assert!(v.is_empty(), "{what}:\n  {}", v.join("\n  "));
}

/// The folders of `src/` (as module paths, the crate's root `""` first) and their child
/// modules.
fn folders(sources: &[Source]) -> BTreeMap<Vec<String>, BTreeSet<String>> {
    let mut out: BTreeMap<Vec<String>, BTreeSet<String>> = BTreeMap::new();
    for s in sources {
        for k in 0..s.module.len() {
            out.entry(s.module[..k].to_vec())
                .or_default()
                .insert(s.module[k].clone());
        }
    }
    out
}

/// The import graph among the child modules of folder `folder`: child `a` imports child `b`
/// when a source under `a` names a module under `b`.
fn graph(sources: &[Source], folder: &[String]) -> BTreeMap<String, BTreeSet<String>> {
    let children = folders(sources).remove(folder).unwrap_or_default();
    let all = imports(sources);
    let mut g: BTreeMap<String, BTreeSet<String>> = children
        .iter()
        .map(|c| (c.clone(), BTreeSet::new()))
        .collect();
    for (i, paths) in &all {
        let s = &sources[*i];
        if s.module.len() <= folder.len() || s.module[..folder.len()] != *folder {
            continue;
        }
        let from = &s.module[folder.len()];
        for p in paths {
            if p.len() > folder.len() && p[..folder.len()] == *folder {
                let to = &p[folder.len()];
                if to != from && children.contains(to) {
                    g.get_mut(from).unwrap().insert(to.clone());
                }
            }
        }
    }
    g
}

/// A cycle of `g`, if there is one.
fn cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        g: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == n) {
            let mut c = path[i..].to_vec();
            c.push(n.to_string());
            return Some(c);
        }
        if done.contains(n) {
            return None;
        }
        path.push(n.to_string());
        for m in &g[n] {
            if let Some(c) = visit(m, g, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(n.to_string());
        None
    }
    let mut done = BTreeSet::new();
    g.keys()
        .find_map(|n| visit(n, g, &mut Vec::new(), &mut done))
}

/// The sources whose code names a crate (`arrow::`, `use arrow`), outside the modules allowed.
fn crate_users(sources: &[Source], krate: &str, allowed: &[&str]) -> Vec<String> {
    sources
        .iter()
        .filter(|s| !allowed.iter().any(|a| starts_with(&s.module, a)))
        .filter(|s| {
            use_paths(&s.code)
                .iter()
                .any(|p| p == krate || p.starts_with(&format!("{krate}::")))
                || s.code.match_indices(&format!("{krate}::")).any(|(i, _)| {
                    i == 0 || {
                        let b = s.code.as_bytes()[i - 1];
                        !(b.is_ascii_alphanumeric() || b == b'_' || b == b':')
                    }
                })
        })
        .map(|s| s.file.strip_prefix(root()).unwrap().display().to_string())
        .collect()
}

#[test]
fn the_import_reader_sees_what_the_code_imports() {
    // The reader itself, on code it must read right: a nested use tree, `self` in braces, a
    // renamed import, `super` from a folder's `mod.rs` and from a file in it, an inline path.
    let code = code_of(
        "use super::{a, b::{self, c as d}};\n// use crate::nope;\npub use crate::x::y;\n\
         fn f() { crate::z::w(); }\n#[cfg(test)]\nmod tests { use crate::t; }",
    );
    let mut got: BTreeSet<String> = use_paths(&code).into_iter().collect();
    got.extend(inline_paths(&code));
    let want = [
        "super::a",
        "super::b",
        "super::b::c",
        "crate::x::y",
        "crate::z::w",
    ];
    assert_eq!(got, want.iter().map(|s| s.to_string()).collect());
    let m = |s: &str| s.split("::").map(String::from).collect::<Vec<_>>();
    assert_eq!(
        resolve(&m("reduce::forced"), "super::core"),
        Some(m("reduce::core"))
    );
    assert_eq!(
        resolve(&m("reduce::forced::probe"), "super::analysis::Plan"),
        Some(m("reduce::forced::analysis::Plan"))
    );
    assert_eq!(resolve(&m("a"), "arrow::array"), None);
}

#[test]
fn issue_25_the_python_binding_imports_nothing_from_the_command_line() {
    for e in std::fs::read_dir(root().join("python/src")).unwrap() {
        let p = e.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(
            !text.contains("impactsweep::app"),
            "{} imports the command line's layer (impactsweep::app); use impactsweep::api",
            p.display()
        );
    }
}

#[test]
fn issue_25_no_import_circles_in_app_and_study() {
    let sources = sources();
    for folder in ["app", "study"] {
        let g = graph(&sources, &[folder.to_string()]);
        assert!(g.len() >= 5, "{folder}: {g:?}");
        if let Some(c) = cycle(&g) {
            panic!("src/{folder}: an import circle: {}", c.join(" -> "));
        }
    }
}

#[test]
fn issue_45_no_import_circles_in_any_folder() {
    let sources = sources();
    let all = folders(&sources);
    // The folders the issue named among them, so that a rename cannot leave them unchecked.
    for named in [
        "",
        "orbits",
        "reduce",
        "reduce::core",
        "reduce::forced",
        "report",
    ] {
        let key: Vec<String> = named
            .split("::")
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        assert!(all.contains_key(&key), "no folder src/{named}");
    }
    for folder in all.keys() {
        let g = graph(&sources, folder);
        if let Some(c) = cycle(&g) {
            panic!(
                "src/{}: an import circle: {}",
                folder.join("/"),
                c.join(" -> ")
            );
        }
    }
    // orbits: continuation imports locate, never the other way (the labels they share live in
    // orbits::label, below both).
    let g = graph(&sources, &["orbits".to_string()]);
    assert!(g["continuation"].contains("locate") && !g["locate"].contains("continuation"));
}

#[test]
fn issue_45_the_store_never_imports_the_layers_above_it() {
    assert_none(
        "the store imports a layer above it",
        violations(
            &sources(),
            &["store"],
            &["reduce", "report", "sweep", "api", "app", "cli"],
        ),
    );
}

#[test]
fn issue_45_the_reducer_never_imports_the_layers_above_it() {
    assert_none(
        "the reducer imports a layer above it",
        violations(
            &sources(),
            &["reduce"],
            &["report", "sweep", "api", "app", "cli"],
        ),
    );
}

#[test]
fn issue_45_the_reducers_core_knows_no_scene() {
    let sources = sources();
    assert!(under(&sources, "reduce::core").count() >= 10);
    assert_none(
        "reduce/core imports a scene",
        violations(
            &sources,
            &["reduce::core"],
            &[
                "reduce::free",
                "reduce::forced",
                "reduce::random",
                "orbits",
                "sim::forced",
                "sim::random",
            ],
        ),
    );
}

#[test]
fn issue_45_no_scene_imports_another() {
    let sources = sources();
    for (layer, scenes) in [
        ("reduce", &["free", "forced", "random"][..]),
        ("report::charts", &["free", "forced", "random"][..]),
        ("report::markdown", &["forced", "random"][..]),
    ] {
        for scene in scenes {
            let from = format!("{layer}::{scene}");
            assert!(under(&sources, &from).count() >= 1, "no module {from}");
            // Another scene's module of this layer, or of the reducer below it.
            let others: Vec<String> = ["free", "forced", "random"]
                .iter()
                .filter(|o| *o != scene)
                .flat_map(|o| [format!("{layer}::{o}"), format!("reduce::{o}")])
                .collect();
            let others: Vec<&str> = others.iter().map(String::as_str).collect();
            assert_none(
                &format!("{from} imports another scene"),
                violations(&sources, &[&from], &others),
            );
        }
    }
}

#[test]
fn issue_45_the_reports_core_knows_no_scene() {
    let core = [
        "report::text",
        "report::charts::plumbing",
        "report::charts::core",
        "report::markdown::core",
        "report::html",
    ];
    let sources = sources();
    for c in core {
        assert!(under(&sources, c).count() >= 1, "no module {c}");
    }
    assert_none(
        "a scene-independent module of the report imports a scene",
        violations(
            &sources,
            &core,
            &[
                "report::charts::free",
                "report::charts::forced",
                "report::charts::random",
                "report::markdown::forced",
                "report::markdown::random",
                "reduce::free",
                "reduce::forced",
                "reduce::random",
                "orbits",
                "sim::forced",
                "sim::random",
            ],
        ),
    );
}

#[test]
fn issue_45_the_library_never_imports_the_command_line() {
    let sources = sources();
    let library: Vec<String> = folders(&sources)[&Vec::new()]
        .iter()
        .filter(|m| !matches!(m.as_str(), "app" | "cli"))
        .cloned()
        .collect();
    let library: Vec<&str> = library.iter().map(String::as_str).collect();
    assert!(library.contains(&"api") && library.contains(&"reduce"));
    assert_none(
        "the library imports the command line's layer",
        violations(&sources, &library, &["app", "cli"]),
    );
}

#[test]
fn issue_45_each_dependency_is_known_by_its_one_layer() {
    let sources = sources();
    for (krate, allowed) in [
        ("arrow", &["store"][..]),
        ("parquet", &["store"][..]),
        ("plotters", &["report"][..]),
        ("clap", &["cli"][..]),
    ] {
        let users = crate_users(&sources, krate, allowed);
        assert!(
            users.is_empty(),
            "only {allowed:?} may know {krate}; these files do too: {users:?}"
        );
        assert!(
            !crate_users(&sources, krate, &[]).is_empty(),
            "nothing uses {krate}: is the rule still needed?"
        );
    }
}

#[test]
fn issue_45_the_pure_layers_do_no_io_and_import_nothing_above_them() {
    let sources = sources();
    let pure = ["sim", "orbits", "stats"];
    assert_none(
        "a pure layer imports one above it",
        violations(
            &sources,
            &pure,
            &["store", "sweep", "reduce", "report", "api", "app", "cli"],
        ),
    );
    let io: Vec<String> = pure
        .iter()
        .flat_map(|p| under(&sources, p))
        .filter(|&i| sources[i].code.contains("std::fs"))
        .map(|i| module_name(&sources[i]))
        .collect();
    assert!(io.is_empty(), "file I/O in a pure layer: {io:?}");
}
