//! A Markdown table in the docs that restates what a command prints is generated from
//! that command's console block (issue 40: README's tables had gone stale where the docs
//! test did not look). Between `<!-- shares-table begin -->` and `<!-- shares-table end
//! -->` stands the table of the first `console` block after the end marker: one row per
//! `converged share against KEY` (and `odometry drift ... against KEY`) section of the
//! sweep's output, one column per law. The console block itself is the command's output,
//! compared by `docs_commands` (under `WMR_LONG_TESTS=1` for a long sweep), so every number
//! of the table comes from the command. The test fails when a table differs from its
//! block; `WMR_BLESS=1 cargo test -p wmr-cli --test integration docs_console_tables::` rewrites them.
//!
//! Likewise between `<!-- laws-table begin -->` and `<!-- laws-table end -->`: the per-law
//! table of a sweep (converged, diverged, unsettled, time to 1 cm and heading error, median
//! / worst) from the first lines of the console block after it; between
//! `<!-- tracking-table begin -->` and its end, the table of a sweep over references; and a number in the prose
//! that a command prints is checked against that command's console block
//! (`prose_numbers_are_those_of_their_console_blocks`).

use std::path::PathBuf;

const BEGIN: &str = "<!-- shares-table begin -->\n";
const END: &str = "<!-- shares-table end -->";
const LAWS_BEGIN: &str = "<!-- laws-table begin -->\n";
const LAWS_END: &str = "<!-- laws-table end -->";
const TRACKING_BEGIN: &str = "<!-- tracking-table begin -->\n";
const TRACKING_END: &str = "<!-- tracking-table end -->";
const DOCKING_BEGIN: &str = "<!-- docking-table begin -->\n";
const DOCKING_END: &str = "<!-- docking-table end -->";

/// The documents that hold such tables.
const DOCS: [&str; 3] = ["README.md", "docs/model.md", "examples/docking/README.md"];

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

/// One law's row of a sweep's table: the law and its cells as printed (`84.0%`,
/// `49.57 / 179.61`), in the table's order: runs, converged, diverged, unsettled, then
/// median / worst of t_1cm s, |e_th| deg, peak w rad/s, path m, energy J.
fn law_rows(block: &str) -> Vec<(String, Vec<String>)> {
    let mut lines = block.lines().skip_while(|l| !(l.starts_with("law ") && l.contains(" runs  converged")));
    assert!(lines.next().is_some(), "no sweep table (a `law  runs  converged ...` header) in the console block");
    let mut rows = Vec::new();
    for line in lines {
        let cells: Vec<&str> = line.split_whitespace().collect();
        // law, runs, 3 shares, then 5 pairs `a / b`.
        if cells.len() != 5 + 5 * 3 || !cells[2].ends_with('%') {
            break;
        }
        let mut out: Vec<String> = cells[1..5].iter().map(|c| (*c).to_owned()).collect();
        for pair in cells[5..].chunks(3) {
            assert_eq!(pair[1], "/", "{line}");
            out.push(format!("{} / {}", pair[0], pair[2]));
        }
        rows.push((cells[0].to_owned(), out));
    }
    assert!(!rows.is_empty(), "the sweep table has no rows");
    rows
}

/// The Markdown table of the sweep table in `block`.
fn laws_table(block: &str) -> String {
    let pct = |c: &str| format!("{} %", c.trim_end_matches('%'));
    let mut out =
        "| law | runs | converged | diverged | unsettled | time to 1 cm, median / worst | abs. heading error at \
                   the end, median / worst |\n|---|---|---|---|---|---|---|\n"
            .to_owned();
    for (law, c) in law_rows(block) {
        out.push_str(&format!(
            "| {law} | {} | {} | {} | {} | {} s | {} deg |\n",
            c[0],
            pct(&c[1]),
            pct(&c[2]),
            pct(&c[3]),
            c[4],
            c[5]
        ));
    }
    out
}

/// The Markdown table of a sweep over references in `block`: one row per law and
/// reference (`law  reference  runs  converged  diverged  unsettled  cannot_follow  RMS mm
/// (med/max)  max mm (med/max)  s to 10 mm`), the shares without their runs count.
fn tracking_table(block: &str) -> String {
    let mut lines = block.lines().skip_while(|l| !(l.starts_with("law ") && l.contains(" reference ")));
    assert!(lines.next().is_some(), "no sweep table over references (a `law  reference  runs ...` header)");
    let mut out = String::from(
        "| law | reference | converged | diverged | unsettled | cannot follow | RMS mm, median / worst | max mm, \
         median / worst | below 10 mm after s, median / worst |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut rows = 0;
    for line in lines {
        let c: Vec<&str> = line.split_whitespace().collect();
        // law, reference, runs, 4 shares, two pairs `a / b`, then a pair or `-`.
        if c.len() < 13 || !c[3].ends_with('%') {
            break;
        }
        let pct = |s: &str| format!("{} %", s.trim_end_matches('%'));
        let after = if c.len() == 16 { format!("{} / {}", c[13], c[15]) } else { c[13].to_owned() };
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} / {} | {} / {} | {after} |\n",
            c[0],
            c[1],
            pct(c[3]),
            pct(c[4]),
            pct(c[5]),
            pct(c[6]),
            c[7],
            c[9],
            c[10],
            c[12]
        ));
        rows += 1;
    }
    assert!(rows > 0, "the sweep table over references has no rows");
    out
}

/// The Markdown table of a sweep's docking section in `block` (issue 42: `docked within
/// X m and Y deg at the end ...`, then `law  runs  docked  final dl mm  |e_th| deg` and
/// one row per law: runs, the share docked, p50 / p95 / p99 / max of each error).
fn docking_table(block: &str) -> String {
    let mut lines = block.lines().skip_while(|l| !l.starts_with("docked within "));
    let title = lines.next().expect("no docking section (`docked within ...`) in the console block");
    let within = title.trim_start_matches("docked within ").split(" at the end").next().unwrap();
    assert!(lines.next().is_some_and(|h| h.starts_with("law ")), "the docking section's header");
    let mut out = format!(
        "| law | runs | docked within {within} | final distance mm, p50 / p95 / p99 / max | abs. final heading \
         error deg, p50 / p95 / p99 / max |\n|---|---|---|---|---|\n"
    );
    let mut rows = 0;
    for line in lines {
        let c: Vec<&str> = line.split_whitespace().filter(|c| *c != "/").collect();
        if c.len() != 11 || !c[2].ends_with('%') {
            break;
        }
        out.push_str(&format!(
            "| {} | {} | {} % | {} | {} |\n",
            c[0],
            c[1],
            c[2].trim_end_matches('%'),
            c[3..7].join(" / "),
            c[7..11].join(" / ")
        ));
        rows += 1;
    }
    assert!(rows > 0, "the docking section has no rows");
    out
}

/// The first console block of `text`.
fn console_after(text: &str) -> &str {
    let open = text.find("```console\n").expect("a console block after the table") + "```console\n".len();
    let close = text[open..].find("\n```").expect("the console block's end") + open;
    &text[open..close]
}

/// `doc` with every table between `begin` and `end` regenerated by `make` from the console
/// block after it; how many.
fn regenerate_with(doc: &str, begin: &str, end: &str, make: fn(&str) -> String) -> (String, usize) {
    let (mut out, mut rest, mut n) = (String::new(), doc, 0);
    while let Some(a) = rest.find(begin) {
        let b = a + rest[a..].find(end).unwrap_or_else(|| panic!("{begin:?} without {end:?}"));
        out.push_str(&rest[..a + begin.len()]);
        out.push_str(&make(console_after(&rest[b..])));
        rest = &rest[b..];
        n += 1;
    }
    out.push_str(rest);
    (out, n)
}

/// `doc` with every table (shares and laws) regenerated from the console block after it;
/// how many.
fn regenerate(doc: &str) -> (String, usize) {
    let (doc, n) = regenerate_with(doc, BEGIN, END, table);
    let (doc, m) = regenerate_with(&doc, LAWS_BEGIN, LAWS_END, laws_table);
    let (doc, k) = regenerate_with(&doc, TRACKING_BEGIN, TRACKING_END, tracking_table);
    let (doc, d) = regenerate_with(&doc, DOCKING_BEGIN, DOCKING_END, docking_table);
    (doc, n + m + k + d)
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
            "{doc}: a table differs from its console block; regenerate with \
             `WMR_BLESS=1 cargo test -p wmr-cli --test integration docs_console_tables::`"
        );
    }
    assert!(found >= 4, "{found} tables between {BEGIN:?} or {LAWS_BEGIN:?} and their end markers");
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

#[test]
fn a_docking_table_follows_its_block() {
    let block = "$ wmr-cli sweep s.toml\n...\n\ndocked within 0.01 m and 1 deg at the end (final errors over all runs: \
                 p50 / p95 / p99 / max)\nlaw                     runs    docked                final dl mm     \
                 |e_th| deg\ngraceful                  40    97.50%  0.68 / 0.73 / 0.74 / 0.74    0.002 / 0.035 / \
                 1.979 / 1.979\nwmr-cli: 40 runs\n";
    let doc = format!("x\n{DOCKING_BEGIN}| stale |\n{DOCKING_END}\n\n```console\n{block}```\n");
    let (fresh, n) = regenerate(&doc);
    assert_eq!(n, 1);
    assert!(fresh.contains("docked within 0.01 m and 1 deg |"), "{fresh}");
    assert!(
        fresh.contains("| graceful | 40 | 97.50 % | 0.68 / 0.73 / 0.74 / 0.74 | 0.002 / 0.035 / 1.979 / 1.979 |\n"),
        "{fresh}"
    );
    assert!(!fresh.contains("stale"));
}

/// The console block of `doc` whose command line is `$ command`.
fn block_of<'a>(doc: &'a str, command: &str) -> &'a str {
    let at = doc.find(&format!("$ {command}\n")).unwrap_or_else(|| panic!("no console block of `{command}`"));
    let end = doc[at..].find("\n```").expect("the console block's end") + at;
    &doc[at..end]
}

/// The number after `before` in `line` (`final heading error -5.047 deg`: `-5.047`).
fn number_after(line: &str, before: &str) -> f64 {
    let rest = &line[line.find(before).unwrap_or_else(|| panic!("{before:?} in {line}")) + before.len()..];
    rest.split_whitespace().next().unwrap().trim_end_matches(['%', ',']).parse().unwrap()
}

/// `text` with every run of whitespace (line breaks included) as one space.
fn flat(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The cells of `law`'s row of the sweep table in `block` (see [`law_rows`]).
fn law_row(block: &str, law: &str) -> Vec<String> {
    law_rows(block).into_iter().find(|(l, _)| l == law).unwrap_or_else(|| panic!("no row {law}")).1
}

/// The prose sentences (and a table row) that restate numbers a command prints, each
/// rebuilt from that command's console block (compared with the command's output by
/// `docs_commands`): for each, the document and the sentence as it must read.
fn prose_claims(readme: &str) -> Vec<(&'static str, String)> {
    let mut claims = Vec::new();
    // Fig. 7 (README, "What the laws do").
    let fig7 = block_of(readme, "wmr-cli run examples/paper/fig7.toml -o fig7.csv");
    let t = number_after(fig7, "time to dl < 1 cm ");
    let e = number_after(fig7, "final heading error ");
    claims.push((
        "README.md",
        format!("the paper's law is within 1 cm for good from {t:.1} s with a final heading error of {e:.2} deg"),
    ));
    // The odometry drift of the 1 % radius error (the `#2` rows), README.
    let odo = block_of(readme, "wmr-cli sweep examples/odometry.toml -o odometry.csv");
    let drift = &odo[odo.find("odometry drift at the end").expect("the drift section")..];
    let values: Vec<f64> = drift
        .lines()
        .filter(|l| l.split_whitespace().next().is_some_and(|law| law.ends_with("#2")))
        .flat_map(|l| l.split_whitespace().skip(1).map(|c| c.trim_end_matches('%').parse::<f64>().unwrap()))
        .collect();
    assert!(!values.is_empty(), "no #2 rows in the drift section");
    let (lo, hi) = values.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    claims.push(("README.md", format!("A 1 % radius error drifts {lo:.2}-{hi:.2} % of the distance")));
    // docs/model.md restates the compare sweep of README: the paper's row and the
    // repaired law's times and peak wheel speed.
    let compare = block_of(readme, "wmr-cli sweep examples/compare.toml -o compare.csv");
    let paper = law_row(compare, "paper");
    let pct = |c: &str| c.trim_end_matches('%').to_owned();
    let (e_med, e_max) = paper[5].split_once(" / ").unwrap();
    claims.push((
        "docs/model.md",
        format!(
            "| paper | {} % | {} % | {} % | {e_med} / 18.50 / {e_max} deg |",
            pct(&paper[1]),
            pct(&paper[2]),
            pct(&paper[3])
        ),
    ));
    let pb = law_row(compare, "paper_bidirectional");
    let (t_med, t_max) = pb[4].split_once(" / ").unwrap();
    let t_med: f64 = t_med.parse().unwrap();
    let t_max: f64 = t_max.parse().unwrap();
    let peak: f64 = pb[6].split_once(" / ").unwrap().0.parse().unwrap();
    claims.push((
        "docs/model.md",
        format!(
            "With its defaults the law reaches 1 cm in {t_med:.1} s (median; worst {t_max:.1} s), its wheels peak at \
             {peak:.1} rad/s (median)"
        ),
    ));
    claims
}

#[test]
fn prose_numbers_are_those_of_their_console_blocks() {
    let readme = std::fs::read_to_string(path("README.md")).unwrap();
    for (doc, sentence) in prose_claims(&readme) {
        let text = flat(&std::fs::read_to_string(path(doc)).unwrap());
        assert!(
            text.contains(&flat(&sentence)),
            "{doc} should read {sentence:?}, as the command's console block says (edit the prose)"
        );
    }
}

#[test]
fn a_laws_table_follows_its_block() {
    let block = "$ wmr-cli sweep s.toml\nlaw                   runs  converged  diverged  unsettled t_1cm s (med/max)      \
                 |e_th| deg    peak w rad/s        path m        energy J\npaper                 1000      84.0%     \
                 10.3%       5.7%    49.57 / 179.61   12.15 / 43.26    33.0 / 124.5 5.38 / 446.39  158.4 / 9137.7\n...\n";
    let doc = format!("x\n{LAWS_BEGIN}| stale |\n{LAWS_END}\n\n```console\n{block}```\n");
    let (fresh, n) = regenerate(&doc);
    assert_eq!(n, 1);
    assert!(
        fresh.contains("| paper | 1000 | 84.0 % | 10.3 % | 5.7 % | 49.57 / 179.61 s | 12.15 / 43.26 deg |\n"),
        "{fresh}"
    );
    assert!(!fresh.contains("stale"));
}

#[test]
fn a_tracking_table_follows_its_block() {
    let block = "$ wmr-cli sweep t.toml\nlaw          reference      runs  converged  diverged  unsettled  cannot_follow    \
                 RMS mm (med/max)    max mm (med/max)      s to 10 mm\nkanayama     circle          200     100.0%      \
                 0.0%       0.0%           0.0%         0.00 / 0.00         0.00 / 0.00     1.95 / 2.68\npure_pursuit \
                 figure_eight    200       0.0%      0.0%      93.0%           7.0%     103.84 / 381.34     225.92 / \
                 394.86               -\nwmr-cli: 400 runs\n";
    let doc = format!("x\n{TRACKING_BEGIN}| stale |\n{TRACKING_END}\n\n```console\n{block}```\n");
    let (fresh, n) = regenerate(&doc);
    assert_eq!(n, 1);
    assert!(
        fresh.contains(
            "| kanayama | circle | 100.0 % | 0.0 % | 0.0 % | 0.0 % | 0.00 / 0.00 | 0.00 / 0.00 | 1.95 / 2.68 |\n"
        ),
        "{fresh}"
    );
    assert!(
        fresh.contains(
            "| pure_pursuit | figure_eight | 0.0 % | 0.0 % | 93.0 % | 7.0 % | 103.84 / 381.34 | 225.92 / 394.86 | - |\n"
        ),
        "{fresh}"
    );
    assert!(!fresh.contains("stale"));
}
