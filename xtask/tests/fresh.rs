//! Every file made by a generator of this crate is as the generator writes it: a file
//! edited by hand, or a registry changed without `cargo xtask gen`, fails here.

#[test]
fn generated_files_are_up_to_date() {
    let bad = xtask::out_of_date();
    assert!(bad.is_empty(), "out of date: {bad:?}; run `cargo xtask gen`");
}

/// The C storage of a law is never too small for it, whatever the registry holds (the
/// C API also checks this at compile time).
#[test]
fn storage_words_hold_every_law() {
    for law in xtask::registry::laws() {
        for (i, bytes) in law.slot_bytes.into_iter().enumerate() {
            let words = xtask::ffi_laws::storage_words(bytes);
            assert!(
                words * 8 >= bytes && words.is_multiple_of(8),
                "{} precision {i}: {words} words for {bytes} bytes",
                law.kind
            );
            assert!(law.slot_align[i] <= 8, "{}: alignment {}", law.kind, law.slot_align[i]);
        }
    }
}

/// Every law of the registry gets its entry points in C, in both precisions.
#[test]
fn every_law_has_its_c_entry_points() {
    let (f32_src, f64_src) = (xtask::ffi_api::api_f32(), xtask::ffi_api::api_f64());
    for law in xtask::registry::laws() {
        for f in ["init", "update", "update_reference", "update_on", "reset", "for_plant"] {
            for (p, src) in [("f32", &f32_src), ("f64", &f64_src)] {
                assert!(src.contains(&format!("fn wmr_{}_controller_{p}_{f}(", law.kind)), "{} {p} {f}", law.kind);
            }
        }
        assert!(f32_src.contains(&format!("fn wmr_{}_params_f32_default(", law.kind)), "{}", law.kind);
    }
}

/// Every field type of a struct C shares with the core has a C type: a float, or a
/// `uint32_t`/`uint64_t` code.
#[test]
fn shared_struct_fields_have_c_types() {
    for (name, _, fields) in xtask::ffi_header::shared_structs() {
        for f in fields {
            assert!(matches!(xtask::ffi_header::c_type(f.ty).0, "T" | "u32" | "u64"), "{name}.{}: {}", f.name, f.ty);
        }
    }
}

/// Every key the schema describes has its table in docs/scenario.md (a new law or key
/// without its docs section fails here, naming the block to add).
#[test]
fn every_described_key_has_a_docs_block() {
    let doc = std::fs::read_to_string(xtask::repo_root().join("docs/scenario.md")).expect("docs/scenario.md");
    let keys = wmr_scenario::schema();
    let (_, ids) = xtask::docs_keys::regenerate(&doc, &keys);
    for k in keys.iter().filter(|k| k.is_described() && k.key != "model") {
        let id = xtask::docs_keys::block_of(k);
        assert!(ids.contains(&id), "docs/scenario.md has no block keys:{id} for {}", k.key);
    }
}
