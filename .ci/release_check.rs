//! Release checks of the published crate, for `.ci/run`. A single file with no
//! dependency, so a fresh machine with only a Rust toolchain builds it with `rustc`
//! (no python, no jq):
//!
//! ```sh
//! rustc --edition 2021 -o target/ci/release-check .ci/release_check.rs
//! target/ci/release-check rust-version   # rust-version >= every dependency's
//! target/ci/release-check package-list   # ships only sources, README, CHANGELOG, licences
//! target/ci/release-check readme-links   # README links resolve from the packaged crate
//! ```
//!
//! Each takes `--package NAME` (default `rapier-contact-graph`) and runs `cargo`
//! (`$CARGO`, else `cargo`) from the current directory, the workspace root.

use std::collections::{BTreeMap, BTreeSet, HashSet};
use std::path::{Path, PathBuf};
use std::process::{exit, Command};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut package = "rapier-contact-graph".to_string();
    let mut command = None;
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "--package" | "-p" if i + 1 < args.len() => {
                package = args[i + 1].clone();
                i += 1;
            }
            c if command.is_none() && !c.starts_with('-') => command = Some(c.to_string()),
            other => fail(&format!("unexpected argument {other:?}")),
        }
        i += 1;
    }
    let result = match command.as_deref() {
        Some("rust-version") => rust_version(&package),
        Some("package-list") => package_list(&package),
        Some("readme-links") => readme_links(&package),
        _ => Err(
            "usage: release-check rust-version|package-list|readme-links [--package NAME]"
                .to_string(),
        ),
    };
    if let Err(message) = result {
        fail(&message);
    }
}

fn fail(message: &str) -> ! {
    eprintln!("release-check: {message}");
    exit(1);
}

fn cargo(args: &[&str]) -> Result<String, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let out = Command::new(&cargo)
        .args(args)
        .output()
        .map_err(|e| format!("cannot run {cargo}: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "`cargo {}` failed:\n{}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    String::from_utf8(out.stdout).map_err(|e| e.to_string())
}

fn metadata(no_deps: bool) -> Result<Json, String> {
    let mut args = vec![
        "metadata",
        "--format-version",
        "1",
        "--locked",
        "--all-features",
    ];
    if no_deps {
        args.push("--no-deps");
    }
    Json::parse(&cargo(&args)?)
}

/// The workspace member named `name`.
fn member<'a>(meta: &'a Json, name: &str) -> Result<&'a Json, String> {
    let members: HashSet<&str> = meta["workspace_members"]
        .iter()
        .filter_map(Json::as_str)
        .collect();
    meta["packages"]
        .iter()
        .find(|p| {
            p["name"].as_str() == Some(name) && members.contains(p["id"].as_str().unwrap_or(""))
        })
        .ok_or_else(|| format!("no workspace member named {name}"))
}

// ---------------------------------------------------------------------------------
// rust-version

/// `1.86` or `1.89.0` as (major, minor, patch).
fn version(text: &str) -> Option<(u64, u64, u64)> {
    let mut parts = text.split('.').map(|p| p.parse::<u64>().ok());
    let major = parts.next()??;
    let minor = parts.next().unwrap_or(Some(0))?;
    let patch = parts.next().unwrap_or(Some(0))?;
    Some((major, minor, patch))
}

/// Fails if the package's `rust-version` is lower than the highest `rust-version`
/// declared by a package it depends on (normal and build dependencies, transitively,
/// all features, every target platform, as resolved in Cargo.lock; dev-dependencies
/// are not a user's).
fn rust_version(name: &str) -> Result<(), String> {
    let meta = metadata(false)?;
    let root = member(&meta, name)?;
    let own_text = root["rust_version"]
        .as_str()
        .ok_or_else(|| format!("{name} declares no rust-version"))?;
    let own = version(own_text).ok_or_else(|| format!("bad rust-version {own_text:?}"))?;

    let packages: BTreeMap<&str, &Json> = meta["packages"]
        .iter()
        .map(|p| (p["id"].as_str().unwrap_or(""), p))
        .collect();
    let nodes: BTreeMap<&str, &Json> = meta["resolve"]["nodes"]
        .iter()
        .map(|n| (n["id"].as_str().unwrap_or(""), n))
        .collect();
    let mut seen = BTreeSet::new();
    let mut stack = vec![root["id"].as_str().unwrap_or("")];
    while let Some(id) = stack.pop() {
        let node = nodes
            .get(id)
            .ok_or_else(|| format!("{id} not in the resolve graph"))?;
        for dep in node["deps"].iter() {
            let used = dep["dep_kinds"]
                .iter()
                .any(|k| matches!(k["kind"].as_str(), None | Some("build")));
            let pkg = dep["pkg"].as_str().unwrap_or("");
            if used && seen.insert(pkg) {
                stack.push(pkg);
            }
        }
    }
    let mut declared: Vec<((u64, u64, u64), String)> = Vec::new();
    for id in &seen {
        let p = packages
            .get(id)
            .ok_or_else(|| format!("{id} not among the packages"))?;
        if let Some(text) = p["rust_version"].as_str() {
            let v = version(text).ok_or_else(|| format!("bad rust-version {text:?} in {id}"))?;
            let label = format!(
                "{} {} (rust-version {text})",
                str_of(&p["name"]),
                str_of(&p["version"])
            );
            declared.push((v, label));
        }
    }
    declared.sort();
    declared.reverse();
    let Some((highest, _)) = declared.first().cloned() else {
        println!("{name}: rust-version {own_text}; no dependency declares one");
        return Ok(());
    };
    let top: Vec<&str> = declared
        .iter()
        .take_while(|(v, _)| *v == highest)
        .map(|(_, l)| l.as_str())
        .collect();
    println!(
        "{name}: rust-version {own_text}; {} dependencies, {} declare a rust-version; highest: {}",
        seen.len(),
        declared.len(),
        top.join(", ")
    );
    for (_, label) in declared.iter().skip(top.len()).take(4) {
        println!("  then {label}");
    }
    if own < highest {
        return Err(format!(
            "{name}'s rust-version {own_text} is lower than its dependencies' highest, {}.{}.{} ({}): raise it in Cargo.toml",
            highest.0,
            highest.1,
            highest.2,
            top.join(", ")
        ));
    }
    if own > highest {
        println!("  (higher than every dependency's: fine if the crate's own code needs it)");
    }
    Ok(())
}

fn str_of(j: &Json) -> &str {
    j.as_str().unwrap_or("?")
}

// ---------------------------------------------------------------------------------
// package-list

/// The files `cargo package` would ship: only the plugin's sources, README, CHANGELOG
/// and licences (and what cargo adds itself), with a licence file for each licence of
/// the `license` field.
fn package_list(name: &str) -> Result<(), String> {
    let meta = metadata(true)?;
    let pkg = member(&meta, name)?;
    // `--allow-dirty`: only lists; the CI's `cargo package` itself refuses a dirty tree.
    let list = cargo(&["package", "--list", "--locked", "--allow-dirty", "-p", name])?;
    let files: BTreeSet<&str> = list
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();

    let readme = pkg["readme"].as_str().unwrap_or("README.md");
    let mut licence_files = Vec::new();
    let license = pkg["license"].as_str().ok_or("no `license` field")?;
    for id in license.split(|c: char| c.is_whitespace() || c == '(' || c == ')') {
        match id {
            "" | "OR" | "AND" | "WITH" => {}
            "MIT" => licence_files.push((
                "LICENSE-MIT",
                "Permission is hereby granted, free of charge",
            )),
            "Apache-2.0" => licence_files.push((
                "LICENSE-APACHE",
                "Apache License\n                        Version 2.0",
            )),
            other => {
                return Err(format!(
                    "no licence file known for {other:?}; add it to release_check.rs"
                ))
            }
        }
    }
    let fixed: BTreeSet<&str> = [
        "Cargo.toml",
        "Cargo.toml.orig",
        "Cargo.lock",
        ".cargo_vcs_info.json",
        "CHANGELOG.md",
        readme,
    ]
    .into_iter()
    .chain(licence_files.iter().map(|(f, _)| *f))
    .collect();
    let extra: Vec<&&str> = files
        .iter()
        .filter(|f| !fixed.contains(**f) && !f.starts_with("src/"))
        .collect();
    let mut problems = Vec::new();
    if !extra.is_empty() {
        problems.push(format!("ships files beyond sources, README, CHANGELOG and licences: {extra:?} (`include` in Cargo.toml)"));
    }
    for required in ["src/lib.rs", "CHANGELOG.md", readme, "Cargo.toml"] {
        if !files.contains(required) {
            problems.push(format!("does not ship {required}"));
        }
    }
    let dir = manifest_dir(pkg)?;
    for (file, text) in &licence_files {
        if !files.contains(file) {
            problems.push(format!("does not ship {file} (license = {license:?})"));
        }
        match std::fs::read_to_string(dir.join(file)) {
            Ok(body) if body.contains(text) => {}
            Ok(_) => problems.push(format!(
                "{file} does not read as the {license} licence text"
            )),
            Err(e) => problems.push(format!("{file}: {e}")),
        }
    }
    for f in ["LICENSE", "LICENSE.md", "LICENSE.txt", "COPYING"] {
        if dir.join(f).exists() && !licence_files.iter().any(|(l, _)| *l == f) {
            problems.push(format!(
                "{f} exists but matches no licence of license = {license:?}"
            ));
        }
    }
    let src = files.iter().filter(|f| f.starts_with("src/")).count();
    println!(
        "{name}: {} files: {src} under src/, {}",
        files.len(),
        files
            .iter()
            .filter(|f| !f.starts_with("src/"))
            .copied()
            .collect::<Vec<_>>()
            .join(", ")
    );
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n"))
    }
}

fn manifest_dir(pkg: &Json) -> Result<PathBuf, String> {
    let manifest = pkg["manifest_path"].as_str().ok_or("no manifest_path")?;
    Ok(Path::new(manifest)
        .parent()
        .ok_or("manifest_path has no parent")?
        .to_path_buf())
}

// ---------------------------------------------------------------------------------
// readme-links

/// Every link target in the README resolves from the packaged crate (crates.io and
/// docs.rs show the README without the repository's other files): an anchor of a
/// README heading, an absolute link into the `repository` whose file exists in this
/// checkout (and, into a Markdown file, whose anchor is one of its headings), or
/// another absolute URL (not fetched). Relative links fail.
fn readme_links(name: &str) -> Result<(), String> {
    let meta = metadata(true)?;
    let pkg = member(&meta, name)?;
    let dir = manifest_dir(pkg)?;
    let readme_name = pkg["readme"].as_str().unwrap_or("README.md");
    let readme = std::fs::read_to_string(dir.join(readme_name))
        .map_err(|e| format!("{readme_name}: {e}"))?;
    let repository = pkg["repository"]
        .as_str()
        .map(|r| r.trim_end_matches('/').to_string());

    let mut problems = Vec::new();
    let mut counts = (0, 0, 0); // anchors, into the repository, other URLs
    let own_anchors = anchors(&readme);
    let targets = link_targets(&readme);
    for (line, target) in &targets {
        let at = format!("{readme_name}:{line}: {target}");
        if let Some(anchor) = target.strip_prefix('#') {
            counts.0 += 1;
            if !own_anchors.contains(anchor) {
                problems.push(format!("{at}: no such heading in {readme_name}"));
            }
        } else if let Some(rest) = repository.as_deref().and_then(|r| target.strip_prefix(r)) {
            counts.1 += 1;
            // `/blob/BRANCH/PATH#anchor` or `/tree/BRANCH/PATH`.
            let mut parts = rest.trim_start_matches('/').splitn(3, '/');
            let (kind, _branch, path) = (parts.next(), parts.next(), parts.next());
            let (path, anchor) = match path.map(|p| p.split_once('#').unwrap_or((p, ""))) {
                Some((p, a)) if matches!(kind, Some("blob" | "tree")) => (p, a),
                _ if rest.is_empty() || rest == "/" => continue,
                _ => {
                    problems.push(format!(
                        "{at}: not a /blob/BRANCH/PATH or /tree/BRANCH/PATH link"
                    ));
                    continue;
                }
            };
            let file = dir.join(path);
            if !file.exists() {
                problems.push(format!("{at}: {path} does not exist in the repository"));
            } else if !anchor.is_empty() && path.ends_with(".md") {
                let body = std::fs::read_to_string(&file).map_err(|e| format!("{path}: {e}"))?;
                if !anchors(&body).contains(anchor) {
                    problems.push(format!("{at}: no heading #{anchor} in {path}"));
                }
            }
        } else if target.contains("://") || target.starts_with("mailto:") {
            counts.2 += 1;
        } else {
            problems.push(format!(
                "{at}: relative link, which the published README cannot resolve; use {}/blob/main/{}",
                repository.as_deref().unwrap_or("<repository>"),
                target
            ));
        }
    }
    println!(
        "{readme_name}: {} links: {} to its own headings, {} into {}, {} other URLs",
        targets.len(),
        counts.0,
        counts.1,
        repository.as_deref().unwrap_or("(no repository field)"),
        counts.2
    );
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("\n"))
    }
}

/// The link targets of a Markdown text with their line numbers: inline links and
/// images `[..](target)`, reference definitions `[id]: target`, autolinks `<url>` and
/// HTML `href`/`src`, outside fenced code blocks and code spans.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut fence: Option<&str> = None;
    for (n, raw) in text.lines().enumerate() {
        let trimmed = raw.trim_start();
        if let Some(f) = fence {
            if trimmed.starts_with(f) {
                fence = None;
            }
            continue;
        }
        if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
            fence = Some(&trimmed[..3]);
            continue;
        }
        let line = strip_code_spans(raw);
        let push = |out: &mut Vec<(usize, String)>, t: &str| {
            let t = t.trim().trim_start_matches('<').trim_end_matches('>');
            // A title after the target: `(url "title")`.
            let t = t.split_whitespace().next().unwrap_or("");
            if !t.is_empty() {
                out.push((n + 1, t.to_string()));
            }
        };
        // Reference definitions.
        if let Some(rest) = trimmed.strip_prefix('[') {
            if let Some((_, target)) = rest.split_once("]:") {
                push(&mut out, target);
                continue;
            }
        }
        let mut rest = line.as_str();
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let mut depth = 1;
            let mut end = after.len();
            for (j, c) in after.char_indices() {
                match c {
                    '(' => depth += 1,
                    ')' => {
                        depth -= 1;
                        if depth == 0 {
                            end = j;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            push(&mut out, &after[..end]);
            rest = &after[end.min(after.len())..];
        }
        for key in ["href=\"", "src=\"", "<http"] {
            let mut rest = line.as_str();
            while let Some(i) = rest.find(key) {
                let start = if key == "<http" { i + 1 } else { i + key.len() };
                let tail = &rest[start..];
                let end = tail.find(['"', '>']).unwrap_or(tail.len());
                push(&mut out, &tail[..end]);
                rest = &tail[end..];
            }
        }
    }
    out
}

fn strip_code_spans(line: &str) -> String {
    let mut out = String::new();
    let mut parts = line.split('`');
    if let Some(first) = parts.next() {
        out.push_str(first);
    }
    let mut inside = true;
    for part in parts {
        if !inside {
            out.push_str(part);
        }
        inside = !inside;
    }
    out
}

/// The anchors GitHub gives a Markdown file's headings: lower case, letters, digits,
/// spaces, `-` and `_` kept, spaces to `-`, repeats suffixed `-1`, `-2`, ...
fn anchors(text: &str) -> HashSet<String> {
    let mut out = HashSet::new();
    let mut fence = false;
    for line in text.lines() {
        let t = line.trim_start();
        if t.starts_with("```") || t.starts_with("~~~") {
            fence = !fence;
            continue;
        }
        if fence || !t.starts_with('#') {
            continue;
        }
        let heading = t.trim_start_matches('#');
        if !heading.starts_with(' ') && !heading.is_empty() {
            continue;
        }
        let mut slug = String::new();
        for c in heading.trim().chars() {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                slug.extend(c.to_lowercase());
            } else if c == ' ' {
                slug.push('-');
            }
        }
        let mut candidate = slug.clone();
        let mut k = 0;
        while out.contains(&candidate) {
            k += 1;
            candidate = format!("{slug}-{k}");
        }
        out.insert(candidate);
    }
    out
}

// ---------------------------------------------------------------------------------
// A minimal JSON reader (enough for `cargo metadata`).

enum Json {
    Null,
    Bool,
    Num,
    Str(String),
    Arr(Vec<Json>),
    Obj(Vec<(String, Json)>),
}

static NULL: Json = Json::Null;

impl std::ops::Index<&str> for Json {
    type Output = Json;
    fn index(&self, key: &str) -> &Json {
        match self {
            Json::Obj(fields) => fields
                .iter()
                .find(|(k, _)| k == key)
                .map(|(_, v)| v)
                .unwrap_or(&NULL),
            _ => &NULL,
        }
    }
}

impl Json {
    fn as_str(&self) -> Option<&str> {
        match self {
            Json::Str(s) => Some(s),
            _ => None,
        }
    }

    fn iter(&self) -> std::slice::Iter<'_, Json> {
        match self {
            Json::Arr(items) => items.iter(),
            _ => [].iter(),
        }
    }

    fn parse(text: &str) -> Result<Json, String> {
        let mut p = Parser {
            s: text.as_bytes(),
            i: 0,
        };
        let v = p.value()?;
        p.ws();
        if p.i != p.s.len() {
            return Err(format!("JSON: trailing input at byte {}", p.i));
        }
        Ok(v)
    }
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
}

impl Parser<'_> {
    fn ws(&mut self) {
        while self.i < self.s.len() && matches!(self.s[self.i], b' ' | b'\n' | b'\r' | b'\t') {
            self.i += 1;
        }
    }

    fn err<T>(&self, what: &str) -> Result<T, String> {
        Err(format!("JSON: {what} at byte {}", self.i))
    }

    fn eat(&mut self, lit: &str) -> Result<(), String> {
        if self.s[self.i..].starts_with(lit.as_bytes()) {
            self.i += lit.len();
            Ok(())
        } else {
            self.err(&format!("expected {lit}"))
        }
    }

    fn value(&mut self) -> Result<Json, String> {
        self.ws();
        match self.s.get(self.i) {
            Some(b'n') => self.eat("null").map(|_| Json::Null),
            Some(b't') => self.eat("true").map(|_| Json::Bool),
            Some(b'f') => self.eat("false").map(|_| Json::Bool),
            Some(b'"') => self.string().map(Json::Str),
            Some(b'[') => {
                self.i += 1;
                let mut items = Vec::new();
                self.ws();
                if self.s.get(self.i) == Some(&b']') {
                    self.i += 1;
                    return Ok(Json::Arr(items));
                }
                loop {
                    items.push(self.value()?);
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b']') => {
                            self.i += 1;
                            return Ok(Json::Arr(items));
                        }
                        _ => return self.err("expected , or ]"),
                    }
                }
            }
            Some(b'{') => {
                self.i += 1;
                let mut fields = Vec::new();
                self.ws();
                if self.s.get(self.i) == Some(&b'}') {
                    self.i += 1;
                    return Ok(Json::Obj(fields));
                }
                loop {
                    self.ws();
                    let key = self.string()?;
                    self.ws();
                    self.eat(":")?;
                    fields.push((key, self.value()?));
                    self.ws();
                    match self.s.get(self.i) {
                        Some(b',') => self.i += 1,
                        Some(b'}') => {
                            self.i += 1;
                            return Ok(Json::Obj(fields));
                        }
                        _ => return self.err("expected , or }"),
                    }
                }
            }
            Some(c) if *c == b'-' || c.is_ascii_digit() => {
                while self.i < self.s.len()
                    && matches!(
                        self.s[self.i],
                        b'-' | b'+' | b'.' | b'e' | b'E' | b'0'..=b'9'
                    )
                {
                    self.i += 1;
                }
                Ok(Json::Num)
            }
            _ => self.err("expected a value"),
        }
    }

    fn hex4(&mut self) -> Result<u32, String> {
        let h = self
            .s
            .get(self.i..self.i + 4)
            .ok_or("JSON: short \\u escape")?;
        let v = u32::from_str_radix(std::str::from_utf8(h).map_err(|e| e.to_string())?, 16)
            .map_err(|e| e.to_string())?;
        self.i += 4;
        Ok(v)
    }

    fn string(&mut self) -> Result<String, String> {
        if self.s.get(self.i) != Some(&b'"') {
            return self.err("expected a string");
        }
        self.i += 1;
        let mut out: Vec<u8> = Vec::new();
        loop {
            match self.s.get(self.i) {
                None => return self.err("unterminated string"),
                Some(b'"') => {
                    self.i += 1;
                    return String::from_utf8(out).map_err(|e| e.to_string());
                }
                Some(b'\\') => {
                    self.i += 1;
                    let c = *self.s.get(self.i).ok_or("JSON: bad escape")?;
                    self.i += 1;
                    let ch = match c {
                        b'"' => '"',
                        b'\\' => '\\',
                        b'/' => '/',
                        b'b' => '\u{8}',
                        b'f' => '\u{c}',
                        b'n' => '\n',
                        b'r' => '\r',
                        b't' => '\t',
                        b'u' => {
                            let mut code = self.hex4()?;
                            if (0xD800..0xDC00).contains(&code)
                                && self.s[self.i..].starts_with(b"\\u")
                            {
                                self.i += 2;
                                let low = self.hex4()?;
                                code = 0x10000
                                    + ((code - 0xD800) << 10)
                                    + (low.wrapping_sub(0xDC00) & 0x3FF);
                            }
                            char::from_u32(code).unwrap_or('\u{FFFD}')
                        }
                        _ => return self.err("bad escape"),
                    };
                    let mut buf = [0; 4];
                    out.extend_from_slice(ch.encode_utf8(&mut buf).as_bytes());
                }
                Some(&b) => {
                    out.push(b);
                    self.i += 1;
                }
            }
        }
    }
}
