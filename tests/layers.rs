//! The layers of ARCHITECTURE.md, checked on the sources: every import between two files of
//! `src/` points down the drawing under its "Layers" heading (a file imports files of its own
//! layer or of a layer below), and no files import each other, directly or round a loop.
//!
//! What counts as file A importing file B: a `use` in A, or a path in A's code (`crate::…`,
//! `super::…`, `self::…`, a child module's name, or a name a `use` bound to a module), that
//! names B's module or an item defined in B. Paths are followed through `use` declarations, so
//! a module that re-exports its children (`pub use clip::Clip` in `anim.rs`) is a door, not a
//! stop: naming `crate::anim::Clip` imports `anim/clip.rs`. A `pub use` imports what it names
//! only when its file also uses the name itself. `mod` declarations build the module tree and
//! are no imports. Comments, strings and unit tests (`#[cfg(test)]`) are left out: unit tests,
//! like the crates in `tests/` and `benches/`, may use anything.
//!
//! The layers are read from ARCHITECTURE.md, the one place they are listed: the drawing is the
//! list the test checks, and the code map names each module's layer.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::Path;

// ---------------------------------------------------------------------------------------------
// The layers, as ARCHITECTURE.md draws them.

/// The layers, bottom first: each a name and its top-level modules (`sim` stands for `sim.rs`
/// and every file under `sim/`; `main` for the binary's `main.rs`).
#[derive(Debug, Clone)]
struct Layers(Vec<(String, Vec<String>)>);

impl Layers {
    /// The drawing of the first fenced block after the heading `## Layers`: lines
    /// `NAME: module, module, …` from the top layer down, arrows between them.
    fn parse(architecture: &str) -> Result<Layers, String> {
        let (_, after) = architecture
            .split_once("\n## Layers\n")
            .ok_or("ARCHITECTURE.md has no `## Layers` section holding the layer drawing")?;
        let block = after.split("```").nth(1).ok_or("the `## Layers` section has no fenced drawing")?;
        let mut layers = Vec::new();
        // The rest of the opening fence's line is its language tag.
        for line in block.lines().skip(1) {
            let line = line.trim();
            if line.chars().all(|c| c.is_whitespace() || matches!(c, '↓' | '│' | '|')) {
                continue;
            }
            let (name, modules) = line
                .split_once(':')
                .ok_or_else(|| format!("layer drawing: expected `NAME: modules`, found `{line}`"))?;
            let modules: Vec<String> = modules.split(',').map(|m| m.trim().to_string()).collect();
            if let Some(bad) =
                modules.iter().find(|m| m.is_empty() || !m.chars().all(|c| c.is_ascii_lowercase() || c == '_'))
            {
                return Err(format!("layer drawing: `{bad}` in `{line}` is not a module name"));
            }
            layers.push((name.trim().to_string(), modules));
        }
        if layers.is_empty() {
            return Err("the layer drawing lists no layers".into());
        }
        layers.reverse();
        Ok(Layers(layers))
    }

    /// The layer of a top-level module (`lib`, the crate root declaring the modules, sits below
    /// them all).
    fn of(&self, module: &str) -> Option<usize> {
        if module == "lib" {
            return Some(0);
        }
        self.0.iter().position(|(_, mods)| mods.iter().any(|m| m == module))
    }

    fn name(&self, layer: usize) -> &str {
        &self.0[layer].0
    }
}

/// The top-level module a file of `src/` belongs to: `sim/follow.rs` → `sim`.
fn top_module(file: &str) -> &str {
    let first = file.split('/').next().unwrap_or(file);
    first.strip_suffix(".rs").unwrap_or(first)
}

// ---------------------------------------------------------------------------------------------
// Reading Rust: tokens without comments, strings, characters, lifetimes and unit tests.

#[derive(Debug, Clone, PartialEq)]
struct Token {
    /// An identifier, `::`, or one punctuation character.
    text: String,
    /// 1-based line.
    line: usize,
}

fn is_ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_ident_continue(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

fn lex(src: &str) -> Vec<Token> {
    let c: Vec<char> = src.chars().collect();
    let n = c.len();
    let at = |i: usize| c.get(i).copied().unwrap_or('\0');
    let mut out = Vec::new();
    let (mut i, mut line) = (0usize, 1usize);
    // Skips a string whose opening quote is at `i`; returns the index past its closing quote.
    let skip_string = |mut i: usize, line: &mut usize| -> usize {
        i += 1;
        while i < n && c[i] != '"' {
            if c[i] == '\n' {
                *line += 1;
            }
            i += if c[i] == '\\' { 2 } else { 1 };
        }
        i + 1
    };
    // Skips a character literal or a lifetime whose quote is at `i`.
    let skip_quote = |i: usize| -> usize {
        if at(i + 1) == '\\' {
            let mut j = i + 3;
            while j < n && c[j] != '\'' {
                j += 1;
            }
            j + 1
        } else if at(i + 2) == '\'' {
            i + 3
        } else {
            let mut j = i + 1;
            while j < n && is_ident_continue(c[j]) {
                j += 1;
            }
            j
        }
    };
    while i < n {
        let ch = c[i];
        if ch == '\n' {
            line += 1;
            i += 1;
        } else if ch.is_whitespace() {
            i += 1;
        } else if ch == '/' && at(i + 1) == '/' {
            while i < n && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < n {
                if c[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if c[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                }
            }
        } else if ch == '"' {
            i = skip_string(i, &mut line);
        } else if ch == '\'' {
            i = skip_quote(i);
        } else if ch.is_ascii_digit() {
            while i < n && is_ident_continue(c[i]) {
                i += 1;
            }
        } else if is_ident_start(ch) {
            let start = i;
            while i < n && is_ident_continue(c[i]) {
                i += 1;
            }
            let word: String = c[start..i].iter().collect();
            match (word.as_str(), at(i)) {
                ("r" | "br" | "cr", '"' | '#') => {
                    let mut j = i;
                    while at(j) == '#' {
                        j += 1;
                    }
                    let hashes = j - i;
                    if at(j) == '"' {
                        // A raw string: up to a quote followed by as many hashes.
                        j += 1;
                        while j < n && !(c[j] == '"' && (1..=hashes).all(|k| at(j + k) == '#')) {
                            if c[j] == '\n' {
                                line += 1;
                            }
                            j += 1;
                        }
                        i = j + 1 + hashes;
                    } else if word == "r" && hashes == 1 {
                        // A raw identifier, `r#type`.
                        let s = j;
                        while j < n && is_ident_continue(c[j]) {
                            j += 1;
                        }
                        out.push(Token { text: c[s..j].iter().collect(), line });
                        i = j;
                    } else {
                        out.push(Token { text: word, line });
                    }
                }
                ("b" | "c", '"') => i = skip_string(i, &mut line),
                ("b", '\'') => i = skip_quote(i),
                _ => out.push(Token { text: word, line }),
            }
        } else if ch == ':' && at(i + 1) == ':' {
            out.push(Token { text: "::".into(), line });
            i += 2;
        } else {
            out.push(Token { text: ch.to_string(), line });
            i += 1;
        }
    }
    out
}

/// The index past the bracketed group opening at `i` (`(`, `[` or `{`).
fn group_end(t: &[Token], i: usize) -> usize {
    let mut depth = 0i64;
    for (j, tok) in t.iter().enumerate().skip(i) {
        match tok.text.as_str() {
            "(" | "[" | "{" => depth += 1,
            ")" | "]" | "}" => {
                depth -= 1;
                if depth == 0 {
                    return j + 1;
                }
            }
            _ => {}
        }
    }
    t.len()
}

/// `tokens` without the items marked `#[cfg(test)]` (and their other attributes).
fn without_unit_tests(t: Vec<Token>) -> Vec<Token> {
    let is_cfg_test = |i: usize| {
        let want = ["#", "[", "cfg", "(", "test", ")", "]"];
        t.len() >= i + want.len() && want.iter().enumerate().all(|(k, w)| t[i + k].text == *w)
    };
    let mut out = Vec::with_capacity(t.len());
    let mut i = 0;
    while i < t.len() {
        if !is_cfg_test(i) {
            out.push(t[i].clone());
            i += 1;
            continue;
        }
        i += 7;
        // Further attributes, then the item: up to its `;` or the end of its first braces.
        while i < t.len() && t[i].text == "#" && t.get(i + 1).is_some_and(|x| x.text == "[") {
            i = group_end(&t, i + 1);
        }
        while i < t.len() {
            match t[i].text.as_str() {
                ";" => {
                    i += 1;
                    break;
                }
                "{" => {
                    i = group_end(&t, i);
                    break;
                }
                "(" | "[" => i = group_end(&t, i),
                _ => i += 1,
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// What each file declares, defines, imports and names.

/// A module path from the crate root (`["sim", "follow"]`).
type ModPath = Vec<String>;

/// One name a `use` declaration brings in.
#[derive(Debug, Clone)]
struct UseLeaf {
    /// The module the declaration stands in.
    scope: ModPath,
    /// The path as written (`["crate", "sim", "Body"]`, `["super", "files"]` for `self`).
    path: Vec<String>,
    /// The name it binds (`None` for a glob).
    alias: Option<String>,
    /// `pub`, `pub(crate)`, …: a re-export.
    public: bool,
    /// Stands at module level (not in a function).
    module_level: bool,
    line: usize,
}

/// A path in code, outside `use` declarations.
#[derive(Debug, Clone)]
struct PathRef {
    scope: ModPath,
    path: Vec<String>,
    line: usize,
}

/// A module: its file and what is declared in it.
#[derive(Debug, Clone, Default)]
struct Module {
    file: String,
    children: BTreeSet<String>,
    items: BTreeSet<String>,
    uses: Vec<UseLeaf>,
}

#[derive(Debug, Default)]
struct FileFacts {
    uses: Vec<UseLeaf>,
    paths: Vec<PathRef>,
    /// Identifiers of the code outside `use` declarations.
    names: BTreeSet<String>,
    /// `mod NAME;` declarations: (scope, name).
    declared: Vec<(ModPath, String)>,
    /// Modules in this file (its own and inline ones), with their module-level items.
    modules: Vec<(ModPath, BTreeSet<String>)>,
}

const ITEM_KEYWORDS: &[&str] = &["fn", "struct", "enum", "trait", "type", "const", "static", "union"];

/// Parses one `use` tree starting at `i` under `prefix`, pushing its leaves; returns the index
/// after it.
fn use_tree(
    t: &[Token],
    mut i: usize,
    prefix: &[String],
    out: &mut Vec<(Vec<String>, Option<String>, usize)>,
) -> usize {
    let mut path = prefix.to_vec();
    if t.get(i).is_some_and(|x| x.text == "::") {
        i += 1;
    }
    loop {
        let Some(tok) = t.get(i) else { return i };
        match tok.text.as_str() {
            "{" => {
                i += 1;
                while t.get(i).is_some_and(|x| x.text != "}") {
                    i = use_tree(t, i, &path, out);
                    if t.get(i).is_some_and(|x| x.text == ",") {
                        i += 1;
                    }
                }
                return i + 1;
            }
            "*" => {
                out.push((path, None, tok.line));
                return i + 1;
            }
            "self" if !path.is_empty() => {
                let alias = path.last().cloned();
                i += 1;
                let alias = match (t.get(i), t.get(i + 1)) {
                    (Some(a), Some(name)) if a.text == "as" => {
                        i += 2;
                        Some(name.text.clone())
                    }
                    _ => alias,
                };
                out.push((path, alias, tok.line));
                return i;
            }
            word => {
                path.push(word.to_string());
                i += 1;
                match t.get(i).map(|x| x.text.as_str()) {
                    Some("::") => i += 1,
                    Some("as") => {
                        let alias = t.get(i + 1).map(|x| x.text.clone());
                        out.push((path, alias, tok.line));
                        return i + 2;
                    }
                    _ => {
                        let alias = path.last().cloned();
                        out.push((path, alias, tok.line));
                        return i;
                    }
                }
            }
        }
    }
}

fn file_facts(file_module: &ModPath, src: &str) -> FileFacts {
    let t = without_unit_tests(lex(src));
    let mut f = FileFacts::default();
    // Open modules: (path, brace depth inside it).
    let mut scopes: Vec<(ModPath, usize)> = vec![(file_module.clone(), 0)];
    let mut items: BTreeMap<ModPath, BTreeSet<String>> = BTreeMap::new();
    items.insert(file_module.clone(), BTreeSet::new());
    let mut depth = 0usize;
    let mut i = 0;
    while i < t.len() {
        let (scope, scope_depth) = scopes.last().cloned().unwrap_or_default();
        let word = t[i].text.as_str();
        let next = t.get(i + 1).map(|x| x.text.as_str());
        let module_level = depth == scope_depth;
        match word {
            "{" => depth += 1,
            "}" => {
                depth = depth.saturating_sub(1);
                if scopes.len() > 1 && depth < scope_depth {
                    scopes.pop();
                }
            }
            "use" => {
                // `pub use`, `pub(crate) use`, `pub(in …) use`: a re-export.
                let public = i > 0
                    && (t[i - 1].text == "pub"
                        || (t[i - 1].text == ")" && {
                            let mut k = i - 1;
                            while k > 0 && t[k].text != "(" {
                                k -= 1;
                            }
                            k > 0 && t[k - 1].text == "pub"
                        }));
                let mut leaves = Vec::new();
                let end = use_tree(&t, i + 1, &[], &mut leaves);
                for (path, alias, line) in leaves {
                    f.uses.push(UseLeaf { scope: scope.clone(), path, alias, public, module_level, line });
                }
                i = end;
                continue;
            }
            "mod" if next.is_some_and(|n| is_ident_start(n.chars().next().unwrap_or('0'))) => {
                let name = t[i + 1].text.clone();
                items.entry(scope.clone()).or_default().insert(name.clone());
                match t.get(i + 2).map(|x| x.text.as_str()) {
                    Some(";") => f.declared.push((scope.clone(), name)),
                    Some("{") => {
                        let mut inner = scope.clone();
                        inner.push(name);
                        items.entry(inner.clone()).or_default();
                        depth += 1;
                        scopes.push((inner, depth));
                        i += 3;
                        continue;
                    }
                    _ => {}
                }
                i += 2;
                continue;
            }
            "macro_rules" if next == Some("!") => {
                if let Some(name) = t.get(i + 2) {
                    items.entry(scope.clone()).or_default().insert(name.text.clone());
                }
            }
            w if ITEM_KEYWORDS.contains(&w) && module_level => {
                if let Some(name) = t.get(i + 1).filter(|n| is_ident_start(n.text.chars().next().unwrap_or('0')))
                    && !ITEM_KEYWORDS.contains(&name.text.as_str())
                {
                    items.entry(scope.clone()).or_default().insert(name.text.clone());
                }
            }
            _ => {}
        }
        if is_ident_start(word.chars().next().unwrap_or('0')) {
            f.names.insert(word.to_string());
            let starts_path = next == Some("::") && (i == 0 || t[i - 1].text != "::");
            if starts_path {
                let line = t[i].line;
                let mut path = vec![word.to_string()];
                let mut j = i + 1;
                while t.get(j).is_some_and(|x| x.text == "::")
                    && t.get(j + 1).is_some_and(|x| is_ident_start(x.text.chars().next().unwrap_or('0')))
                {
                    path.push(t[j + 1].text.clone());
                    f.names.insert(t[j + 1].text.clone());
                    j += 2;
                }
                f.paths.push(PathRef { scope: scope.clone(), path, line });
                i = j;
                continue;
            }
        }
        i += 1;
    }
    f.modules = items.into_iter().collect();
    f
}

// ---------------------------------------------------------------------------------------------
// The crate: its module tree, and paths resolved to the files that define what they name.

struct Crate {
    modules: BTreeMap<ModPath, Module>,
    facts: BTreeMap<String, FileFacts>,
    /// Each file's text, for quoting the lines of imports.
    texts: BTreeMap<String, String>,
    /// Files of `src/` no `mod` declaration reaches.
    unreached: Vec<String>,
}

/// The module of the binary's `main.rs` (a crate of its own, naming the library `strider`).
fn binary() -> ModPath {
    vec!["<main>".to_string()]
}

enum Target {
    Module(ModPath),
    Item(String),
}

impl Crate {
    /// Reads the crate from its files (paths relative to `src/`, with their text).
    fn read(files: &BTreeMap<String, String>) -> Crate {
        let mut c =
            Crate { modules: BTreeMap::new(), facts: BTreeMap::new(), texts: files.clone(), unreached: Vec::new() };
        let mut queue: VecDeque<(ModPath, String)> = VecDeque::from([(Vec::new(), "lib.rs".to_string())]);
        if files.contains_key("main.rs") {
            queue.push_back((binary(), "main.rs".to_string()));
        }
        while let Some((path, file)) = queue.pop_front() {
            let Some(text) = files.get(&file) else { continue };
            let facts = file_facts(&path, text);
            for (m, items) in &facts.modules {
                let module = c.modules.entry(m.clone()).or_default();
                module.file = file.clone();
                module.items.extend(items.iter().cloned());
                if m.len() > path.len() {
                    let parent = m[..m.len() - 1].to_vec();
                    c.modules.entry(parent).or_default().children.insert(m[m.len() - 1].clone());
                }
            }
            for u in &facts.uses {
                if u.module_level {
                    c.modules.entry(u.scope.clone()).or_default().uses.push(u.clone());
                }
            }
            for (scope, name) in &facts.declared {
                c.modules.entry(scope.clone()).or_default().children.insert(name.clone());
                let mut child = scope.clone();
                child.push(name.clone());
                let base = child.join("/");
                let found =
                    [format!("{base}.rs"), format!("{base}/mod.rs")].into_iter().find(|f| files.contains_key(f));
                if let Some(f) = found {
                    queue.push_back((child, f));
                }
            }
            c.facts.insert(file, facts);
        }
        c.unreached = files.keys().filter(|f| !c.facts.contains_key(*f)).cloned().collect();
        c
    }

    fn module(&self, path: &ModPath) -> Option<&Module> {
        self.modules.get(path)
    }

    /// Where the first segments of a path in `scope` lead: the module they start from and how
    /// many segments that took; `None` for paths outside the crate (std, other crates, local
    /// types and values).
    fn start(&self, scope: &ModPath, path: &[String], depth: usize) -> Option<(Target, usize)> {
        let first = path.first()?.as_str();
        let crate_root = || if scope.first().is_some_and(|s| s == "<main>") { None } else { Some(Vec::new()) };
        match first {
            "crate" => Some((Target::Module(crate_root()?), 1)),
            "strider" if scope.first().is_some_and(|s| s == "<main>") => Some((Target::Module(Vec::new()), 1)),
            "self" => Some((Target::Module(scope.clone()), 1)),
            "super" => {
                let mut m = scope.clone();
                let mut k = 0;
                while path.get(k).is_some_and(|s| s == "super") {
                    m.pop()?;
                    k += 1;
                }
                Some((Target::Module(m), k))
            }
            name => {
                let module = self.module(scope)?;
                if module.children.contains(name) {
                    let mut m = scope.clone();
                    m.push(name.to_string());
                    return Some((Target::Module(m), 1));
                }
                // A name a `use` of this module binds (at module level or in a function).
                let file = &module.file;
                let leaf = self
                    .facts
                    .get(file)?
                    .uses
                    .iter()
                    .find(|u| u.scope == *scope && u.alias.as_deref() == Some(name))?;
                Some((self.resolve(&leaf.scope, &leaf.path, depth + 1)?, 1))
            }
        }
    }

    /// What a path written in `scope` names: a module, or an item and the file defining it.
    fn resolve(&self, scope: &ModPath, path: &[String], depth: usize) -> Option<Target> {
        if depth > 32 {
            return None;
        }
        let (start, used) = self.start(scope, path, depth)?;
        self.walk(start, &path[used..], depth)
    }

    fn walk(&self, start: Target, rest: &[String], depth: usize) -> Option<Target> {
        let Target::Module(mut m) = start else { return Some(start) };
        for (k, seg) in rest.iter().enumerate() {
            let module = self.module(&m)?;
            if module.children.contains(seg) {
                m.push(seg.clone());
                continue;
            }
            if let Some(leaf) = module.uses.iter().find(|u| u.alias.as_deref() == Some(seg.as_str())) {
                let target = self.resolve(&leaf.scope, &leaf.path, depth + 1)?;
                return self.walk(target, &rest[k + 1..], depth + 1);
            }
            if module.items.contains(seg) {
                return Some(Target::Item(module.file.clone()));
            }
            for glob in module.uses.iter().filter(|u| u.alias.is_none()) {
                if let Some(Target::Module(g)) = self.resolve(&glob.scope, &glob.path, depth + 1) {
                    let found = self.module(&g).is_some_and(|gm| {
                        gm.children.contains(seg)
                            || gm.items.contains(seg)
                            || gm.uses.iter().any(|u| u.alias.as_deref() == Some(seg.as_str()))
                    });
                    if found {
                        return self.walk(Target::Module(g), &rest[k..], depth + 1);
                    }
                }
            }
            return Some(Target::Item(module.file.clone()));
        }
        Some(Target::Module(m))
    }

    fn file_of(&self, target: Target) -> Option<String> {
        match target {
            Target::Module(m) => self.module(&m).map(|m| m.file.clone()),
            Target::Item(f) => Some(f),
        }
    }

    /// Every import of one file by another: (from, to, line).
    fn imports(&self) -> Vec<Import> {
        let mut out = Vec::new();
        for (file, facts) in &self.facts {
            let mut add = |scope: &ModPath, path: &[String], line: usize| {
                if let Some(to) = self.resolve(scope, path, 0).and_then(|t| self.file_of(t))
                    && to != *file
                {
                    out.push(Import { from: file.clone(), to, line });
                }
            };
            for u in &facts.uses {
                let re_export_only = u.public && u.alias.as_ref().is_some_and(|a| !facts.names.contains(a));
                if !re_export_only {
                    add(&u.scope, &u.path, u.line);
                }
            }
            for p in &facts.paths {
                add(&p.scope, &p.path, p.line);
            }
        }
        out.sort_by(|a, b| (&a.from, a.line, &a.to).cmp(&(&b.from, b.line, &b.to)));
        out.dedup_by(|a, b| a.from == b.from && a.to == b.to && a.line == b.line);
        out
    }

    /// `src/FILE:LINE: the line`.
    fn quote(&self, file: &str, line: usize) -> String {
        let text = self.texts.get(file).and_then(|t| t.lines().nth(line - 1)).unwrap_or("").trim();
        format!("src/{file}:{line}: {text}")
    }
}

#[derive(Debug, Clone, PartialEq)]
struct Import {
    from: String,
    to: String,
    line: usize,
}

// ---------------------------------------------------------------------------------------------
// The checks.

/// Every import from a lower layer to a higher one.
fn upward_imports(c: &Crate, layers: &Layers) -> Vec<String> {
    let mut found = Vec::new();
    for i in c.imports() {
        let (Some(from), Some(to)) = (layers.of(top_module(&i.from)), layers.of(top_module(&i.to))) else {
            continue;
        };
        if to > from {
            found.push(format!(
                "{}\n    imports src/{}: layer \"{}\" may not import layer \"{}\" above it",
                c.quote(&i.from, i.line),
                i.to,
                layers.name(from),
                layers.name(to)
            ));
        }
    }
    found
}

/// Every set of files that import each other (directly or round a loop), with one loop through
/// them and the line of each import on it.
fn cycles(c: &Crate) -> Vec<String> {
    let imports = c.imports();
    let mut next: BTreeMap<&str, BTreeMap<&str, usize>> = BTreeMap::new();
    for i in &imports {
        next.entry(&i.from).or_default().entry(&i.to).or_insert(i.line);
    }
    let reach = |from: &str| -> BTreeSet<String> {
        let mut seen = BTreeSet::new();
        let mut queue = VecDeque::from([from.to_string()]);
        while let Some(f) = queue.pop_front() {
            for to in next.get(f.as_str()).into_iter().flat_map(|m| m.keys()) {
                if seen.insert(to.to_string()) {
                    queue.push_back(to.to_string());
                }
            }
        }
        seen
    };
    let files: Vec<&String> = c.facts.keys().collect();
    let reaches: BTreeMap<&str, BTreeSet<String>> = files.iter().map(|f| (f.as_str(), reach(f))).collect();
    let mut done = BTreeSet::new();
    let mut found = Vec::new();
    for f in &files {
        if done.contains(f.as_str()) || !reaches[f.as_str()].contains(f.as_str()) {
            continue;
        }
        let group: BTreeSet<&str> = files
            .iter()
            .map(|g| g.as_str())
            .filter(|g| reaches[f.as_str()].contains(*g) && reaches[*g].contains(f.as_str()))
            .collect();
        done.extend(group.iter().map(|g| g.to_string()));
        // The shortest loop from `f` back to itself, inside the group.
        let mut came: BTreeMap<&str, &str> = BTreeMap::new();
        let mut queue = VecDeque::from([f.as_str()]);
        let mut last = None;
        'search: while let Some(g) = queue.pop_front() {
            for to in next.get(g).into_iter().flat_map(|m| m.keys()).copied() {
                if to == f.as_str() {
                    last = Some(g);
                    break 'search;
                }
                if group.contains(to) && !came.contains_key(to) {
                    came.insert(to, g);
                    queue.push_back(to);
                }
            }
        }
        let mut back = Vec::new();
        let mut g = last.unwrap_or(f.as_str());
        while g != f.as_str() {
            back.push(g);
            g = came[g];
        }
        // f → … → f.
        let path: Vec<&str> = [f.as_str()].into_iter().chain(back.into_iter().rev()).chain([f.as_str()]).collect();
        let steps: Vec<String> = path
            .windows(2)
            .map(|w| format!("    {}\n        → src/{}", c.quote(w[0], next[w[0]][w[1]]), w[1]))
            .collect();
        found.push(format!(
            "{} files import each other ({}):\n{}",
            group.len(),
            group.iter().map(|g| format!("src/{g}")).collect::<Vec<_>>().join(", "),
            steps.join("\n")
        ));
    }
    found
}

/// Top-level modules missing from the drawing or listed twice, names it lists that are no
/// module, and files no `mod` declaration reaches.
fn layer_coverage(c: &Crate, layers: &Layers) -> Vec<String> {
    let mut found = Vec::new();
    let modules: BTreeSet<&str> = c.texts.keys().map(|f| top_module(f)).filter(|m| *m != "lib").collect();
    let mut listed: BTreeMap<&str, usize> = BTreeMap::new();
    for (_, mods) in &layers.0 {
        for m in mods {
            *listed.entry(m).or_default() += 1;
        }
    }
    for m in &modules {
        match listed.get(m) {
            None => found.push(format!("src/{m}.rs is in no layer of ARCHITECTURE.md's drawing")),
            Some(n) if *n > 1 => found.push(format!("`{m}` is in {n} layers of ARCHITECTURE.md's drawing")),
            _ => {}
        }
    }
    for m in listed.keys() {
        if !modules.contains(m) {
            found.push(format!("ARCHITECTURE.md's drawing lists `{m}`, which is no module of src/"));
        }
    }
    for f in &c.unreached {
        found.push(format!("src/{f} is declared by no `mod` (the check cannot see its imports)"));
    }
    found
}

/// Code-map sections whose `Layer:` line is missing or differs from the drawing, and modules of
/// the drawing no section names.
fn code_map_layers(architecture: &str, layers: &Layers) -> Vec<String> {
    let mut found = Vec::new();
    let mut mapped = BTreeSet::new();
    let map = architecture.split("\n## Code map\n").nth(1).unwrap_or("");
    let map = map.split("\n## ").next().unwrap_or("");
    for section in map.split("\n### ").skip(1) {
        let heading = section.lines().next().unwrap_or("");
        let modules: BTreeSet<&str> = heading
            .split('`')
            .filter_map(|s| s.strip_prefix("src/"))
            .map(|s| top_module(s.trim_end_matches('/')))
            .collect();
        if modules.is_empty() {
            continue;
        }
        let stated = section.lines().find_map(|l| l.trim().strip_prefix("Layer: ")).map(|l| l.trim_end_matches('.'));
        let Some(stated) = stated else {
            found.push(format!("code map `### {heading}` says no `Layer: …`"));
            continue;
        };
        for m in modules {
            mapped.insert(m);
            let drawn = layers.of(m).map(|l| layers.name(l));
            if drawn != Some(stated) {
                found.push(format!(
                    "code map `### {heading}` says layer \"{stated}\" but the drawing puts `{m}` in {}",
                    drawn.map_or("no layer".to_string(), |d| format!("\"{d}\""))
                ));
            }
        }
    }
    for (_, mods) in &layers.0 {
        for m in mods.iter().filter(|m| !mapped.contains(m.as_str())) {
            found.push(format!("the code map has no `### ` section naming `src/{m}.rs`"));
        }
    }
    found
}

// ---------------------------------------------------------------------------------------------
// The tests.

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn architecture() -> String {
    std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap()
}

fn sources() -> BTreeMap<String, String> {
    fn walk(dir: &Path, src: &Path, out: &mut BTreeMap<String, String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, src, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix(src).unwrap().to_string_lossy().replace('\\', "/");
                out.insert(rel, std::fs::read_to_string(&p).unwrap());
            }
        }
    }
    let src = root().join("src");
    let mut out = BTreeMap::new();
    walk(&src, &src, &mut out);
    out
}

fn layers() -> Layers {
    Layers::parse(&architecture()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_import_points_down_the_layers() {
    let found = upward_imports(&Crate::read(&sources()), &layers());
    assert!(
        found.is_empty(),
        "{} import(s) from a lower layer to a higher one (ARCHITECTURE.md, Layers):\n{}",
        found.len(),
        found.join("\n")
    );
}

#[test]
fn no_files_import_each_other() {
    let found = cycles(&Crate::read(&sources()));
    assert!(
        found.is_empty(),
        "{} import cycle(s) between files of src/ (move what both sides need below them):\n{}",
        found.len(),
        found.join("\n")
    );
}

#[test]
fn the_drawing_puts_every_module_in_one_layer() {
    let found = layer_coverage(&Crate::read(&sources()), &layers());
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn the_code_map_names_the_layer_of_each_module() {
    let found = code_map_layers(&architecture(), &layers());
    assert!(found.is_empty(), "{}", found.join("\n"));
}

// The checker itself, on small made-up crates.

fn made_up(files: &[(&str, &str)]) -> Crate {
    Crate::read(&files.iter().map(|(f, t)| (f.to_string(), t.to_string())).collect())
}

fn made_up_layers() -> Layers {
    Layers::parse("x\n## Layers\n\n```text\nfront: cli\n  ↓\ncore: geom, sim\n```\n").unwrap()
}

#[test]
fn the_checker_sees_an_upward_import_through_a_re_export() {
    let c = made_up(&[
        ("lib.rs", "pub mod cli;\npub mod geom;\n"),
        ("cli.rs", "pub mod files;\npub use files::write_atomic;\n"),
        ("cli/files.rs", "pub fn write_atomic() {}\n"),
        (
            "geom.rs",
            "// crate::cli::nothing in a comment\nfn f() { let s = \"crate::cli::x\"; crate::cli::write_atomic(); }\n",
        ),
    ]);
    let found = upward_imports(&c, &made_up_layers());
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("src/geom.rs:2: fn f()"), "{}", found[0]);
    assert!(
        found[0].contains("imports src/cli/files.rs: layer \"core\" may not import layer \"front\""),
        "{}",
        found[0]
    );
    assert!(cycles(&c).is_empty());
}

#[test]
fn the_checker_sees_a_loop_through_super_and_a_facade() {
    let c = made_up(&[
        ("lib.rs", "pub mod sim;\n"),
        ("sim.rs", "pub mod follow;\npub mod sense;\nuse follow::Side;\npub fn step(_: Side) {}\n"),
        ("sim/follow.rs", "pub enum Side { Left }\nfn f() { super::sense::scan(); }\n"),
        (
            "sim/sense.rs",
            "use crate::sim::step;\npub fn scan() {}\n#[cfg(test)]\nmod tests { use crate::sim::follow::Side; }\n",
        ),
    ]);
    let found = cycles(&c);
    assert_eq!(found.len(), 1, "{found:?}");
    let text = &found[0];
    assert!(text.starts_with("3 files import each other (src/sim.rs, src/sim/follow.rs, src/sim/sense.rs)"), "{text}");
    assert!(text.contains("src/sim/sense.rs:1: use crate::sim::step;\n        → src/sim.rs"), "{text}");
    assert!(text.contains("src/sim/follow.rs:2: fn f() { super::sense::scan(); }"), "{text}");
    // A facade that only re-exports is no import; one that uses the name is.
    let c = made_up(&[
        ("lib.rs", "pub mod anim;\n"),
        ("anim.rs", "pub mod clip;\npub mod skeleton;\npub use clip::Clip;\n"),
        ("anim/clip.rs", "use super::skeleton::Pose;\npub struct Clip;\n"),
        ("anim/skeleton.rs", "pub struct Pose;\nfn f(_: crate::anim::Clip) {}\n"),
    ]);
    let found = cycles(&c);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("2 files import each other (src/anim/clip.rs, src/anim/skeleton.rs)"), "{}", found[0]);
}

#[test]
fn the_checker_reads_the_drawing_and_the_code_map() {
    let l = made_up_layers();
    assert_eq!((l.of("geom"), l.of("sim"), l.of("cli"), l.of("tui")), (Some(0), Some(0), Some(1), None));
    let doc = "x\n## Code map\n\n### `src/geom.rs` — geometry\n\nLayer: core.\n\n### `src/cli.rs`\n\nLayer: core.\n\n### `scripts/`\n\n## Next\n";
    let found = code_map_layers(doc, &l);
    assert_eq!(
        found,
        vec![
            "code map `### `src/cli.rs`` says layer \"core\" but the drawing puts `cli` in \"front\"".to_string(),
            "the code map has no `### ` section naming `src/sim.rs`".to_string()
        ]
    );
    let c = made_up(&[("lib.rs", "pub mod geom;\n"), ("geom.rs", ""), ("stray.rs", "")]);
    let found = layer_coverage(&c, &l);
    assert!(
        found.contains(&"src/stray.rs is declared by no `mod` (the check cannot see its imports)".to_string()),
        "{found:?}"
    );
    assert!(found.contains(&"src/stray.rs is in no layer of ARCHITECTURE.md's drawing".to_string()), "{found:?}");
}
