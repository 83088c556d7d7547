//! A `.geo` file is a program: Gmsh's scripting language can run shell commands (`SystemCall`),
//! start other programs (`OnelabRun`) and write, rename or delete files (`Printf … > "file"`,
//! `Save`, `Print`, `CreateDir`, `DeleteFile`, `RenameFile`). A model file may come from anyone,
//! and meshing its `.geo` must not do any of that unless the user says so: geoslip reads the script
//! (and every `.geo` it includes or merges) before it hands it to Gmsh, and refuses one that uses
//! these commands, or that names an included file by an expression it cannot follow.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Commands that start a program, and what they do.
const RUN_PROGRAMS: &[(&str, &str)] = &[
    ("SystemCall", "runs a shell command"),
    ("NonBlockingSystemCall", "runs a shell command"),
    ("Shell", "runs a shell command"),
    ("OnelabRun", "starts another program"),
];

/// Commands that write, rename or delete files outside geoslip's output folder.
const TOUCH_FILES: &[(&str, &str)] = &[
    ("Save", "writes a file"),
    ("Print", "writes a file"),
    ("CreateDir", "creates a folder"),
    ("DeleteFile", "deletes a file"),
    ("RenameFile", "renames a file"),
];

/// Commands that read another file into the script.
const READ_FILES: &[&str] = &["Include", "Merge", "MergeWithBoundingBox", "Open"];

/// How deep `Include`s may nest.
const MAX_DEPTH: usize = 16;

/// What a script does that geoslip will not run unasked: the file, its line, and what.
#[derive(Debug, Clone, PartialEq)]
pub struct ScriptAction {
    pub file: PathBuf,
    pub line: usize,
    pub what: String,
}

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Word(String, usize),
    Text(String, usize),
    Symbol(char, usize),
}

impl Token {
    fn line(&self) -> usize {
        match self {
            Token::Word(_, l) | Token::Text(_, l) | Token::Symbol(_, l) => *l,
        }
    }
}

/// Words, string literals and symbols, comments left out.
fn tokens(text: &str) -> Vec<Token> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let (mut i, mut line) = (0, 1);
    while i < chars.len() {
        let c = chars[i];
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && chars.get(i + 1) == Some(&'*') {
            i += 2;
            while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                line += usize::from(chars[i] == '\n');
                i += 1;
            }
            i += 2;
        } else if c == '"' {
            let start = line;
            let mut s = String::new();
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' && i + 1 < chars.len() {
                    i += 1;
                }
                line += usize::from(chars[i] == '\n');
                s.push(chars[i]);
                i += 1;
            }
            i += 1;
            out.push(Token::Text(s, start));
        } else if c.is_alphabetic() || c == '_' {
            let mut s = String::new();
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                s.push(chars[i]);
                i += 1;
            }
            out.push(Token::Word(s, line));
        } else {
            if !c.is_whitespace() {
                out.push(Token::Symbol(c, line));
            }
            i += 1;
        }
    }
    out
}

/// Everything `script` (and every `.geo` it reads in) does that starts a program or touches files;
/// empty when it does none of it.
pub fn actions(script: &Path) -> Vec<ScriptAction> {
    let mut found = Vec::new();
    let mut seen = HashSet::new();
    scan(script, 0, &mut seen, &mut found);
    found
}

fn scan(file: &Path, depth: usize, seen: &mut HashSet<PathBuf>, found: &mut Vec<ScriptAction>) {
    let key = file.canonicalize().unwrap_or_else(|_| file.to_path_buf());
    if !seen.insert(key) {
        return;
    }
    let act = |line: usize, what: String, found: &mut Vec<ScriptAction>| {
        found.push(ScriptAction { file: file.to_path_buf(), line, what });
    };
    if depth > MAX_DEPTH {
        act(1, format!("includes nest deeper than {MAX_DEPTH} files"), found);
        return;
    }
    // A file Gmsh cannot read fails there, before it does anything.
    let Ok(bytes) = std::fs::read(file) else { return };
    let text = String::from_utf8_lossy(&bytes);
    let tokens = tokens(&text);
    let dir = file.parent().unwrap_or(Path::new("."));
    for (k, token) in tokens.iter().enumerate() {
        let Token::Word(word, line) = token else { continue };
        // `Print.Width = …` sets an option of a category that shares a command's name
        if matches!(tokens.get(k + 1), Some(Token::Symbol('.', _))) {
            continue;
        }
        if let Some((name, what)) = RUN_PROGRAMS.iter().chain(TOUCH_FILES).find(|(name, _)| name == word) {
            act(*line, format!("`{name}` {what}"), found);
        } else if word == "Printf" && writes_to_file(&tokens[k + 1..]) {
            act(*line, "`Printf … > \"file\"` writes a file".to_string(), found);
        } else if READ_FILES.contains(&word.as_str()) {
            match tokens.get(k + 1) {
                Some(Token::Text(name, _)) => {
                    let path = dir.join(name);
                    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("geo")) {
                        scan(&path, depth + 1, seen, found);
                    }
                }
                next => act(
                    next.map_or(*line, Token::line),
                    format!("`{word}` names its file by an expression, which geoslip cannot follow to check it"),
                    found,
                ),
            }
        }
    }
}

/// Whether the `Printf(…)` whose tokens follow ends in a redirection to a file (`> "file"` or
/// `>> "file"`) before its `;`.
fn writes_to_file(after: &[Token]) -> bool {
    let mut depth = 0usize;
    let mut closed = false;
    for t in after {
        match t {
            Token::Symbol('(', _) => depth += 1,
            Token::Symbol(')', _) => {
                depth = depth.saturating_sub(1);
                closed = depth == 0;
            }
            Token::Symbol(';', _) if depth == 0 => return false,
            Token::Symbol('>', _) if closed && depth == 0 => return true,
            _ => {}
        }
    }
    false
}

#[cfg(test)]
mod tests {
    //! The commands of the Gmsh reference manual's "General commands" that run programs or touch
    //! files, each found, and a plain geometry passed.
    use super::*;

    fn scan_text(text: &str) -> Vec<String> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.geo");
        std::fs::write(&path, text).unwrap();
        actions(&path).into_iter().map(|a| format!("{}: {}", a.line, a.what)).collect()
    }

    #[test]
    fn a_plain_geometry_does_nothing_to_refuse() {
        let geo = "// a box\nlc = 0.1;\nPoint(1) = {0, 0, 0, lc};\nPoint(2) = {1, 0, 0, lc};\nLine(1) = {1, 2};\n\
                   Printf(\"lc = %g, %g\", lc, lc > 1 ? 1 : 0);\nPhysical Curve(\"base\") = {1};\n\
                   /* SystemCall \"in a comment\"; */ s = \"SystemCall in a string\";\nPrint.Width = 800;\n";
        assert_eq!(scan_text(geo), Vec::<String>::new());
    }

    #[test]
    fn commands_that_run_programs_or_write_files_are_found() {
        let geo = "SystemCall \"touch /tmp/x\";\nNonBlockingSystemCall \"x\";\nOnelabRun(\"a\", \"b\");\n\
                   Printf(\"x\") > \"/tmp/out.txt\";\nPrintf(\"x\") >> \"/tmp/out.txt\";\nSave \"/tmp/m.msh\";\n\
                   CreateDir \"/tmp/d\";\nDeleteFile \"/tmp/f\";\nRenameFile \"/tmp/a\", \"/tmp/b\";\nInclude StrCat(\"a\", \".geo\");\n";
        let found = scan_text(geo);
        assert_eq!(found.len(), 10, "{found:?}");
        assert!(found[0].starts_with("1: `SystemCall` runs a shell command"));
        assert!(found[3].starts_with("4: `Printf"));
        assert!(found[9].starts_with("10: `Include` names its file by an expression"));
    }

    #[test]
    fn an_included_script_is_read_too() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("inner.geo"), "Point(1) = {0, 0, 0};\nSystemCall \"x\";\n").unwrap();
        let outer = dir.path().join("outer.geo");
        std::fs::write(&outer, "Include \"inner.geo\";\nInclude \"outer.geo\";\n").unwrap();
        let found = actions(&outer);
        assert_eq!(found.len(), 1);
        assert!(found[0].file.ends_with("inner.geo") && found[0].line == 2);
    }
}
