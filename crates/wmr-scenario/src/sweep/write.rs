//! The `[sweep]` table written back as TOML, every key with its value (`wmr-cli check`).

use toml::Value;

use super::spec::SweepSpec;
use super::starts::StartsSource;
use crate::controller as controller_table;

impl SweepSpec {
    /// The `[sweep]` table in TOML, every key written; reads back to the same sweep.
    pub(crate) fn write_toml(&self, out: &mut String) {
        use std::fmt::Write as _;
        let f = crate::keys::toml_f64;
        let g = &self.goal;
        match &self.tracking {
            None => {
                let _ = writeln!(out, "\n[sweep]\ngoal = {{ x = {}, y = {}, theta = {} }}", f(g.x), f(g.y), f(g.theta));
            }
            Some(tr) => {
                let _ = writeln!(out, "\n[sweep]\nreferences = [");
                for (_, r) in &tr.references {
                    let keys: Vec<String> = r.table.iter().map(|(k, v)| format!("{k} = {v}")).collect();
                    let _ = writeln!(out, "  {{ {} }},", keys.join(", "));
                }
                let _ = writeln!(out, "]");
            }
        }
        let _ = writeln!(out, "controllers = [");
        for (_, setup) in &self.laws {
            // Derived wheel-stage keys left out (written commented, then dropped): each run
            // derives them again from its own drive and model, as a `vary` on them needs.
            let mut noted = String::new();
            let drive = setup.drive.params();
            controller_table::write_noted(&setup.controller, &drive, setup.model.params(), &mut noted, |_| None);
            let mut table: String = noted.lines().filter(|l| !l.starts_with('#')).map(|l| format!("{l}\n")).collect();
            if setup.model != setup.robot {
                let mut model = String::new();
                crate::keys::write_keys(&mut model, &crate::keys::to_table(setup.model.params()), &[]);
                let _ = writeln!(table, "model = {{ {} }}", model.lines().collect::<Vec<_>>().join(", "));
            }
            let _ = writeln!(out, "  {{ {} }},", table.lines().collect::<Vec<_>>().join(", "));
        }
        let _ = writeln!(out, "]");
        match &self.source {
            StartsSource::Grid(g) => {
                let thetas: Vec<String> = g.theta_deg.iter().flatten().map(|t| f(*t)).collect();
                let _ = writeln!(
                    out,
                    "grid = {{ x_min = {}, x_max = {}, nx = {}, y_min = {}, y_max = {}, ny = {}, theta_deg = [{}] }}",
                    f(g.x_min),
                    f(g.x_max),
                    g.nx,
                    f(g.y_min),
                    f(g.y_max),
                    g.ny,
                    thetas.join(", ")
                );
            }
            StartsSource::Random(r) => {
                let heading = r.max_heading_deg.map(|h| format!(", max_heading_deg = {}", f(h))).unwrap_or_default();
                let _ = writeln!(
                    out,
                    "random = {{ n = {}, seed = {}, radius = {}, min_radius = {}{heading} }}",
                    r.n,
                    r.seed,
                    f(r.radius),
                    f(r.min_radius)
                );
            }
        }
        let v = &self.variation;
        let _ = writeln!(out, "trials = {}\nseed = {}", v.trials, v.seed);
        if !v.keys.is_empty() {
            let _ = writeln!(out, "vary = [");
            for k in &v.keys {
                let spread = match &k.spread {
                    crate::vary::Spread::Values(x) => {
                        format!("values = [{}]", x.iter().map(|x| f(*x)).collect::<Vec<_>>().join(", "))
                    }
                    crate::vary::Spread::Uniform(lo, hi) => format!("uniform = [{}, {}]", f(*lo), f(*hi)),
                    crate::vary::Spread::Normal(m, sd) => format!("normal = [{}, {}]", f(*m), f(*sd)),
                };
                let with = if k.with.is_empty() {
                    String::new()
                } else {
                    let pairs: Vec<String> =
                        k.with.iter().map(|(key, v)| format!("{} = {v}", Value::String(key.clone()))).collect();
                    format!(", with = {{ {} }}", pairs.join(", "))
                };
                let _ = writeln!(out, "  {{ key = {}, {spread}{with} }},", Value::String(k.key.clone()));
            }
            let _ = writeln!(out, "]");
        }
        let refs =
            if self.tracking.is_some() { format!(" x {} references", self.n_references()) } else { String::new() };
        let _ = writeln!(
            out,
            "# {} laws{refs} x {} variants x {} trials x {} starts = {} runs",
            self.laws.len(),
            self.variants.len(),
            v.trials,
            self.starts.len(),
            self.len()
        );
    }
}
