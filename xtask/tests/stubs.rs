//! The Python stubs as a reader sees them: every `[robot]` key and every key of each
//! law's `[controller]` kind is a keyword of its class's `__new__` (parsed back from the
//! text `cargo xtask gen` wrote), with the schema's default.

use wmr_scenario::schema;
use xtask::python_stubs::{PATH, PYTHON_KEYWORDS, class_keys};

/// `(name, default)` of the keyword-only arguments of `class NAME`'s `__new__`.
fn init_kwargs<'a>(stub: &'a str, class: &str) -> Vec<(&'a str, &'a str)> {
    let start = stub.find(&format!("class {class}:")).unwrap_or_else(|| panic!("no class {class}"));
    let body = &stub[start..];
    let new = &body[body.find("def __new__(").expect("__new__")..];
    let new = &new[..new.find(") -> Self").expect("the end of __new__")];
    let star = new.find('*').expect("keyword-only arguments");
    new[star..]
        .lines()
        .filter(|l| !l.trim().starts_with('#'))
        .filter_map(|l| {
            // `name: type = default,  # [unit] doc`: the default ends at the comma.
            let (name, rest) = l.trim().split_once(':')?;
            Some((name.trim(), rest.split_once('=')?.1.split(',').next()?.trim()))
        })
        .collect()
}

/// The value a Python default spells, as TOML would hold it.
fn as_toml(shown: &str) -> toml::Value {
    match shown {
        "math.inf" => toml::Value::Float(f64::INFINITY),
        "True" | "False" => toml::Value::Boolean(shown == "True"),
        s if s.starts_with('"') => toml::Value::String(s.trim_matches('"').to_owned()),
        s => s
            .parse::<i64>()
            .map(toml::Value::Integer)
            .unwrap_or_else(|_| toml::Value::Float(s.parse().unwrap_or_else(|_| panic!("not a number: {s}")))),
    }
}

#[test]
fn stubs_list_every_robot_and_controller_key_with_its_default() {
    let stub = std::fs::read_to_string(xtask::repo_root().join(PATH)).expect("the stubs");
    let keys = schema();
    let mut classes = vec![("Robot".to_owned(), "robot", None)];
    classes.extend(
        wmr_core::LawParams::<f64>::defaults()
            .iter()
            .map(|l| (format!("{}Controller", l.name()), "controller", Some(l.kind()))),
    );
    for (class, table, kind) in classes {
        let got = init_kwargs(&stub, &class);
        // A key spelled as a Python keyword is a comment line (passed through **kwargs).
        let want: Vec<_> =
            class_keys(&keys, table, kind).into_iter().filter(|k| !PYTHON_KEYWORDS.contains(&k.key)).collect();
        // MPPI's class also takes the world it plans around and the run whose noise it
        // draws: arguments of the class, not keys of the law.
        let mut got_names: Vec<&str> =
            got.iter().map(|(n, _)| *n).filter(|n| !["obstacles", "footprint_radius", "run"].contains(n)).collect();
        let mut want_names: Vec<&str> = want.iter().map(|k| k.key).collect();
        got_names.sort_unstable();
        want_names.sort_unstable();
        assert_eq!(got_names, want_names, "{class}.__new__ keywords");
        for k in want {
            let shown = got.iter().find(|(n, _)| *n == k.key).map(|(_, d)| as_toml(d)).expect("shown");
            let real = k.default.clone().or(k.default_by_drive.first().map(|(_, v)| v.clone())).expect("a default");
            assert_eq!(shown, real, "{class}: {}", k.key);
        }
    }
}
