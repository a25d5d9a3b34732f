//! `crates/wmr-ffi/src/laws.rs`: each law's C declarations (its parameter struct, its
//! storage words and opaque storage per precision) and the line that gives its
//! parameter struct its C reading (`imp::c_params!`). cbindgen reads the file as
//! written: it does not see through macros, so the declarations are spelled out here.

use crate::registry::{LawRow, laws, screaming};
use crate::{Generated, header};
use core::fmt::Write as _;

/// Words (8 bytes) of a storage slot of `bytes`, rounded up to a multiple of 8 words (64
/// bytes): a law that grows by less than the rounding keeps its C ABI. (The rule gives
/// every law the words it had when they were written by hand, except pure pursuit, whose
/// storage shrank from 40 and 72 words to 32 and 64: `WMR_ABI_VERSION` 4.)
pub fn storage_words(bytes: usize) -> usize {
    bytes.div_ceil(8).div_ceil(8) * 8
}

fn c_params_line(law: &LawRow) -> String {
    let mirrored = law.fields.iter().any(|f| f.ty == "bool");
    if mirrored {
        let floats: Vec<&str> = law.fields.iter().filter(|f| f.ty == "T").map(|f| f.name).collect();
        let flags: Vec<&str> = law.fields.iter().filter(|f| f.ty == "bool").map(|f| f.name).collect();
        assert!(
            law.fields.iter().all(|f| f.ty == "T" || f.ty == "bool"),
            "{}: a law's keys in C are floats, flags or #[repr(u32)] enums, not a mix of flags and enums",
            law.kind
        );
        format!(
            "    mirror wmr_{}_params = {} {{ {}; flags {} }};\n",
            law.kind,
            law.params,
            floats.join(", "),
            flags.join(", ")
        )
    } else {
        let enums: Vec<String> =
            // A `u32` key (a count, a seed) is a plain number, valid for any bits: no check.
            law.fields.iter().filter(|f| f.ty != "T" && f.ty != "u32").map(|f| format!("{}: wmr_core::{}", f.name, f.ty)).collect();
        format!("    alias {} {{ {} }};\n", law.params, enums.join(", "))
    }
}

/// The file's text.
pub fn generate() -> Generated {
    let laws = laws();
    let mut s = header("each law's C declarations.");
    s.push_str(
        "//! Each law's C declarations, from the registry: its parameter struct, its storage\n\
         //! words and its opaque storage (f32 and f64).\n\n",
    );
    for law in &laws {
        let k = law.kind;
        let big = screaming(k);
        let mirrored = law.fields.iter().any(|f| f.ty == "bool");
        let _ = writeln!(s, "/// {} (`kind = \"{k}\"`): `wmr_core::{}`.", law.about, law.params);
        if mirrored {
            let _ = writeln!(s, "/// The core's keys with each flag as a 0/1 `uint32_t`.");
            let _ = writeln!(s, "#[repr(C)]\n#[derive(Clone, Copy, Debug, Default, PartialEq)]");
            let _ = writeln!(s, "pub struct wmr_{k}_params<T> {{");
            for f in law.fields {
                let unit = if f.unit.is_empty() { String::new() } else { format!("Unit: {}; ", f.unit) };
                let rule = if f.ty == "bool" { "1 or 0".to_owned() } else { f.rule.to_owned() };
                let _ = writeln!(s, "    /// {} {unit}valid: {rule}.", f.doc);
                let ty = if f.ty == "bool" { "u32" } else { "T" };
                let _ = writeln!(s, "    pub {}: {ty},", f.name);
            }
            let _ = writeln!(s, "}}");
        } else {
            for f in law.fields.iter().filter(|f| f.ty != "T" && f.ty != "u32") {
                let _ = writeln!(
                    s,
                    "/// `{}` is a `uint32_t` in C (a `WMR_*` constant of `{}`): a value that is not one is refused by `*_init`.",
                    f.name, f.ty
                );
            }
            let _ = writeln!(s, "/// cbindgen:ignore");
            let _ = writeln!(s, "pub type wmr_{k}_params<T> = wmr_core::{}<T>;", law.params);
        }
        for (i, (p, prec)) in [("f32", "F32"), ("f64", "F64")].into_iter().enumerate() {
            let words = storage_words(law.slot_bytes[i]);
            let _ = writeln!(
                s,
                "/// Words (8 bytes each) of `wmr_{k}_controller_{p}`: the law `{k}` with its wheel stage."
            );
            let _ = writeln!(s, "pub const WMR_{big}_CONTROLLER_{prec}_WORDS: usize = {words};");
        }
        for (p, prec) in [("f32", "F32"), ("f64", "F64")] {
            let _ = writeln!(s, "/// The law `{k}` with its wheel stage ({p}): {}", law.about);
            let _ = writeln!(
                s,
                "#[repr(C)]\npub struct wmr_{k}_controller_{p} {{\n    /// Opaque: only the library reads or writes it.\n    pub opaque: [u64; WMR_{big}_CONTROLLER_{prec}_WORDS],\n}}"
            );
        }
        s.push('\n');
    }
    s.push_str("/// How each law's C parameter struct becomes the core's: `imp` expands this list with\n");
    s.push_str("/// its `c_params!` (an alias of the core's `#[repr(C)]` struct, its enums checked as\n");
    s.push_str("/// `uint32_t`, or a mirror whose flags are 0/1 `uint32_t`).\n");
    s.push_str("macro_rules! for_each_c_params {\n    ($callback:ident) => {\n        $callback! {\n");
    // c_params! takes the aliases first, then the mirrors.
    let (mirrors, aliases): (Vec<&LawRow>, Vec<&LawRow>) =
        laws.iter().partition(|l| l.fields.iter().any(|f| f.ty == "bool"));
    for law in aliases.into_iter().chain(mirrors) {
        s.push_str(&format!("        {}", c_params_line(law).trim_start()));
    }
    s.push_str("        }\n    };\n}\npub(crate) use for_each_c_params;\n");
    Generated { path: "crates/wmr-ffi/src/laws.rs".into(), text: s }
}
