//! A Markdown table in the docs that restates what a command prints is generated from
//! that command's console block (issue 40: README's tables had gone stale where the docs
//! test did not look). Between `<!-- shares-table begin -->` and `<!-- shares-table end
//! -->` stands the table of the first `console` block after the end marker: one row per
//! `converged share against KEY` (and `odometry drift ... against KEY`) section of the
//! sweep's output, one column per law. The console block itself is the command's output,
//! compared by `docs_commands` (under `WMR_LONG_TESTS=1` for a long sweep), so every number
//! of the table comes from the command. The test fails when a table differs from its
//! block; `WMR_BLESS=1 cargo test -p wmr-cli --test docs_console_tables` rewrites them.

use std::path::PathBuf;

const BEGIN: &str = "<!-- shares-table begin -->\n";
const END: &str = "<!-- shares-table end -->";

/// The documents that hold such tables.
const DOCS: [&str; 1] = ["README.md"];

fn path(doc: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..").join(doc)
}

/// One section of a sweep's output: its title, the values of the key, and per law its
/// numbers as printed (`70.0%`, `0.93%`).
struct Section {
    title: String,
    values: Vec<String>,
    rows: Vec<(String, Vec<String>)>,
}

/// The sections of a console block's lines.
fn sections(block: &str) -> Vec<Section> {
    let mut out: Vec<Section> = Vec::new();
    let mut lines = block.lines().peekable();
    while let Some(line) = lines.next() {
        if !(line.starts_with("converged share against ") || line.starts_with("odometry drift at the end")) {
            continue;
        }
        let head = lines.next().expect("a header line under a section title");
        let values: Vec<String> = head.split_whitespace().skip(1).map(str::to_owned).collect();
        assert_eq!(head.split_whitespace().next(), Some("law"), "{head}");
        let mut rows = Vec::new();
        while let Some(row) = lines.peek() {
            let cells: Vec<&str> = row.split_whitespace().collect();
            if cells.len() != values.len() + 1 || !cells[1..].iter().all(|c| c.ends_with('%')) {
                break;
            }
            rows.push((cells[0].to_owned(), cells[1..].iter().map(|c| (*c).to_owned()).collect()));
            lines.next();
        }
        assert!(!rows.is_empty(), "section {line:?} has no rows");
        out.push(Section { title: line.to_owned(), values, rows });
    }
    out
}

/// `70.0%` as `70`, `37.5%` as `37.5`, `0.93%` as `0.93`.
fn number(cell: &str) -> &str {
    let n = cell.trim_end_matches('%');
    n.strip_suffix(".0").unwrap_or(n)
}

/// The Markdown table of `block`'s sections.
fn table(block: &str) -> String {
    let sections = sections(block);
    assert!(!sections.is_empty(), "no `converged share against` section in the console block");
    let laws: Vec<&str> = sections[0].rows.iter().map(|(law, _)| law.as_str()).collect();
    let mut out = format!("| against (values) | {} |\n|---|{}\n", laws.join(" | "), "---|".repeat(laws.len()));
    for s in &sections {
        let (what, key) = s.title.rsplit_once(" against ").expect("`... against KEY`");
        let what = if what == "converged share" { String::new() } else { format!("{what}: ") };
        out.push_str(&format!("| {what}`{key}` = {} |", s.values.join(" / ")));
        for law in &laws {
            let (_, cells) = s.rows.iter().find(|(l, _)| l == law).unwrap_or_else(|| panic!("{law} in {}", s.title));
            let first = number(&cells[0]);
            if cells.iter().all(|c| number(c) == first) {
                out.push_str(&format!(" {first} % throughout |"));
            } else {
                out.push_str(&format!(" {} % |", cells.iter().map(|c| number(c)).collect::<Vec<_>>().join(" / ")));
            }
        }
        out.push('\n');
    }
    out
}

/// `doc` with every table regenerated from the console block after it; how many.
fn regenerate(doc: &str) -> (String, usize) {
    let (mut out, mut rest, mut n) = (String::new(), doc, 0);
    while let Some(a) = rest.find(BEGIN) {
        let b = rest.find(END).unwrap_or_else(|| panic!("{BEGIN:?} without {END:?}"));
        let after = &rest[b..];
        let open = after.find("```console\n").expect("a console block after the table") + "```console\n".len();
        let close = after[open..].find("\n```").expect("the console block's end") + open;
        out.push_str(&rest[..a + BEGIN.len()]);
        out.push_str(&table(&after[open..close]));
        rest = &rest[b..];
        n += 1;
    }
    out.push_str(rest);
    (out, n)
}

#[test]
fn shares_tables_are_generated_from_their_console_blocks() {
    let mut found = 0;
    for doc in DOCS {
        let p = path(doc);
        let text = std::fs::read_to_string(&p).unwrap();
        let (fresh, n) = regenerate(&text);
        found += n;
        if std::env::var_os("WMR_BLESS").is_some() {
            std::fs::write(&p, &fresh).unwrap();
            eprintln!("WMR_BLESS=1: rewrote the tables of {doc} instead of comparing them");
        }
        let now = std::fs::read_to_string(&p).unwrap();
        assert!(
            fresh == now,
            "{doc}: a shares table differs from its console block; regenerate with \
             `WMR_BLESS=1 cargo test -p wmr-cli --test docs_console_tables`"
        );
    }
    assert!(found > 0, "no table between {BEGIN:?} and {END:?}");
}

#[test]
fn a_table_follows_its_block() {
    let block = "converged share against sensor.latency\nlaw  0  0.1\npaper  70.0%  0.0%\npolar  100.0%  100.0%\n\
                 wmr-cli: 4 runs\n";
    let doc = format!("x\n{BEGIN}| stale |\n{END}\n\n```console\n$ wmr-cli sweep s.toml\n{block}```\n");
    let (fresh, n) = regenerate(&doc);
    assert_eq!(n, 1);
    assert!(fresh.contains("| `sensor.latency` = 0 / 0.1 | 70 / 0 % | 100 % throughout |\n"), "{fresh}");
    assert!(!fresh.contains("stale"));
}
